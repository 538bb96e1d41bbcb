"""bench-volumes: what media cost, end to end on two scenes at a tiny resolution in the bpy
module."""

import json
import math
import subprocess
import sys


def test_each_scene_gives_both_engines_times_with_and_without_the_medium(tmp_path):
    subprocess.run(
        [
            *(sys.executable, "-m", "whitted_tools", "bench-volumes", "--out", str(tmp_path)),
            *("--resolution", "24", "18", "--repeats", "1", "--reference-samples", "64"),
            *("--scenes", "fog", "grid"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        check=True,
    )
    page = (tmp_path / "VOLUMES.md").read_text()
    scenes = ["fog box (homogeneous), spot", "Volume object's grid, spot"]
    assert all(scene in page for scene in scenes), page
    data = json.loads(next((tmp_path / "data").glob("volumes-blender-*.json")).read_text())
    assert [r["scene"] for r in data] == scenes
    for result in data:
        assert [r["label"] for r in result["rows"]] == ["Cycles default", "Whitted Final"]
        for row in result["rows"]:
            assert row["with"] > 0.0 and row["without"] > 0.0, row
            assert math.isfinite(row["error"]) and math.isfinite(row["error_without"]), row
