"""bench-noise: Whitted's noise targets against Cycles, end to end on one tiny scene in
the bpy module (Cycles with its own Open Image Denoise, Whitted with the build's)."""

import json
import math
import subprocess
import sys


def test_one_scene_gives_every_render_a_time_an_error_and_a_noise(tmp_path):
    subprocess.run(
        [
            *(sys.executable, "-m", "whitted_tools", "bench-noise", "--out", str(tmp_path)),
            *("--resolution", "32", "24", "--repeats", "1", "--scenes", "depth_of_field"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        check=True,
    )
    page = (tmp_path / "NOISE.md").read_text()
    assert "| depth_of_field |" in page and "## depth_of_field" in page
    (results,) = json.loads(next((tmp_path / "data").glob("noise-blender-*.json")).read_text())
    labels = [row["label"] for row in results["rows"]]
    assert labels[0] == "Cycles default (0.01, denoised)"
    assert "Whitted Final denoised" in labels and "Whitted Draft" in labels
    for row in results["rows"]:
        assert row["seconds"] > 0.0, row
        for key in ("rmse", "linear_rmse", "noise"):
            assert math.isfinite(row[key]) and row[key] >= 0.0, row
    assert math.isfinite(results["bias"])
