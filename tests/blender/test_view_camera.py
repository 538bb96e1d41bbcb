"""The viewport's camera (addon/viewport/camera.py) reads the view's matrices; here it
is checked against Blender's own camera maths: the projection Blender builds for a
camera (Object.calc_matrix_camera, what the viewport's camera view uses) must give
the same window, clip range and placement as the F12 camera exporter."""

import math
from types import SimpleNamespace

import bpy
import numpy as np
import pytest
from mathutils import Matrix
from whitted.export.camera import convert_camera
from whitted.viewport.camera import border_pixels, camera_frame, view_camera
from whitted.viewport.session import region_camera


@pytest.fixture
def camera(empty_scene):
    data = bpy.data.cameras.new("Camera")
    obj = bpy.data.objects.new("Camera", data)
    obj.location = (1.0, -6.0, 2.5)
    obj.rotation_euler = (math.radians(70.0), 0.0, math.radians(15.0))
    empty_scene.collection.objects.link(obj)
    empty_scene.camera = obj
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = 320, 200
    bpy.context.view_layer.update()  # matrix_world
    return obj


def _as_view(obj, scene):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    render = scene.render
    projection = obj.calc_matrix_camera(
        depsgraph, x=render.resolution_x, y=render.resolution_y, scale_x=1.0, scale_y=1.0
    )
    return view_camera(obj.matrix_world.inverted(), projection, obj.data.type == "PERSP")


@pytest.mark.parametrize(
    "setup",
    [
        {},
        {"lens": 85.0, "shift_x": 0.2, "shift_y": -0.1},
        {"sensor_fit": "VERTICAL", "sensor_height": 30.0},
        {"type": "ORTHO", "ortho_scale": 4.0, "shift_x": 0.1},
    ],
    ids=["default", "lens-shift", "vertical-fit", "ortho"],
)
def test_view_matrices_give_the_f12_camera(camera, empty_scene, setup):
    for name, value in setup.items():
        setattr(camera.data, name, value)
    expected = convert_camera(camera, empty_scene.render, [])
    got = _as_view(camera, empty_scene)
    assert got.projection == expected.projection
    np.testing.assert_allclose(got.window, expected.window, rtol=1e-5, atol=1e-6)
    if got.projection == "PERSPECTIVE":
        np.testing.assert_allclose(np.array(got.to_world), expected.to_world, atol=1e-5)
        assert got.clip_start == pytest.approx(expected.clip_start, rel=1e-3)
        assert got.clip_end == pytest.approx(expected.clip_end, rel=1e-3)
    else:
        # Orthographic: the same axes; the origin may move back along +Z (rays are
        # parallel, so only where they start changes).
        to_world = np.array(got.to_world)
        np.testing.assert_allclose(to_world[:3, :3], expected.to_world[:3, :3], atol=1e-5)
        offset = to_world[:3, 3] - expected.to_world[:3, 3]
        assert np.linalg.norm(np.cross(offset, expected.to_world[:3, 2])) < 1e-4


def test_orthographic_view_behind_the_view_point_moves_the_origin_back():
    # Blender's orthographic viewport clips from -clip_end/2 to +clip_end/2 around the
    # view point (here: near -50, far 50).
    near, far, half = -50.0, 50.0, 3.0
    projection = Matrix.OrthoProjection("XY", 4) @ Matrix.Diagonal((1 / half, 1 / half, 1, 1))
    projection[2][2] = -2.0 / (far - near)
    projection[2][3] = -(far + near) / (far - near)
    got = view_camera(Matrix.Identity(4), projection, False)
    assert got.window == pytest.approx((-half, half, -half, half))
    assert got.clip_start == 0.0
    assert got.clip_end == pytest.approx(far - near)
    assert np.array(got.to_world)[:3, 3] == pytest.approx((0.0, 0.0, -near))


def test_camera_frame_and_border_in_region_pixels(camera, empty_scene):
    # Seen through its own camera, the camera frame covers the whole image, and a
    # border's fractions land on those pixels.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    render = empty_scene.render
    projection = camera.calc_matrix_camera(
        depsgraph, x=render.resolution_x, y=render.resolution_y, scale_x=1.0, scale_y=1.0
    )
    perspective = projection @ camera.matrix_world.inverted()
    corners = [camera.matrix_world @ c for c in camera.data.view_frame(scene=empty_scene)]
    frame = camera_frame(perspective, corners, 320, 200)
    assert frame == pytest.approx((0.0, 0.0, 320.0, 200.0), abs=1e-3)
    assert border_pixels(frame, (0.25, 0.5, 0.75, 1.0), 320, 200) == (80, 100, 240, 200)
    assert border_pixels(frame, (1.0, 1.0, 1.0, 1.0), 320, 200) is None


def _camera_view(obj, scene, width, height):
    """A 3D view looking through `obj` exactly (no zoom, no offset), as region data."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    window = obj.calc_matrix_camera(depsgraph, x=width, y=height, scale_x=1.0, scale_y=1.0)
    view = obj.matrix_world.inverted()
    return SimpleNamespace(
        view_matrix=view,
        window_matrix=window,
        perspective_matrix=window @ view,
        is_perspective=True,
        view_perspective="CAMERA",
    )


@pytest.mark.parametrize("kind", ["PERSP", "PANO"])
def test_the_camera_view_shows_the_cameras_lens_and_panorama(camera, empty_scene, kind):
    # As Cycles' viewport: through the camera, its depth of field and its panorama; the
    # same camera as F12's when the view fits the camera frame to the region.
    camera.data.type = kind
    camera.data.dof.use_dof = True
    camera.data.dof.aperture_fstop = 1.4
    camera.data.shift_x = 0.05
    bpy.context.view_layer.update()
    expected = convert_camera(camera, empty_scene.render, [])
    space = SimpleNamespace(camera=None, use_local_camera=False)
    view = _camera_view(camera, empty_scene, 320, 200)
    got = region_camera(empty_scene, space, view, 320, 200)
    assert got.lens == expected.lens and got.lens.aperture_radius > 0.0
    assert got.projection == expected.projection
    assert got.panorama == expected.panorama
    np.testing.assert_allclose(got.window, expected.window, rtol=1e-4, atol=1e-4)
    # Outside camera view: the view's own pinhole.
    view.view_perspective = "PERSP"
    outside = region_camera(empty_scene, space, view, 320, 200)
    assert outside.lens.aperture_radius == 0.0 and outside.panorama is None
