"""Render statistics: the WHITTED_STATS JSON a headless or farm render writes."""

import json

import pytest

WIDTH, HEIGHT = 64, 48


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene


def test_stats_json_counts_every_ray_and_times_every_phase(
    demo, render_pixels, tmp_path, monkeypatch
):
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    demo.whitted.aa_samples = 2
    demo.whitted.max_depth = 4
    render_pixels(demo)
    stats = json.loads(path.read_text())
    assert stats["settings"] == {
        "width": WIDTH,
        "height": HEIGHT,
        "max_depth": 4,
        "aa_samples": 2,
        "fresnel": "EXACT",
    }
    rays = stats["rays"]
    assert rays["camera"] == WIDTH * HEIGHT * 4
    # The demo has a mirror, glass and two shadow-casting lights: every kind is traced.
    assert rays["reflection"] > 0
    assert rays["refraction"] > 0
    assert rays["shadow"] > rays["camera"]
    assert rays["total"] == sum(rays[k] for k in ("camera", "shadow", "reflection", "refraction"))
    phases = stats["phases"]
    assert all(phases[k] >= 0.0 for k in phases)
    assert phases["trace"] > 0.0
    assert phases["total"] >= phases["trace"] + phases["export"]
    assert stats["rays_per_second"] == pytest.approx(rays["total"] / phases["trace"])
    assert stats["nonfinite_samples"] == 0
    assert stats["cancelled"] is False
    assert stats["lights"] == 2
