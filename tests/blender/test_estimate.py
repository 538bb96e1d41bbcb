"""The Estimate button (issue 13): each preset's predicted time and error against
Reference, from a probe that traces a sample of the frame's tiles at full resolution."""

import math
import re
from dataclasses import replace

import bpy
import numpy as np
import pytest
from whitted.estimate import REFERENCE, _render, copy_seconds
from whitted.properties.presets import PRESETS, preset
from whitted.sync.frame import sync_frame

WIDTH, HEIGHT = 160, 120


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene


def test_estimate_fills_time_and_error_of_every_preset(demo):
    assert bpy.ops.whitted.estimate() == {"FINISHED"}
    estimates = list(demo.whitted.estimates)
    assert [e.preset for e in estimates] == [key for key, _, _, _ in PRESETS]
    for estimate in estimates:
        assert math.isfinite(estimate.seconds) and estimate.seconds > 0.0
        assert math.isfinite(estimate.rays_per_pixel) and estimate.rays_per_pixel >= 1.0
        if estimate.preset == REFERENCE:
            assert estimate.error == 0.0
        else:
            assert math.isfinite(estimate.error) and estimate.error > 0.0
    rays = [e.rays_per_pixel for e in estimates]
    assert rays == sorted(rays)  # each preset traces more than the one before
    # On the demo each preset is closer to Reference than the one before.
    errors = [e.error for e in estimates]
    assert errors == sorted(errors, reverse=True)
    # 160 x 120 is 19,200 pixels: one tile in 4 gives about 4,800.
    probe = re.fullmatch(
        r"([\d,]+)-pixel probe \(1 tile in 4\) of 160x120", demo.whitted.estimate_probe
    )
    assert probe, demo.whitted.estimate_probe
    assert 4000 <= int(probe[1].replace(",", "")) <= 5600
    # Memory beside time: the guard's estimate of the full render.
    assert 0.0 < demo.whitted.estimate_memory_mib < 100.0
    # The demo's modifiers render as the viewport shows them.
    assert demo.whitted.estimate_caveat == ""


def test_estimate_says_how_a_renders_geometry_differs_from_the_viewports(demo):
    # The Estimate can only measure the viewport's depsgraph; F12 evaluates modifiers
    # with their render settings. It must say so rather than predict another scene.
    mesh = next(o for o in demo.objects if o.type == "MESH")
    subdivision = mesh.modifiers.new("Smooth", "SUBSURF")
    subdivision.levels, subdivision.render_levels = 0, 2
    bevel = mesh.modifiers.new("Edges", "BEVEL")
    bevel.show_viewport = False
    assert bpy.ops.whitted.estimate() == {"FINISHED"}
    caveat = demo.whitted.estimate_caveat
    assert f"'{mesh.name}': 'Smooth' subdivides 0 times in the viewport, 2 in renders" in caveat
    assert f"'{mesh.name}': modifier 'Edges' is on in renders only" in caveat
    subdivision.render_levels = 0
    bevel.show_viewport = True
    assert bpy.ops.whitted.estimate() == {"FINISHED"}
    assert demo.whitted.estimate_caveat == ""


def test_a_probe_traces_the_full_renders_pixels(demo, native):
    # The premise of the estimate: a pixel of the probe is the full render's pixel, so
    # no resolution model is needed.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    frame = sync_frame(depsgraph, native)
    # At a fixed count of samples (a noise threshold's depend on the neighbours too: below).
    quality = replace(preset("PREVIEW"), adaptive_sampling=False)
    settings = frame.at_quality(depsgraph, native, quality)
    full = frame.job(native, settings)
    _render(full)
    settings.tile_size = 8
    settings.probe_stride = 4
    probe = frame.job(native, settings)
    stats = _render(probe)
    traced = probe.cost_image() > 0.0
    assert stats["pixels"] == traced.sum()
    assert WIDTH * HEIGHT / 16 * 0.8 < traced.sum() < WIDTH * HEIGHT / 16 * 1.2
    # Spread over the whole frame: every row of tiles has some (and every column, given
    # n^2 rows of tiles: tests/native/schedule_test.cpp).
    assert traced.any(axis=1).reshape(-1, 8).any(axis=1).all()
    np.testing.assert_array_equal(probe.image()[traced], full.image()[traced])
    np.testing.assert_array_equal(probe.cost_image()[traced], full.cost_image()[traced])
    assert not probe.image()[~traced].any()


def test_a_probe_takes_the_full_renders_samples_per_pixel_at_a_noise_threshold(demo, native):
    # With a noise threshold, a pixel stops once it and its 8 neighbours are converged:
    # the probe's pixels at its tiles' edges lack some neighbours, so its counts are not
    # the full render's pixel by pixel, but their mean is what the estimate scales.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    frame = sync_frame(depsgraph, native)
    settings = frame.at_quality(depsgraph, native, preset("PREVIEW"))
    full = frame.job(native, settings)
    full_stats = _render(full)
    settings.tile_size, settings.probe_stride = 2, 4
    probe = frame.job(native, settings)
    stats = _render(probe)
    full_mean = full_stats["samples"] / full_stats["pixels"]
    probe_mean = stats["samples"] / stats["pixels"]
    assert full_stats["samples_per_pixel"][0] < full_stats["samples_per_pixel"][2]
    assert probe_mean == pytest.approx(full_mean, rel=0.25)


def test_the_copies_a_render_skips_are_left_out_of_the_fixed_costs(demo):
    # Blender < 4.1: a render depsgraph computes the corner normals of a mesh with auto
    # smooth, and F12 reads it in place; the viewport's export copies it and computes
    # them itself, work the Estimate must not predict for the render.
    assert copy_seconds(bpy.context.evaluated_depsgraph_get()) == 0.0
    mesh = next(o for o in demo.objects if o.type == "MESH").data
    if not hasattr(mesh, "use_auto_smooth"):
        pytest.skip("Blender 4.1+: to_mesh() shares the normals; renders copy as the viewport")
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.use_auto_smooth = True  # sharp edges by angle: normals per corner
    mesh.update()
    assert copy_seconds(bpy.context.evaluated_depsgraph_get()) > 0.0
