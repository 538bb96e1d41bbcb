"""Hair, curves and point clouds (issue 31): particle hair with children, a Curves object
whose curves geometry nodes make, and a point cloud from Distribute Points on Faces,
each traced as round tubes or spheres (export/curves.py, native Mesh curves and points)
against Cycles' Thick curves; the report names none of them as not rendered. Particle
hair with Cycles' default shape, Ribbons, traced as flat curves against Cycles' Ribbons,
closer to them than the same strands traced round."""

import json

import numpy as np
import pytest
from whitted_tools.cycles_scenes import box_filtered, render_rgba
from whitted_tools.hair_scenes import SCENES, ribbon_hair
from whitted_tools.metrics import subject_figures


@pytest.mark.parametrize("name", SCENES)
def test_strands_and_points_as_cycles(empty_scene, tmp_path, monkeypatch, name):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    SCENES[name](scene)
    box_filtered(scene, cycles_samples=128, whitted_samples=6)
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    image = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    stats = json.loads(stats_path.read_text())
    assert np.isfinite(image).all() and stats["nonfinite_samples"] == 0
    # Counted as traced, per instance (an instanced mesh's each time): the render's
    # 2,000 children (not their 200 parents) of 9 keys, 49 curves of 6 keys, the points.
    expected = {"particle hair": ("curve_segments", 2000 * 8), "curves": ("curve_segments", 49 * 5)}
    if name in expected:
        what, count = expected[name]
        assert stats[what] == count
    else:
        assert stats["points"] > 100
    # Alone (the floor hidden), their coverage of the image: how thick and where.
    floor = scene.objects["Floor"]
    floor.hide_render = True
    alone = render_rgba(scene, "WHITTED", str(tmp_path / "alone.exr"))
    alone_cycles = render_rgba(scene, "CYCLES", str(tmp_path / "alone_cycles.exr"))
    floor.hide_render = False
    covered = alone[..., 3] > 0.5
    coverage = alone[..., 3].mean() / alone_cycles[..., 3].mean()
    value, ratio = subject_figures(image, cycles, covered)
    print(
        f"\n{name}: SSIM {value:.4f}, ratio {ratio:.4f}, coverage {alone[..., 3].mean():.4f} "
        f"(Cycles {alone_cycles[..., 3].mean():.4f})"
    )
    assert covered.mean() > 0.02  # they are in the picture
    assert coverage == pytest.approx(1.0, abs=0.05)
    assert value > 0.95
    assert abs(ratio - 1.0) < 0.05


def test_ribbons_as_cycles(empty_scene, tmp_path):
    scene = empty_scene
    ribbon_hair(scene)
    box_filtered(scene, cycles_samples=128, whitted_samples=6)
    floor = scene.objects["Floor"]

    def render(engine, shape):
        scene.cycles_curves.shape = shape
        image = render_rgba(scene, engine, str(tmp_path / f"{engine}_{shape}.exr"))
        floor.hide_render = True
        alone = render_rgba(scene, engine, str(tmp_path / f"{engine}_{shape}_alone.exr"))
        floor.hide_render = False
        return image, alone

    cycles, cycles_alone = render("CYCLES", "RIBBONS")
    figures = {}
    for shape in ("RIBBONS", "THICK"):  # Whitted's ribbons, and the same strands round
        image, alone = render("WHITTED", shape)
        assert np.isfinite(image).all()
        value, ratio = subject_figures(image, cycles, alone[..., 3] > 0.5)
        figures[shape] = value, ratio, alone[..., 3].mean()
        print(
            f"\nWhitted {shape} against Cycles' Ribbons: SSIM {value:.4f}, ratio {ratio:.4f}, "
            f"coverage {alone[..., 3].mean():.4f} (Cycles {cycles_alone[..., 3].mean():.4f})"
        )
    value, ratio, coverage = figures["RIBBONS"]
    assert coverage / cycles_alone[..., 3].mean() == pytest.approx(1.0, abs=0.01)
    assert value > 0.985
    assert abs(ratio - 1.0) < 0.025
    # Traced round, the same strands are further from Cycles' ribbons.
    assert figures["THICK"][0] < value - 0.01
