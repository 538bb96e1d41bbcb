"""Open Image Denoise through the binding: the status's shape, denoising a noisy image
when the library is staged (scripts/stage_oidn.sh), and argument checks."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import whitted_native as wn
from conftest import BUILD_DIR


def noisy_constant(height=48, width=64, seed=3):
    """A 0.5 grey image as one Monte Carlo sample per pixel sees it: times U[0, 2)."""
    rng = np.random.default_rng(seed)
    return (0.5 * rng.uniform(0.0, 2.0, (height, width, 3))).astype(np.float32)


def mean_error(image):
    return float(np.mean(np.abs(image - 0.5)))


@pytest.fixture
def oidn():
    status = wn.oidn_status()
    if not status["ok"]:
        pytest.skip(status["report"])
    return status


def test_the_status_is_a_dict_with_a_report_either_way():
    status = wn.oidn_status()
    assert set(status) == {"ok", "version", "path", "report"}
    assert status["report"]
    if status["ok"]:
        assert status["version"] >= 20000 and status["path"] in status["report"]
    else:
        assert status["version"] == 0 and "OpenImageDenoise" in status["report"]


def test_without_the_library_denoise_raises_the_report():
    status = wn.oidn_status()
    if status["ok"]:
        pytest.skip("OpenImageDenoise is available here")
    with pytest.raises(RuntimeError, match="OpenImageDenoise"):
        wn.oidn_denoise(noisy_constant())


def test_a_noisy_grey_images_error_drops_more_than_five_times(oidn):
    color = noisy_constant()
    albedo = np.full_like(color, 0.8)
    normal = np.zeros_like(color)
    normal[..., 2] = 1.0
    for prefilter in ("none", "fast", "accurate"):
        out = wn.oidn_denoise(color, albedo, normal, threads=2, prefilter=prefilter)
        assert out.shape == color.shape and out.dtype == np.float32
        assert mean_error(out) * 5 < mean_error(color), prefilter
    alone = wn.oidn_denoise(color, threads=2, quality="fast")
    assert mean_error(alone) * 3 < mean_error(color)


def test_float64_input_is_converted_and_the_input_is_left_alone(oidn):
    color = noisy_constant().astype(np.float64)
    before = color.copy()
    out = wn.oidn_denoise(color, threads=2, quality="balanced")
    assert np.array_equal(color, before)
    assert mean_error(out) * 3 < mean_error(color)


def test_bad_shapes_and_names_are_value_errors():
    color = noisy_constant(8, 8)
    with pytest.raises(ValueError, match="color"):
        wn.oidn_denoise(color[..., :2])
    with pytest.raises(ValueError, match="albedo"):
        wn.oidn_denoise(color, albedo=np.zeros((8, 9, 3), np.float32))
    with pytest.raises(ValueError, match="prefilter"):
        wn.oidn_denoise(color, prefilter="best")
    with pytest.raises(ValueError, match="quality"):
        wn.oidn_denoise(color, quality="best")


def test_the_environment_variable_is_the_first_place_looked_at(tmp_path):
    # A file that exists but is no library: it is taken (and fails) before any other place.
    impostor = tmp_path / "libOpenImageDenoise.so.2"
    impostor.write_text("not a library")
    probe = "import json, whitted_native as wn; print(json.dumps(wn.oidn_status()))"
    env = {**os.environ, "WHITTED_OIDN_LIBRARY": str(impostor)}
    answer = subprocess.run(
        [sys.executable, "-c", probe],
        env=env,
        cwd=BUILD_DIR,
        capture_output=True,
        text=True,
        check=True,
    )
    status = json.loads(answer.stdout)
    assert not status["ok"] and status["path"] == str(impostor)
    assert status["report"].startswith(f"OpenImageDenoise could not be loaded from {impostor}: ")


def test_a_cancelled_denoise_raises_and_an_uncancelled_one_runs(oidn):
    color = noisy_constant(64, 64)
    cancel = wn.DenoiseCancel()
    assert not cancel.cancelled
    wn.oidn_denoise(color, cancel=cancel)  # not cancelled: it runs to the end
    cancel.cancel()
    assert cancel.cancelled
    with pytest.raises(RuntimeError, match="cancel"):
        wn.oidn_denoise(color, cancel=cancel)
