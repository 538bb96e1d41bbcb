"""World export: background radiance, and the light the world gives surfaces: the
ambient term of the Lecture model, the world light of the Blender model
(test_world_light.py compares that with Cycles)."""

import bpy
import pytest
from whitted.export.world import convert_world
from whitted.properties.presets import preset
from whitted.sync import SceneSync, SyncParams
from whitted_tools.material_scenes import lambert_material


def node_world(color, strength):
    world = bpy.data.worlds.new("World")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    return world


def test_no_world_is_black(warnings):
    world = convert_world(None, 1.0, warnings)
    assert world.background == (0.0, 0.0, 0.0)
    assert world.ambient == (0.0, 0.0, 0.0)


def test_background_node_color_times_strength(warnings):
    world = convert_world(node_world((0.2, 0.4, 0.8), 2.0), 1.0, warnings, "LECTURE")
    assert world.background == pytest.approx((0.4, 0.8, 1.6))
    assert world.ambient == pytest.approx((0.4, 0.8, 1.6))
    assert not world.light.on and "Lecture" in world.light.why
    assert warnings == []
    # The Blender model: the world is a light, and there is no ambient term.
    world = convert_world(node_world((0.2, 0.4, 0.8), 2.0), 1.0, warnings)
    assert world.ambient == (0.0, 0.0, 0.0)
    assert world.light.on and world.light.width == 0  # one colour: no map


def test_linked_background_color_warns(warnings):
    world = node_world((0.2, 0.4, 0.8), 1.0)
    tree = world.node_tree
    noise = tree.nodes.new("ShaderNodeParticleInfo")  # a node the program lacks
    tree.links.new(noise.outputs["Age"], tree.nodes["Background"].inputs["Color"])
    assert convert_world(world, 1.0, warnings).background == pytest.approx((0.2, 0.4, 0.8))
    assert "'World'" in warnings[0]
    assert "'Background'" in warnings[0]


def test_a_background_colour_from_an_rgb_node_is_used(warnings):
    # The graph folds to a constant: that constant is the background (it was dropped,
    # with a "linked; uses its unlinked value" warning, before).
    world = node_world((1.0, 0.0, 0.0), 2.0)
    tree = world.node_tree
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.2, 0.4, 0.8, 1.0)
    tree.links.new(rgb.outputs[0], tree.nodes["Background"].inputs["Color"])
    converted = convert_world(world, 1.0, warnings, "LECTURE")
    assert converted.background == pytest.approx((0.4, 0.8, 1.6))
    assert converted.ambient == pytest.approx((0.4, 0.8, 1.6))
    assert converted.program is None
    assert warnings == []


def test_world_without_nodes_uses_its_colour(warnings):
    if bpy.app.version >= (5, 0, 0):
        pytest.skip("Blender 5.0 worlds always use nodes")
    world = bpy.data.worlds.new("Plain")
    world.use_nodes = False
    world.color = (0.1, 0.2, 0.3)
    assert convert_world(world, 1.0, warnings).background == pytest.approx((0.1, 0.2, 0.3))


def test_world_not_lighting_diffuse_surfaces_gives_no_ambient(warnings):
    world = node_world((0.2, 0.4, 0.8), 2.0)
    world.cycles_visibility.diffuse = False
    exported = convert_world(world, 1.0, warnings, "LECTURE")
    assert exported.background == pytest.approx((0.4, 0.8, 1.6))
    assert exported.ambient == (0.0, 0.0, 0.0)
    blender = convert_world(world, 1.0, warnings)
    assert blender.ambient == (0.0, 0.0, 0.0)
    assert not blender.light.on and "Diffuse off" in blender.light.why
    world.cycles_visibility.diffuse = True
    world.cycles_visibility.glossy = False  # only diffuse visibility matters
    lecture = convert_world(world, 1.0, warnings, "LECTURE")
    assert lecture.ambient == pytest.approx((0.4, 0.8, 1.6))
    blender = convert_world(world, 1.0, warnings)
    assert blender.light.on and not blender.light.glossy


