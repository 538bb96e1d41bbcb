"""Rendering with Whitted inside Blender: the demo scene's character, errors, sizes.

Pixels are read back as linear radiance (see conftest.render_pixels), rows
bottom to top; scene points are located in the image with Blender's own
projection (world_to_camera_view) and visibility with Blender's own ray cast,
so the expectations do not go through the exporters under test.
"""

import math
import os
import signal
import threading
import time

import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

WIDTH, HEIGHT = 160, 120
# Blender's ray cast starts this far above the floor so it does not hit the floor.
ABOVE_FLOOR = 1e-4


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    """The demo scene at test size; returns (scene, demo_scene module)."""
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene, demo_scene_module


def pixel_of(scene, point):
    """(row, column) of the pixel that shows world `point`, rows from the bottom."""
    view = world_to_camera_view(scene, scene.camera, Vector(point))
    return int(view.y * scene.render.resolution_y), int(view.x * scene.render.resolution_x)


def disc(scene, center, radius):
    """Projected centre (row, column) and radius, in pixels, of a sphere."""
    right = scene.camera.matrix_world.col[0].xyz.normalized()
    row, column = (
        np.array(world_to_camera_view(scene, scene.camera, Vector(center))[:2])
        * (scene.render.resolution_x, scene.render.resolution_y)
    )[::-1]
    edge = world_to_camera_view(scene, scene.camera, Vector(center) + radius * right)
    radius_px = abs(edge.x * scene.render.resolution_x - column)
    return row, column, radius_px


def halves(shape, row, column, inner, outer, half_width):
    """Masks of the pixels whose centres lie `inner` to `outer` pixels above, and
    below, (row, column), within `half_width` pixels of its column."""
    rows, columns = np.mgrid[0 : shape[0], 0 : shape[1]] + 0.5
    distance = np.hypot(rows - row, columns - column)
    band = (distance >= inner) & (distance < outer) & (np.abs(columns - column) < half_width)
    return band & (rows > row), band & (rows < row)


def is_sky(pixels):
    # The sky is blue; the floor red or yellow; neither is both.
    return (pixels[..., 2] > pixels[..., 0]) & (pixels[..., 2] > 0.3)


def is_floor(pixels):
    return pixels[..., 0] > 2.0 * pixels[..., 2]


