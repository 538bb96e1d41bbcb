"""bench-viewport-clean --quick: Whitted and Cycles edited in turn in one real Blender 3.4
window (160x120, one repeat, rough_gold), each capture's error against its engine's
converged capture, and the page."""

import re
import subprocess
import sys

from windowrun import require


def test_quick_run_times_every_row_and_compares_the_references(tmp_path):
    require("xvfb-run")
    require("blender")
    page_path = tmp_path / "VIEWPORT_CLEAN.md"
    done = subprocess.run(
        [
            *(sys.executable, "-m", "whitted_tools", "bench-viewport-clean"),
            *("--quick", "--out", str(page_path)),
        ],
        capture_output=True,
        text=True,
        timeout=240,
        check=False,
    )
    assert done.returncode == 0, f"{done.stdout[-4000:]}\n{done.stderr[-4000:]}"
    page = page_path.read_text()
    assert "## rough_gold" in page
    for label in ("Cycles, no denoising", "Whitted, no denoising", "Whitted, viewport Denoise"):
        (row,) = [line for line in page.splitlines() if line.startswith(f"| {label} |")]
        cells = [cell.strip() for cell in row.strip("|").split("|")]
        # Every engine gets below 4 levels of 255 within the quick run's 3 s.
        assert re.fullmatch(r"\d+\.\d\d", cells[1]), row
        assert float(cells[4]) < 4.0, row  # the last capture's RMSE
        if label.startswith("Whitted"):
            # It reached its Preview preset's last pass (and, with Denoise, denoised it).
            assert cells[5].endswith("(done 1/1)"), row
    cross = re.search(r"Cycles' reference against Whitted's: RMSE (\d+\.\d+) levels", page)
    assert cross and 0.0 < float(cross.group(1)) < 10.0, page