@pytest.mark.parametrize("ambient_strength", [0.5, 0.0])
def test_ambient_strength_scales_the_ambient_light_only(warnings, ambient_strength):
    world = convert_world(node_world((0.2, 0.4, 0.8), 2.0), ambient_strength, warnings, "LECTURE")
    assert world.background == pytest.approx((0.4, 0.8, 1.6))
    assert world.ambient == pytest.approx(tuple(ambient_strength * c for c in (0.4, 0.8, 1.6)))


@pytest.mark.parametrize("ambient_strength", [1.0, 0.25, 0.0])
def test_world_lights_an_unlit_scene_by_its_ambient_strength(
    empty_scene, render_pixels, ambient_strength
):
    # No lights: a diffuse surface (albedo 0.8) facing the
    # orthographic camera shows only the ambient term ka * Ia * kd, with
    # Ia = world radiance * ambient strength; the sky shows the world itself.
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera
    quad = bpy.data.meshes.new("Quad")
    quad.from_pydata([(-1, -1, -5), (1, -1, -5), (1, 1, -5), (-1, 1, -5)], [], [(0, 1, 2, 3)])
    quad.materials.append(lambert_material("Lambert", 0.8))
    empty_scene.collection.objects.link(bpy.data.objects.new("Quad", quad))
    empty_scene.world = node_world((0.2, 0.4, 0.8), 0.5)
    empty_scene.whitted.ambient_strength = ambient_strength
    empty_scene.whitted.local_model = "LECTURE"
    render = empty_scene.render
    render.resolution_x = render.resolution_y = 8
    render.resolution_percentage = 100
    pixels = render_pixels(empty_scene)
    sky = (0.1, 0.2, 0.4)
    assert pixels[0, 0, :3] == pytest.approx(sky, rel=1e-5)
    surface = tuple(0.8 * ambient_strength * c for c in sky)
    assert pixels[4, 4, :3] == pytest.approx(surface, rel=1e-5, abs=1e-7)
    # The Blender model: the sky is a light over the open quad, which returns albedo x
    # sky exactly (a world of one colour is drawn by the cosine: no noise), whatever the
    # ambient strength.
    empty_scene.whitted.local_model = "BLENDER"
    pixels = render_pixels(empty_scene)
    assert pixels[4, 4, :3] == pytest.approx(tuple(0.8 * c for c in sky), rel=1e-5)


def synced_ambient(scene, native):
    """The ambient light Ia the native scene synced from `scene` renders with."""
    sync = SceneSync(native)
    sync.sync(bpy.context.evaluated_depsgraph_get(), SyncParams.of(scene, preset("PREVIEW")))
    return sync.scene.ambient


