"""Open Image Denoise inside Blender's own process (Blender 3.4 links jemalloc and its
TBB is in global scope: without RTLD_DEEPBIND and the preloaded CPU device, OIDN's first
device commit aborts the process there; native/src/denoise/oidn.cpp)."""

import numpy as np
import pytest
from whitted import whitted_native as wn


def test_denoising_in_blenders_process_works_or_reports_why_not():
    status = wn.oidn_status()
    if not status["ok"]:
        pytest.skip(status["report"])
    rng = np.random.default_rng(5)
    color = (0.5 * rng.uniform(0.0, 2.0, (40, 40, 3))).astype(np.float32)
    normal = np.zeros_like(color)
    normal[..., 2] = 1.0
    out = wn.oidn_denoise(color, np.full_like(color, 0.8), normal, threads=2)
    assert np.mean(np.abs(out - 0.5)) * 5 < np.mean(np.abs(color - 0.5))
