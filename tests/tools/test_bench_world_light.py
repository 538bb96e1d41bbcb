"""bench-world-light: the world light's cost and error, end to end on one HDRI scene and
one third-party file at a tiny resolution in the bpy module."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

FILE = "4Cubes4Mats_248.blend"


def test_one_scene_and_one_file_give_each_preset_its_times_map_and_errors(tmp_path):
    if not (Path("/usr/share/assimp/models/BLEND") / FILE).exists():
        pytest.skip(f"{FILE} is not installed (Debian's assimp-testmodels)")
    subprocess.run(
        [
            *(sys.executable, "-m", "whitted_tools", "bench-world-light", "--out", str(tmp_path)),
            *("--resolution", "24", "18", "--file-resolution", "24", "18"),
            *("--converged-grid", "4", "--scenes", "forest", "--files", FILE),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        check=True,
    )
    page = (tmp_path / "WORLD_LIGHT.md").read_text()
    assert "### forest" in page and f"### {FILE}" in page
    assert (tmp_path / "images" / "world_light" / "forest.png").exists()
    data = json.loads(next((tmp_path / "data").glob("world-light-blender-*.json")).read_text())
    (forest,) = data["scenes"]
    (survey,) = data["survey"]
    (authored,) = data["files"]
    assert survey["lit"] and survey["world"] is not None
    assert forest["world_light"].startswith("map ")
    assert authored["world_light"].startswith("a world of one colour")
    for result in (forest, authored):
        assert [r["preset"] for r in result["rows"]] == ["DRAFT", "PREVIEW", "FINAL"]
        for row in result["rows"]:
            assert row["seconds_on"] > 0.0 and row["seconds_off"] > 0.0, row
            assert row["world_feelers"] > 0 and row["effect"]["on"], row
            assert row["samples_on"] > 0.0 and row["samples_off"] > 0.0, row
            for key in ("error_converged", "error_cycles", "luminance_ratio", "ssim"):
                assert math.isfinite(row[key]), row
    # The HDRI's map is built in every render (a new scene each time); one colour needs
    # none (its light is built in microseconds).
    assert all(r["map_seconds"] > 0.0 for r in forest["rows"])
    assert all(r["map_seconds"] < 1e-3 for r in authored["rows"])
    # Under the HDRI alone its feelers are the only shadow rays: more rays with it.
    assert all(r["rays_on"] > r["rays_off"] for r in forest["rows"])
