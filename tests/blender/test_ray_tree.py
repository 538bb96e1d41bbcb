"""The ray-tree inspector in Blender: bpy.ops.whitted.inspect_ray_tree on the demo
scene traces a pixel again, and the stored tree has the rays Whitted's recursion must
trace there, contributions that sum to the rendered pixel, and feelers that name what
blocks them."""

import json

import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

WIDTH, HEIGHT = 96, 72


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    bpy.ops.whitted.apply_preset(preset="PREVIEW")
    # The inspector traces a pixel's whole grid of samples; a noise threshold may stop the
    # render's pixel earlier (docs/notes/adaptive_sampling.md): compare at a fixed count.
    scene.whitted.adaptive_sampling = False
    return scene


def _pixel_of(scene, point):
    """The pixel (x, y from the bottom-left) whose centre sees `point`."""
    u, v, _ = world_to_camera_view(scene, scene.camera, Vector(point))
    return int(u * WIDTH), int(v * HEIGHT)


def _inspect(x, y):
    assert bpy.ops.whitted.inspect_ray_tree(x=x, y=y) == {"FINISHED"}
    return json.loads(bpy.context.scene.whitted.last_ray_tree)


def test_glass_sphere_pixel_has_camera_refraction_and_feeler_rays_summing_to_the_render(
    demo, demo_scene_module, render_pixels
):
    pixels = render_pixels(demo)
    x, y = _pixel_of(demo, demo_scene_module.GLASS_CENTER)
    tree = _inspect(x, y)
    rays = tree["rays"]
    camera = [r for r in rays if r["kind"] == "camera"]
    # One camera ray per anti-aliasing sample.
    assert len(camera) > 1 and len(camera) == len({r["sample"] for r in rays})
    assert all(r["object"] == "Glass Sphere" and r["depth"] == 0 for r in camera)
    refraction_depths = {r["depth"] for r in rays if r["kind"] == "refraction"}
    assert {1, 2} <= refraction_depths  # into the sphere and out again
    assert any(r["kind"] == "shadow" and r["cut"] is None for r in rays)
    total = np.sum([r["contribution"] for r in rays], axis=0)
    rendered = pixels[y, x, :3]
    np.testing.assert_allclose(tree["pixel"], rendered, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(total, rendered, rtol=1e-5, atol=1e-6)
    # The summary's depths add up to the pixel too.
    np.testing.assert_allclose(np.sum(tree["summary"]["depths"], axis=0), rendered, rtol=1e-5)


def test_floor_pixel_in_the_cube_shadow_has_a_blocked_feeler_naming_the_cube(
    demo, demo_scene_module
):
    from whitted.native import load_native
    from whitted.sync.frame import sync_frame

    # The cube's shadow from the sun: behind the cube along the sun's direction, on z = 0.
    centre = Vector(demo_scene_module.CUBE_CENTER)
    direction = Vector(demo_scene_module.SUN_DIRECTION).normalized()
    on_floor = centre - direction * (centre.z / direction.z)
    native = load_native()
    job = sync_frame(bpy.context.evaluated_depsgraph_get(), native).job(native)
    cx, cy = _pixel_of(demo, on_floor)
    candidates = [(cx + dx, cy + dy) for dy in range(-3, 4) for dx in range(-3, 4)]

    def sun_blocked(tree):
        return any(
            r["kind"] == "shadow" and r["light"] == "Sun" and r["blocked"] and r["depth"] == 0
            for r in tree["rays"]
        )

    shadowed = next(p for p in candidates if sun_blocked(job.inspect(*p)))
    tree = _inspect(*shadowed)
    assert tree["rays"][0]["object"] == "Floor"
    blocked = [r for r in tree["rays"] if r["kind"] == "shadow" and r["blocked"]]
    assert blocked and all(r["object"] == "Cube" for r in blocked if r["light"] == "Sun")
    assert all(r["contribution"] == [0.0, 0.0, 0.0] for r in blocked)
    assert "depth 0" in tree["summary"]["text"]


def test_tree_becomes_a_curve_object_and_clears(demo, demo_scene_module):
    x, y = _pixel_of(demo, demo_scene_module.MIRROR_CENTER)
    tree = _inspect(x, y)
    assert any(r["kind"] == "reflection" and r["depth"] == 1 for r in tree["rays"])
    assert bpy.ops.whitted.ray_tree_to_curve() == {"FINISHED"}
    curve = bpy.data.objects["Whitted Ray Tree"]
    drawn = [r for r in tree["rays"] if r["cut"] is None]
    assert len(curve.data.splines) == len(drawn)
    first = curve.data.splines[0].points
    assert tuple(first[0].co)[:3] == pytest.approx(tree["rays"][0]["origin"], abs=1e-5)
    assert bpy.ops.whitted.clear_ray_tree() == {"FINISHED"}
    assert demo.whitted.last_ray_tree == ""


def test_pixels_outside_the_image_are_refused_with_a_report(demo):
    with pytest.raises(RuntimeError, match="outside"):
        bpy.ops.whitted.inspect_ray_tree(x=WIDTH, y=0)
    assert demo.whitted.last_ray_tree == ""


def test_a_floor_pixel_under_an_emissive_panel_has_feelers_naming_it(empty_scene, render_pixels):
    # Emissive meshes are lights: the inspector shows their feelers, each naming the
    # mesh it samples, and the contributions still sum to the rendered pixel.
    from whitted.ui.ray_tree import _ray_label
    from whitted_tools.material_scenes import panel_room

    scene = empty_scene
    panel_room(scene)
    scene.render.engine = "WHITTED"
    pixels = render_pixels(scene)
    x, y = 32, 8  # the floor, near the bottom of the frame
    tree = _inspect(x, y)
    feelers = [r for r in tree["rays"] if r["kind"] == "shadow"]
    assert len(feelers) == 4 * 4 * 4  # 2 x 2 camera samples, 4 x 4 emitter feelers each
    assert all(r["emitter"] == "Panel" and r["light"] is None for r in feelers)
    assert _ray_label(feelers[0]).startswith("shadow -> Panel: ")
    total = np.sum([r["contribution"] for r in tree["rays"]], axis=0)
    np.testing.assert_allclose(total, pixels[y, x, :3], rtol=1e-5, atol=1e-6)
    assert pixels[y, x, 0] > 0.0


def test_a_pixel_in_the_lit_fog_shows_its_segment_scatter_points_and_feelers(
    empty_scene, render_pixels
):
    # The spot's cone in the fog stage: each camera ray ends on the fog box's bound and goes
    # on behind it in its own sample; its stretch inside the fog is a "volume" segment, the
    # feelers from its scatter points name the spot, and the contributions, the fog's among
    # them, sum to the rendered pixel.
    from whitted.ray_tree.tree import segments
    from whitted_tools.volume_scenes import fog_stage

    scene = fog_stage(empty_scene)
    scene.render.engine = "WHITTED"
    scene.whitted.aa_samples = 2
    scene.whitted.adaptive_sampling = False
    pixels = render_pixels(scene)
    height = pixels.shape[0]
    upper = pixels[height // 2 :, :, :3].sum(axis=2)  # rows bottom to top: above the floor
    row, x = np.unravel_index(np.argmax(upper), upper.shape)
    y = height // 2 + int(row)
    tree = _inspect(int(x), y)
    rays = tree["rays"]
    camera = [r for r in rays if r["kind"] == "camera"]
    assert len(camera) == 4 and all(r["object"] == "Fog" for r in camera)
    assert {r["sample"] for r in rays} == {0, 1, 2, 3}
    volume = [r for r in rays if r["kind"] == "volume"]
    assert volume and all(rays[r["parent"]]["kind"] == "transparent" for r in volume)
    scatter = [r for r in rays if r.get("scatter")]
    assert scatter and all(rays[r["parent"]]["kind"] == "volume" for r in scatter)
    assert all(r["light"] == "Spot" for r in scatter)
    lit = [r for r in scatter if r["cut"] is None]
    media = tree["summary"]["media"]
    assert media["segments"] == len(volume) and media["feelers"] == len(lit) > 0
    rendered = pixels[y, x, :3]
    total = np.sum([r["contribution"] for r in rays], axis=0)
    np.testing.assert_allclose(total, rendered, rtol=1e-5, atol=1e-6)
    # Nothing but the fog lights this pixel: no surface behind it is lit.
    np.testing.assert_allclose(media["scattered"], rendered, rtol=1e-4, atol=1e-6)
    # Drawn: the segments along their rays, in their own colour.
    assert sum(kind == "volume" for kind, *_ in segments(tree)) == len(volume)
    assert bpy.ops.whitted.ray_tree_to_curve() == {"FINISHED"}


@pytest.mark.parametrize("node", ["ambient occlusion", "bevel"])
def test_a_pixel_of_a_ray_traced_node_shows_its_rays_under_the_camera_ray(
    node, empty_scene, render_pixels
):
    # Each camera ray meeting the objects has the node's rays beneath it: ambient
    # occlusion rays Distance long (1), some blocked by the floor's cube; a bevel's probes.
    from test_ambient_occlusion import ao_material
    from test_ambient_occlusion import stage as ao_stage
    from test_bevel import bevel_cube

    if node == "bevel":
        bevel_cube(empty_scene)
    else:
        ao_stage(empty_scene, ao_material())
    scene = empty_scene
    scene.render.engine = "WHITTED"
    scene.whitted.aa_samples = 2
    scene.whitted.adaptive_sampling = False
    render_pixels(scene)
    # Beside the cube's foot (ambient occlusion), on the cube's near corner (bevel).
    point = (0.0, 0.0, 0.5) if node == "bevel" else (0.9, -0.25, 0.0)
    u, v, _ = world_to_camera_view(scene, scene.camera, Vector(point))
    tree = _inspect(int(u * scene.render.resolution_x), int(v * scene.render.resolution_y))
    rays = tree["rays"]
    kind = node.replace(" ", "_")
    traced = [r for r in rays if r["kind"] == kind]
    assert traced and all(rays[r["parent"]]["kind"] == "camera" for r in traced)
    per_sample = 16 if node == "ambient occlusion" else 8
    camera = [r for r in rays if r["kind"] == "camera" and r["object"]]
    assert len(traced) >= per_sample * len(camera) > 0
    assert all(r["weight"] == [0.0, 0.0, 0.0] for r in traced)
    if node == "ambient occlusion":
        assert len(traced) == per_sample * len(camera)
        assert any(r["blocked"] for r in traced) and not all(r["blocked"] for r in traced)
