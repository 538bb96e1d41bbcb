"""The sync with shader programs: a material that starts reading a colour attribute,
a second UV map, a normal map's tangents or Object Info re-exports the meshes (or
re-sets the instances) that carry them, and each edit still renders bit for bit as
a full export (tests/blender/test_sync.py's rule)."""

import bpy
import numpy as np
import pytest
from test_sync import LiveSync, full_export, render


@pytest.fixture
def scene(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    cube = scene.objects["Cube"]
    mesh = cube.data
    paint = mesh.color_attributes.new("Paint", "FLOAT_COLOR", "POINT")
    colors = np.tile(np.float32([0.9, 0.2, 0.1, 1.0]), len(mesh.vertices))
    colors[4::8] = 0.1
    paint.data.foreach_set("color", colors)
    material = bpy.data.materials.new("Programmed")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    mesh.materials.clear()
    mesh.materials.append(material)
    bpy.context.view_layer.update()
    return scene


@pytest.fixture
def live(native, scene):
    if not hasattr(native, "Program"):
        pytest.fail("whitted_native has no Program: rebuild it")
    live = LiveSync(native, scene)
    yield live
    live.close()


def _link(node_type, output, input_name="Base Color", **settings):
    def edit(scene):
        tree = bpy.data.materials["Programmed"].node_tree
        node = tree.nodes.new(node_type)
        for key, value in settings.items():
            setattr(node, key, value)
        tree.links.new(node.outputs[output], tree.nodes["Principled BSDF"].inputs[input_name])

    return edit


def _normal_map(scene):
    tree = bpy.data.materials["Programmed"].node_tree
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.7, 0.5, 0.9, 1.0)
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    tree.links.new(rgb.outputs[0], normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs[0], tree.nodes["Principled BSDF"].inputs["Normal"])


def _unlink_base_color(scene):
    tree = bpy.data.materials["Programmed"].node_tree
    socket = tree.nodes["Principled BSDF"].inputs["Base Color"]
    for link in list(socket.links):
        tree.links.remove(link)


def _displacement_method(method):
    def edit(scene):
        material = bpy.data.materials["Programmed"]
        settings = material if hasattr(material, "displacement_method") else material.cycles
        settings.displacement_method = method
        # Blender 3.4 sends no depsgraph update when a script sets Cycles' property
        # (measured: no handler call); tagged, as a script must for any engine to see it.
        material.update_tag()

    return edit


def _displace(scene):
    # Displacement Only of a Noise Texture: the cube's vertices move.
    tree = bpy.data.materials["Programmed"].node_tree
    noise = tree.nodes.new("ShaderNodeTexNoise")
    displacement = tree.nodes.new("ShaderNodeDisplacement")
    displacement.inputs["Scale"].default_value = 0.5
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(noise.outputs["Fac"], displacement.inputs["Height"])
    tree.links.new(displacement.outputs["Displacement"], output.inputs["Displacement"])
    _displacement_method("DISPLACEMENT")(scene)


def _set_input(node_type, name, value):
    def edit(scene):
        tree = bpy.data.materials["Programmed"].node_tree
        node = next(n for n in tree.nodes if n.bl_idname == node_type)
        node.inputs[name].default_value = value

    return edit


# (name, edit, whether a mesh must be exported again, whether instances are re-set)
EDITS = (
    ("reads a colour attribute", _link("ShaderNodeVertexColor", "Color", layer_name="Paint"), 1),
    ("reads object info", _link("ShaderNodeObjectInfo", "Random", "Roughness"), 0),
    ("normal map tangents", _normal_map, 1),
    ("stops reading the attribute", _unlink_base_color, 1),
    # A displacement that moves vertices: the mesh goes again when it changes (its
    # method, its Scale, its texture), not when the rest of the material does.
    ("displaces the vertices", _displace, 1),
    ("the displacement's scale", _set_input("ShaderNodeDisplacement", "Scale", 0.3), 1),
    ("the noise's scale", _set_input("ShaderNodeTexNoise", "Scale", 2.0), 1),
    (
        "the base colour",
        _set_input("ShaderNodeBsdfPrincipled", "Base Color", (0.2, 0.6, 0.3, 1)),
        0,
    ),
    ("displacement and bump", _displacement_method("BOTH"), 1),
    ("bump only", _displacement_method("BUMP"), 1),
)


def test_program_inputs_follow_the_materials(native, scene, live):
    for name, edit, meshes in EDITS:
        reports = live.edit(lambda edit=edit: edit(scene))
        assert reports, f"{name}: no depsgraph update reached the sync"
        assert sum(r.materials for r in reports) >= 1, f"{name}: {reports}"
        assert sum(r.meshes for r in reports) == meshes, f"{name}: {reports}"
        full = full_export(native, scene)
        synced = render(native, live.sync, scene)
        expected = render(native, full, scene)
        assert np.array_equal(synced, expected), f"after '{name}'"
    # The object info edit re-set the cube's instance with its info.
    instance = live.sync._instances["Cube"]
    assert instance.info is not None and 0.0 <= instance.info[3] <= 1.0