def blocker(scene, point, towards=None, direction=None):
    """Name of what Blender's ray cast hits from `point` to a light, or None."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    origin = Vector(point) + Vector((0.0, 0.0, ABOVE_FLOOR))
    ray = Vector(towards) - origin if direction is None else Vector(direction)
    distance = ray.length if direction is None else 1.0e6
    hit, *_, obj, _ = scene.ray_cast(depsgraph, origin, ray.normalized(), distance=distance)
    return obj.name if hit else None


def test_demo_renders_finite_opaque_pixels(demo, render_pixels):
    scene, _ = demo
    pixels = render_pixels(scene)
    assert pixels.shape == (HEIGHT, WIDTH, 4)
    assert np.isfinite(pixels).all()
    assert (pixels[..., :3] >= 0.0).all()
    np.testing.assert_allclose(pixels[..., 3], 1.0)


def test_mirror_sphere_shows_sky_above_and_floor_below(demo, render_pixels):
    scene, demo_scene = demo
    pixels = render_pixels(scene)
    row, column, radius = disc(scene, demo_scene.MIRROR_CENTER, demo_scene.MIRROR_RADIUS)
    # Away from the middle, whose reflection is about the camera's own view.
    upper, lower = halves(pixels.shape, row, column, 0.4 * radius, 0.8 * radius, 0.8 * radius)
    # A mirror ball reflects the sky in its upper half and the floor in its lower.
    assert is_sky(pixels[upper]).mean() > 0.6
    assert is_floor(pixels[lower]).mean() > 0.6
    # A reflected ray that meets nothing sees the sky: reflectivity 0.9 (the mirror's
    # base colour) times the background, in every channel.
    sky = pixels[upper][is_sky(pixels[upper])][:, :3]
    expected = 0.9 * np.array(demo_scene.SKY_COLOR)
    assert np.median(sky, axis=0) == pytest.approx(expected, rel=0.02)


def test_glass_sphere_shows_an_inverted_view(demo, render_pixels):
    scene, demo_scene = demo
    pixels = render_pixels(scene)
    row, column, radius = disc(scene, demo_scene.GLASS_CENTER, demo_scene.GLASS_RADIUS)
    # Rays through the middle of the ball pass nearly straight: look further out.
    upper, lower = halves(pixels.shape, row, column, 0.4 * radius, 0.8 * radius, 0.8 * radius)
    above, below = halves(pixels.shape, row, column, 1.1 * radius, 1.5 * radius, 0.5 * radius)
    # Seen directly, the sky is above the ball and the floor below it ...
    assert is_sky(pixels[above]).mean() > 0.8
    assert is_floor(pixels[below]).mean() > 0.8
    # ... but a glass ball is a lens that turns the view upside down: the floor
    # shows in its upper half and the sky in its lower half.
    assert is_floor(pixels[upper]).mean() > 0.6
    assert is_sky(pixels[lower]).mean() > 0.6


def floor_cell(demo_scene, point):
    """Which floor colour (index into FLOOR_COLORS) the square under `point` has."""
    half = demo_scene.FLOOR_CELLS / 2
    return (math.floor(point[0] + half) + math.floor(point[1] + half)) % 2


def floor_cell_color(demo_scene, point):
    return np.array(demo_scene.FLOOR_COLORS[floor_cell(demo_scene, point)])


def direct_irradiance(demo_scene, point):
    """Irradiance on the floor (normal +Z) at `point` from the sun and the point
    light, ignoring shadows: E = S cos(theta) and E = I cos(theta) / r^2, I = P/(4 pi)."""
    sun = Vector(demo_scene.SUN_DIRECTION).normalized()
    sun_irradiance = demo_scene.SUN_STRENGTH * max(0.0, -sun.z)
    to_light = Vector(demo_scene.POINT_LIGHT_POSITION) - Vector(point)
    intensity = demo_scene.POINT_LIGHT_POWER / (4.0 * math.pi)
    point_irradiance = intensity * (to_light.z / to_light.length) / to_light.length_squared
    return sun_irradiance + point_irradiance


# Centres of floor squares of one colour, near the mirror sphere: one in the shadow
# of the (opaque) mirror sphere from both lights, one lit by both.
SHADOWED = (1.5, 0.5, 0.0)
LIT = (1.5, -1.5, 0.0)


def test_shadow_is_ambient_only_and_darker_by_the_expected_ratio(demo, render_pixels):
    scene, demo_scene = demo
    sun_travel = Vector(demo_scene.SUN_DIRECTION)
    # The premises, checked with Blender's own ray cast.
    assert blocker(scene, SHADOWED, direction=-sun_travel) == "Mirror Sphere"
    assert blocker(scene, SHADOWED, towards=demo_scene.POINT_LIGHT_POSITION) == "Mirror Sphere"
    assert blocker(scene, LIT, direction=-sun_travel) is None
    assert blocker(scene, LIT, towards=demo_scene.POINT_LIGHT_POSITION) is None
    kd = floor_cell_color(demo_scene, SHADOWED)
    assert floor_cell_color(demo_scene, LIT) == pytest.approx(kd)

    # The seed's ambient term: the Lecture model's (the Blender model lights with the sky).
    scene.whitted.local_model = "LECTURE"
    pixels = render_pixels(scene)
    shadowed = pixels[pixel_of(scene, SHADOWED)][:3]
    lit = pixels[pixel_of(scene, LIT)][:3]
    # The floor is Lambertian (no highlight): radiance kd * (Ia + E / pi) with the
    # ambient light Ia equal to the sky colour.
    ambient = np.array(demo_scene.SKY_COLOR)
    expected_shadowed = kd * ambient
    expected_lit = kd * (ambient + direct_irradiance(demo_scene, LIT) / math.pi)
    assert shadowed / lit == pytest.approx(expected_shadowed / expected_lit, rel=0.05)
    assert shadowed == pytest.approx(expected_shadowed, rel=0.02)
    assert lit == pytest.approx(expected_lit, rel=0.03)


def test_scene_without_lights_renders_ambient_light_only(demo, render_pixels):
    scene, demo_scene = demo
    for obj in [obj for obj in scene.objects if obj.type == "LIGHT"]:
        bpy.data.objects.remove(obj)
    scene.whitted.local_model = "LECTURE"  # the seed's ambient term
    pixels = render_pixels(scene)
    kd = floor_cell_color(demo_scene, LIT)
    expected = kd * np.array(demo_scene.SKY_COLOR)
    assert pixels[pixel_of(scene, LIT)][:3] == pytest.approx(expected, rel=0.02)


def test_scene_without_objects_shows_the_background(empty_scene, demo_scene_module, render_pixels):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera
    empty_scene.world = bpy.data.worlds.new("Plain")
    empty_scene.world.color = (0.2, 0.3, 0.4)
    if bpy.app.version < (5, 0, 0):
        empty_scene.world.use_nodes = False
    else:  # 5.0 always uses the world's nodes
        background = empty_scene.world.node_tree.nodes["Background"]
        background.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = 32, 24
    pixels = render_pixels(empty_scene)
    np.testing.assert_allclose(
        pixels[..., :3], np.broadcast_to((0.2, 0.3, 0.4), (24, 32, 3)), rtol=1e-5
    )


def test_resolution_percentage_sets_the_image_size(demo, render_pixels):
    scene, _ = demo
    scene.render.resolution_x, scene.render.resolution_y = 201, 100
    scene.render.resolution_percentage = 50
    assert render_pixels(scene).shape == (50, 100, 4)


@pytest.mark.parametrize("shift_x", [0.0, 0.25])
def test_orthographic_top_view_shows_the_checkerboard(demo, render_pixels, shift_x):
    scene, demo_scene = demo
    for obj in scene.objects:
        if obj.type == "MESH" and obj.name != "Floor":
            obj.hide_render = True
    # Straight down from above: a 4 m wide view over 160 px, 40 px per 1 m square.
    camera = scene.camera
    camera.location = (0.0, 0.0, 20.0)
    camera.rotation_euler = (0.0, 0.0, 0.0)
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 4.0
    camera.data.shift_x = shift_x
    scene.render.resolution_x = scene.render.resolution_y = 160
    pixels = render_pixels(scene)
    for row in range(4):
        for column in range(4):
            # Square centres in world units; shift moves the view by shift * ortho_scale.
            x = -1.5 + column + shift_x * 4.0
            y = -1.5 + row
            red, green, _ = pixels[20 + 40 * row, 20 + 40 * column, :3]
            # Yellow squares (index 1) reflect about as much green as red, red ones little.
            assert int(green / red > 0.4) == floor_cell(demo_scene, (x, y)), (row, column)


def test_scene_without_camera_raises_a_clear_error(empty_scene):
    empty_scene.render.engine = "WHITTED"
    # Blender itself refuses before the engine runs.
    with pytest.raises(RuntimeError, match="camera"):
        bpy.ops.render.render()


def test_non_camera_object_as_camera_reports_whitted_error(empty_scene, native):
    empty = bpy.data.objects.new("Empty", None)
    empty_scene.collection.objects.link(empty)
    empty_scene.camera = empty
    empty_scene.render.engine = "WHITTED"
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = 8, 8
    # Blender accepts any object as the camera, so this reaches the engine, whose
    # ERROR report makes the operator raise.
    with pytest.raises(RuntimeError, match="Whitted: the scene camera 'Empty' is not a camera"):
        bpy.ops.render.render()


def test_break_stops_the_render_within_a_fifth_of_a_second(demo, native):
    """What Esc does, headless: set Blender's break flag while Whitted renders.

    In `blender -b` the first SIGINT is Blender's "internal break event": it sets
    the flag Esc sets, which RenderEngine.test_break() reports. (A second one
    kills Blender, so only this test sends one.) The bpy module leaves SIGINT to
    Python, which raises KeyboardInterrupt instead: nothing can press Esc there.
    """
    if not bpy.app.binary_path:
        pytest.skip("the bpy module has no scriptable Esc (SIGINT raises KeyboardInterrupt)")
    scene, _ = demo
    # Big enough to take many seconds: the break must cut it short.
    scene.render.resolution_x, scene.render.resolution_y = 1600, 1200
    scene.whitted.aa_samples = 16
    scene.render.engine = "WHITTED"
    rendering = threading.Event()
    sent = []

    def on_stats(*_):
        rendering.set()  # the engine's poll loop runs: it calls update_stats

    def press_escape():
        if rendering.wait(timeout=30.0):
            time.sleep(0.3)
            sent.append(time.perf_counter())
            os.kill(os.getpid(), signal.SIGINT)

    bpy.app.handlers.render_stats.append(on_stats)
    sender = threading.Thread(target=press_escape, daemon=True)
    try:
        sender.start()
        bpy.ops.render.render()
        returned = time.perf_counter()
    finally:
        bpy.app.handlers.render_stats.remove(on_stats)
        sender.join()
    assert sent, "the render never reported stats"
    assert sent[0] < returned, "the render finished before the break: make it bigger"
    assert returned - sent[0] < 0.2
