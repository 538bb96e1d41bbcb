"""Depth of field (issue 30, first part): Blender's camera Depth of Field as a thin lens
(native scene/camera.h Lens), read as Cycles reads it, against Cycles; off, the
pinhole's pixels; named in the report either way."""

import json
import math

import bpy
import numpy as np
import pytest
from cycles_scenes import render_rgba, set_cycles_direct_light
from whitted.export.camera import PINHOLE, convert_camera
from whitted_tools.camera_scenes import balls_in_a_row


def test_the_lens_is_read_as_cycles_reads_it(empty_scene):
    balls_in_a_row(empty_scene)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = depsgraph.scene
    lens = convert_camera(evaluated.camera, evaluated.render, []).lens
    # 50 mm at f/0.5: a radius of 0.05 m; the focus object 5 m down the view axis,
    # the depth of its centre (the camera looks slightly down at it).
    assert lens.aperture_radius == pytest.approx(0.05)
    view = np.array(evaluated.camera.matrix_world)[:3, 2]
    centre = np.array((0.0, 5.0, 0.5)) - np.array((0.0, 0.0, 1.0))
    assert lens.focus_distance == pytest.approx(abs(view @ centre), rel=1e-5)
    assert lens.fstop == pytest.approx(0.5)
    empty_scene.camera.data.dof.use_dof = False
    depsgraph = bpy.context.evaluated_depsgraph_get()
    assert convert_camera(depsgraph.scene.camera, depsgraph.scene.render, []).lens == PINHOLE


def test_depth_of_field_as_cycles(empty_scene, tmp_path, native, monkeypatch):
    # Before, everything was sharp and nothing said why.
    from whitted_tools.metrics import subject_figures

    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    balls_in_a_row(scene)
    set_cycles_direct_light(scene, samples=256)
    scene.cycles.filter_width = 1.5  # Cycles' default; the lens needs samples over the pixel
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = 8
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    stats = json.loads(stats_path.read_text())
    decision = next(e for e in stats["effects"] if e["name"] == "depth of field")
    assert decision["on"] and decision["why"].startswith("aperture radius 0.05, in focus at ")
    scene.camera.data.dof.use_dof = False
    sharp = render_rgba(scene, "WHITTED", str(tmp_path / "sharp.exr"))
    value, ratio = subject_figures(whitted, cycles)
    sharp_value, _ = subject_figures(sharp, cycles)

    def error(image):  # mean absolute difference from Cycles, linear RGB
        return float(np.abs(image[..., :3] - cycles[..., :3]).mean())

    print(
        f"\ndepth of field: SSIM {value:.4f} (sharp {sharp_value:.4f}), ratio {ratio:.4f}, "
        f"mean difference {error(whitted):.5f} (sharp {error(sharp):.5f})"
    )
    # Measured in 3.4 and 5.2: SSIM 0.995 against the sharp render's 0.980, the mean
    # difference 0.0011 against 0.0015 (the rest is the pixel filters: Cycles'
    # Blackman-Harris of width 1.5 against Whitted's box).
    assert value > 0.99 and value > sharp_value + 0.01
    assert error(whitted) < 0.85 * error(sharp)
    assert abs(ratio - 1.0) < 0.05
    stats = json.loads(stats_path.read_text())
    decision = next(e for e in stats["effects"] if e["name"] == "depth of field")
    assert not decision["on"]


def test_depth_of_field_off_renders_the_pinholes_pixels(empty_scene, render_pixels):
    # Use DOF off, or an aperture at f/infinity in effect: the same pixels as before.
    balls_in_a_row(empty_scene)
    empty_scene.camera.data.dof.use_dof = False
    off = render_pixels(empty_scene)
    empty_scene.camera.data.dof.use_dof = True
    empty_scene.camera.data.dof.aperture_fstop = 1e9
    nearly = render_pixels(empty_scene)
    assert np.abs(off - nearly).max() < 1e-3
    assert not math.isnan(float(off.sum()))
