"""Hair, curves and point clouds (issue 31): particle hair with children, a Curves object
whose curves geometry nodes make, and a point cloud from Distribute Points on Faces,
each traced as round tubes or spheres (export/curves.py, native Mesh curves and points)
against Cycles' Thick curves; the report names none of them as not rendered."""

import json

import numpy as np
import pytest
from cycles_scenes import box_filtered, render_rgba
from whitted_tools.hair_scenes import SCENES
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
