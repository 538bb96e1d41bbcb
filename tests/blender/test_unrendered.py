"""Nothing vanishes silently (issue 31, part 4): what Cycles renders and Whitted does not
(Volume objects, a material's or the world's Volume output) is named in the report, with
the object, what it is, and why (export/unrendered.py)."""

import bpy
import pytest
from whitted.export.instance import is_shadow_catcher
from whitted.sync.frame import sync_frame
from whitted_tools.scenes import add_object, cube_mesh


@pytest.fixture
def stage(empty_scene):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera
    camera.location = (0.0, -6.0, 0.0)
    camera.rotation_euler = (1.5708, 0.0, 0.0)
    empty_scene.render.resolution_x = empty_scene.render.resolution_y = 16
    return empty_scene


def _warnings(native):
    return sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings


def _hair(scene, name):
    emitter = add_object(scene.collection, name, cube_mesh(name, 1.0))
    modifier = emitter.modifiers.new("Fur", "PARTICLE_SYSTEM")
    settings = modifier.particle_system.settings
    settings.type = "HAIR"
    settings.count = 20
    return emitter


def test_volumes_are_named_and_what_renders_is_not(stage, native):
    # Hair curves, point clouds and particle hair render (tests/blender/test_hair.py):
    # only the volume is named (tests/blender/test_volume_object.py: what is read of one
    # with grids).
    add_object(stage.collection, "Strands", bpy.data.hair_curves.new("Strands"))
    add_object(stage.collection, "Dust", bpy.data.pointclouds.new("Dust"))
    add_object(stage.collection, "Smoke", bpy.data.volumes.new("Smoke"))
    _hair(stage, "Furry")
    add_object(stage.collection, "Plain", cube_mesh("Plain", 1.0))
    warnings = _warnings(native)
    lines = [w for w in warnings if "not rendered" in w or "Volume object" in w]
    assert lines == [
        "Whitted: Volume object 'Smoke' skipped: it has no grids (no OpenVDB file, no modifier)"
    ], warnings


def test_hidden_objects_are_not_listed(stage, native):
    hidden = add_object(stage.collection, "Hidden Smoke", bpy.data.volumes.new("Hidden Smoke"))
    hidden.hide_render = True
    warnings = _warnings(native)
    assert not any("not rendered" in w or "Volume object" in w for w in warnings)


def test_a_volume_shader_is_named(stage, native):
    material = bpy.data.materials.new("Fog")
    if bpy.app.version < (5, 0, 0):  # node trees by default from 5.0 on
        material.use_nodes = True
    nodes = material.node_tree.nodes
    # A surface shader in the Volume socket is no volume shader rendered (fire and a
    # texture on the density are: tests/blender/test_volume.py).
    volume = nodes.new("ShaderNodeBsdfDiffuse")
    output = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    material.node_tree.links.new(volume.outputs[0], output.inputs["Volume"])
    cube = add_object(stage.collection, "Box", cube_mesh("Box", 1.0))
    cube.data.materials.append(material)
    world = bpy.data.worlds.new("Hazy")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world_output = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    # A world's volume of constant inputs renders (test_volume.py); one a texture drives
    # does not.
    haze = world.node_tree.nodes.new("ShaderNodeVolumePrincipled")
    noise = world.node_tree.nodes.new("ShaderNodeTexNoise")
    world.node_tree.links.new(noise.outputs["Fac"], haze.inputs["Density"])
    world.node_tree.links.new(haze.outputs[0], world_output.inputs["Volume"])
    stage.world = world
    warnings = _warnings(native)
    assert any("material 'Fog' has a volume shader, which is not rendered" in w for w in warnings)
    assert any("world 'Hazy' has a volume shader" in w for w in warnings)


def test_shadow_catchers_are_read_on_geometry_and_not_warned(stage, native):
    # A shadow catcher renders as Cycles' (tests/blender/test_shadow_catcher.py): no
    # report line says otherwise. The flag counts on geometry only: Blender 3.4 sets it
    # on every new lamp, and a lamp or a camera set so is no shadow catcher (issue 49).
    catcher = add_object(stage.collection, "Ground", cube_mesh("Ground", 1.0))
    catcher.is_shadow_catcher = True
    add_object(stage.collection, "Plain", cube_mesh("Plain", 1.0))
    for kind in ("POINT", "SUN", "AREA"):
        lamp = add_object(stage.collection, f"Lamp {kind}", bpy.data.lights.new(kind, kind))
        lamp.is_shadow_catcher = True
    camera = add_object(stage.collection, "Camera", bpy.data.cameras.new("Camera"))
    camera.is_shadow_catcher = True
    warnings = _warnings(native)
    assert not [w for w in warnings if "catcher" in w], warnings
    depsgraph = bpy.context.evaluated_depsgraph_get()
    catchers = {i.object.original.name for i in depsgraph.object_instances if is_shadow_catcher(i)}
    assert catchers == {"Ground"}
