"""bench-rounds: noise-driven sampling's rounds against whole pixels, through the bindings
of this checkout's build (no Blender)."""

import subprocess
import sys

from whitted_tools import REPO


def test_every_kernel_and_way_reports_its_samples_and_rays():
    result = subprocess.run(
        [
            *(sys.executable, "-m", "whitted_tools", "bench-rounds"),
            *("--native", str(REPO / "build"), "--size", "24", "16", "--repeats", "1"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    rows = {}
    for line in result.stdout.splitlines():
        kernel, way, *rest = line.split()
        rows[kernel, way] = line
        assert rest[0] == "best" and float(rest[1]) > 0, line
    assert sorted(rows) == sorted(
        (k, w) for k in ("waves", "recursion") for w in ("fixed", "t0", "t01")
    )

    def rays(kernel, way):
        return int(rows[kernel, way].split("rays ")[1].split()[0])

    for kernel in ("waves", "recursion"):
        assert "spp (64, 64.00, 64)" in rows[kernel, "t0"]  # threshold 0: the whole grid
        assert rays(kernel, "t0") == rays(kernel, "fixed")
        assert rays(kernel, "t01") < rays(kernel, "fixed")  # flat pixels stopped
