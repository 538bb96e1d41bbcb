"""The galleries' pages (whitted_tools.gallery.effects' harness) from results a run kept,
without rendering: the .venv's bpy 5.0 module is imported, no scene is rendered."""

import json

from whitted_tools.gallery.effects import EFFECTS_PAGE, write_markdown
from whitted_tools.gallery.features import FEATURES_PAGE


def _result(scene, effect, why):
    return {
        "scene": scene,
        "effect": effect,
        "decision": None if effect is None else {"name": effect, "on": True, "why": why},
        "turned_off_by": "off",
        "ssim": 0.98,
        "ratio": 1.01,
        "seconds_on": 0.5,
        "seconds_off": 0.25,
        "rays_on": 2e6,
        "rays_off": 1e6,
    }


def test_a_features_page_has_a_row_per_scene_and_says_what_the_report_does_not_name(tmp_path):
    folder = tmp_path / "images" / FEATURES_PAGE.images / "blender-9.9"
    folder.mkdir(parents=True)
    results = [
        _result("shadow_catcher", "shadow catcher", "1 object"),
        _result("bump_displacement", None, ""),
    ]
    (folder / "results.json").write_text(json.dumps(results))
    write_markdown(tmp_path, "the command", FEATURES_PAGE)
    page = (tmp_path / FEATURES_PAGE.file).read_text()
    assert page.startswith(f"# {FEATURES_PAGE.title}\n")
    assert "gallery-features --out docs" in page and "    the command" in page
    assert "## Blender 9.9" in page
    assert "| shadow_catcher | 0.980 | 1.010 | 0.500 | 0.250 | 2.00 | 2.00 / 1.00 |" in page
    assert "| shadow catcher (1 object) |" in page
    assert "(not named in the report: a material's shading)" in page
    assert "![bump_displacement](images/features/blender-9.9/bump_displacement.png)" in page


def test_every_scene_of_both_galleries_has_a_name_a_build_and_a_switch():
    for page in (EFFECTS_PAGE, FEATURES_PAGE):
        names = [entry[0] for entry in page.scenes]
        assert len(names) == len(set(names))
        for _name, build, effect, toggle, how in page.scenes:
            assert callable(build) and callable(toggle) and how
            assert effect is None or isinstance(effect, str)