def test_environment_texture_becomes_a_world_program(empty_scene, native, warnings):
    import numpy as np
    from whitted.export.nodes import ops

    world = node_world((1.0, 1.0, 1.0), 2.0)
    tree = world.node_tree
    environment = tree.nodes.new("ShaderNodeTexEnvironment")
    environment.interpolation = "Closest"
    # Top half bright, bottom half dark (rows bottom to top).
    image = bpy.data.images.new("sky", 4, 2, float_buffer=True)
    pixels = np.array([[0.0] * 4] * 4 + [[1.0] * 4] * 4, dtype=np.float32)
    image.pixels.foreach_set(pixels.reshape(-1))
    environment.image = image
    tree.links.new(environment.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    exported = convert_world(world, 1.0, warnings, "LECTURE")
    program = exported.program
    assert [int(r[0]) for r in program.code] == [ops.INPUT, ops.ENVIRONMENT, ops.VECTOR_MATH]
    assert int(program.code[0][1]) == ops.IN_POSITION  # the ray's direction
    assert exported.textures[0].image == image
    assert exported.output == int(program.code[-1][2])
    assert exported.ambient_strength == 1.0
    # The ambient: what a surface facing up receives, the bright upper half only, at 2.
    empty_scene.world = world
    empty_scene.whitted.ambient_strength = 0.5
    empty_scene.whitted.local_model = "LECTURE"
    assert synced_ambient(empty_scene, native) == pytest.approx((1.0, 1.0, 1.0), rel=1e-6)


def test_ambient_is_the_cosine_weighted_mean_of_the_upper_hemisphere(empty_scene, native):
    # L = a + b z (z of the ray's direction, from Generated coordinates): over the
    # sphere its mean is a; weighted by cos(theta)/pi over z > 0, a + 2b/3.
    a, b = 0.3, 0.6
    world = node_world((1.0, 1.0, 1.0), 1.0)
    tree = world.node_tree
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    line = tree.nodes.new("ShaderNodeMath")
    line.operation = "MULTIPLY_ADD"
    line.inputs[1].default_value = b
    line.inputs[2].default_value = a
    tree.links.new(coordinates.outputs["Generated"], separate.inputs[0])
    tree.links.new(separate.outputs["Z"], line.inputs[0])
    tree.links.new(line.outputs[0], tree.nodes["Background"].inputs["Strength"])
    empty_scene.world = world
    empty_scene.whitted.ambient_strength = 0.5
    empty_scene.whitted.local_model = "LECTURE"
    # 24 x 24 cells, one direction at each centre: the quadrature's error is ~1e-4.
    expected = (0.5 * (a + 2.0 * b / 3.0),) * 3
    assert synced_ambient(empty_scene, native) == pytest.approx(expected, rel=1e-3)
    # A world that does not light diffuse surfaces gives none.
    world.cycles_visibility.diffuse = False
    assert synced_ambient(empty_scene, native) == (0.0, 0.0, 0.0)


def test_environment_background_matches_cycles_by_direction(empty_scene, tmp_path, native):
    # Rays that miss see the HDRI through the world's program, as Cycles shows it.
    import math

    import numpy as np
    from whitted_tools.cycles_scenes import render_exr

    if not hasattr(native, "Program"):
        pytest.fail("whitted_native has no Program: rebuild it")
    scene = empty_scene
    world = node_world((1.0, 1.0, 1.0), 1.5)
    tree = world.node_tree
    environment = tree.nodes.new("ShaderNodeTexEnvironment")
    environment.interpolation = "Closest"
    image = bpy.data.images.new("sky", 16, 8, float_buffer=True)
    rng = np.random.default_rng(3)
    texels = rng.uniform(0.05, 1.0, size=(8, 16, 4)).astype(np.float32)
    texels[..., 3] = 1.0
    image.pixels.foreach_set(texels.reshape(-1))
    image.pack()
    environment.image = image
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, 0.7)
    coords = tree.nodes.new("ShaderNodeTexCoord")
    tree.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs[0], environment.inputs["Vector"])
    tree.links.new(environment.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    scene.world = world
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.rotation_euler = (math.radians(80.0), 0.0, math.radians(30.0))
    camera.data.lens = 20.0
    scene.collection.objects.link(camera)
    scene.camera = camera
    render = scene.render
    render.resolution_x, render.resolution_y = 32, 24
    render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.cycles.samples = 1
    scene.cycles.filter_width = 0.01
    scene.cycles.use_denoising = False
    scene.whitted.aa_samples = 1
    cycles = render_exr(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_exr(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    # Closest texels: a pixel whose direction sits on a texel edge may take either.
    differs = (np.abs(whitted - cycles) > 1e-3).any(axis=-1)
    print(f"\nenvironment: {differs.sum()} of {differs.size} pixels differ by > 1e-3")
    assert differs.mean() <= 0.01, f"{differs.sum()} of {differs.size} pixels differ"
    assert np.median(np.abs(whitted - cycles)) < 1e-5
