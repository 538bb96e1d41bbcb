"""Camera export: the image window against hand-computed values and Blender's own frame."""

import math

import bpy
import numpy as np
import pytest
from whitted.export import ExportError
from whitted.export.camera import convert_camera


def add_camera(scene, width, height, **camera_settings):
    camera = bpy.data.cameras.new("Camera")
    for key, value in camera_settings.items():
        setattr(camera, key, value)
    obj = bpy.data.objects.new("Camera", camera)
    scene.collection.objects.link(obj)
    scene.camera = obj
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    return obj


def convert(scene, warnings):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = depsgraph.scene
    return convert_camera(evaluated.camera, evaluated.render, warnings)


@pytest.mark.parametrize(
    ("width", "height", "settings", "window"),
    [
        # 36 mm sensor on 50 mm: the fitted side spans 36/50 = 0.72 at distance 1.
        (160, 120, {"sensor_fit": "AUTO"}, (-0.36, 0.36, -0.27, 0.27)),
        # AUTO fits the sensor width to the longer side, here the height.
        (120, 160, {"sensor_fit": "AUTO"}, (-0.27, 0.27, -0.36, 0.36)),
        (120, 160, {"sensor_fit": "HORIZONTAL"}, (-0.36, 0.36, -0.48, 0.48)),
        # VERTICAL uses the sensor height (24 mm): 24/50 = 0.48.
        (160, 120, {"sensor_fit": "VERTICAL"}, (-0.32, 0.32, -0.24, 0.24)),
        # Shift is in units of the fitted side: 0.1 * 0.72 and -0.2 * 0.72.
        (160, 120, {"shift_x": 0.1, "shift_y": -0.2}, (-0.288, 0.432, -0.414, 0.126)),
        # 100 mm halves the window.
        (160, 120, {"lens": 100.0}, (-0.18, 0.18, -0.135, 0.135)),
        # Orthographic: ortho_scale spans the fitted side, in camera units.
        (160, 120, {"type": "ORTHO", "ortho_scale": 6.0}, (-3.0, 3.0, -2.25, 2.25)),
        (120, 160, {"type": "ORTHO", "ortho_scale": 6.0}, (-2.25, 2.25, -3.0, 3.0)),
        (
            160,
            120,
            {"type": "ORTHO", "ortho_scale": 6.0, "shift_x": 0.5, "shift_y": 0.25},
            (0.0, 6.0, -0.75, 3.75),
        ),
    ],
)
def test_window_hand_computed(empty_scene, warnings, width, height, settings, window):
    add_camera(empty_scene, width, height, **settings)
    camera = convert(empty_scene, warnings)
    assert camera.window == pytest.approx(window, abs=1e-6)
    assert camera.projection == (
        "ORTHOGRAPHIC" if settings.get("type") == "ORTHO" else "PERSPECTIVE"
    )
    assert (camera.width, camera.height) == (width, height)
    assert warnings == []


@pytest.mark.parametrize("camera_type", ["PERSP", "ORTHO"])
@pytest.mark.parametrize("sensor_fit", ["AUTO", "HORIZONTAL", "VERTICAL"])
@pytest.mark.parametrize("size", [(160, 90), (90, 160), (100, 100)])
@pytest.mark.parametrize("pixel_aspect", [(1.0, 1.0), (2.0, 1.0), (1.0, 1.5)])
def test_window_matches_blenders_camera_frame(
    empty_scene, warnings, camera_type, sensor_fit, size, pixel_aspect
):
    obj = add_camera(
        empty_scene,
        *size,
        type=camera_type,
        sensor_fit=sensor_fit,
        sensor_width=32.0,
        sensor_height=20.0,
        lens=42.0,
        ortho_scale=5.0,
        shift_x=0.13,
        shift_y=-0.07,
    )
    empty_scene.render.pixel_aspect_x, empty_scene.render.pixel_aspect_y = pixel_aspect
    camera = convert(empty_scene, warnings)
    # Blender's view_frame gives the image corners in camera space; a perspective
    # frame lies on a plane at some depth z < 0: divide by -z for distance 1.
    corners = np.array([tuple(v) for v in obj.data.view_frame(scene=empty_scene)])
    if camera_type == "PERSP":
        corners = corners[:, :2] / -corners[:, 2:3]
    expected = (corners[:, 0].min(), corners[:, 0].max(), corners[:, 1].min(), corners[:, 1].max())
    assert camera.window == pytest.approx(expected, abs=1e-5)


def test_resolution_percentage(empty_scene, warnings):
    add_camera(empty_scene, 1921, 1080)
    empty_scene.render.resolution_percentage = 50
    camera = convert(empty_scene, warnings)
    # Blender rounds down: 1921 * 50 // 100.
    assert (camera.width, camera.height) == (960, 540)


def test_to_world_without_scale_and_clip_range(empty_scene, warnings):
    obj = add_camera(empty_scene, 64, 64, clip_start=0.25, clip_end=250.0)
    obj.location = (1.0, -2.0, 3.0)
    obj.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    obj.scale = (2.0, 3.0, 4.0)
    camera = convert(empty_scene, warnings)
    # Rotated 90 degrees about X: local -Z (the view direction) becomes world +Y and
    # local +Y (up) world +Z; scale removed, translation kept.
    expected = np.array(
        [[1.0, 0.0, 0.0, 1.0], [0.0, 0.0, -1.0, -2.0], [0.0, 1.0, 0.0, 3.0], [0.0, 0.0, 0.0, 1.0]]
    )
    np.testing.assert_allclose(camera.to_world, expected, atol=1e-6)
    assert (camera.clip_start, camera.clip_end) == pytest.approx((0.25, 250.0))


def test_panoramic_camera_is_converted_without_warnings(empty_scene, warnings):
    # It used to render as a perspective camera, with a warning (tests/blender/test_panorama.py
    # compares each panorama type with Cycles).
    add_camera(empty_scene, 64, 64, type="PANO")
    camera = convert(empty_scene, warnings)
    assert camera.projection == "PANORAMIC"
    assert camera.panorama is not None
    assert warnings == []


def test_stereoscopy_is_rendered_as_one_view_and_said(empty_scene, warnings):
    add_camera(empty_scene, 64, 64)
    empty_scene.render.use_multiview = True
    convert(empty_scene, warnings)
    assert len(warnings) == 1 and "renders one view" in warnings[0]


def test_no_camera_is_an_export_error(empty_scene, warnings):
    with pytest.raises(ExportError, match="Whitted: the scene has no camera"):
        convert_camera(None, empty_scene.render, warnings)


def test_non_camera_object_as_scene_camera_is_an_export_error(empty_scene, warnings):
    empty = bpy.data.objects.new("Empty", None)
    empty_scene.collection.objects.link(empty)
    empty_scene.camera = empty
    with pytest.raises(ExportError, match="'Empty' is not a camera"):
        convert(empty_scene, warnings)
