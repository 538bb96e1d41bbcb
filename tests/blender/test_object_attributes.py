"""The Attribute node's Object, Instancer and View Layer attributes against Cycles,
rendered in the same test: the emission plane of tests/blender/node_cases.py whose
colour is the node's output (one sample at each pixel centre, nothing lit), with the
properties it reads set on the plane, its mesh, the view layer or the scene; then
several objects and a collection instance sharing one material in one render; then the
live sync after a property edit."""

import bpy
import numpy as np
import pytest
from node_cases import NodeCase, build_scene, render, set_cycles
from test_sync import LiveSync
from test_sync import render as render_synced
from whitted.export.material import convert_material
from whitted_tools.cycles_scenes import render_exr
from whitted_tools.material_scenes import plain_film, top_camera

# Constants on both sides (float32 sums and means): Cycles' value within this.
BOUND = 2e-5


def _plane():
    return bpy.data.objects["Plane"]


def _attribute_case(name, kind, attribute, output, setup, expected):
    def build(tree, uv):
        setup()
        node = tree.nodes.new("ShaderNodeAttribute")
        node.attribute_type = kind
        node.attribute_name = attribute
        return node.outputs[output]

    return NodeCase(name, build, "Attribute"), expected


def _set(owner, key, value):
    def setup():
        owner()[key] = value

    return setup


def _both(*setups):
    def setup():
        for one in setups:
            one()

    return setup


def _layer():
    return bpy.context.view_layer


def _scene():
    return bpy.context.scene


def _mesh():
    return _plane().data


def _nothing():
    pass


# (case, the colour Cycles shows: rgb).
CASES = [
    _attribute_case(
        "object_float", "OBJECT", "tint", "Color", _set(_plane, "tint", 0.35), (0.35,) * 3
    ),
    _attribute_case(
        "object_float_alpha", "OBJECT", "tint", "Alpha", _set(_plane, "tint", 0.35), (1.0,) * 3
    ),
    _attribute_case(
        "object_int_fac", "OBJECT", "count", "Fac", _set(_plane, "count", 2), (2.0,) * 3
    ),
    _attribute_case(
        "object_colour_array",
        "OBJECT",
        "paint",
        "Color",
        _set(_plane, "paint", [0.2, 0.6, 0.9]),
        (0.2, 0.6, 0.9),
    ),
    _attribute_case(
        "object_colour_array_fac",
        "OBJECT",
        "paint",
        "Fac",
        _set(_plane, "paint", [0.2, 0.6, 0.9]),
        ((0.2 + 0.6 + 0.9) / 3,) * 3,
    ),
    _attribute_case(
        "object_four_array_alpha",
        "OBJECT",
        "rgba",
        "Alpha",
        _set(_plane, "rgba", [0.1, 0.2, 0.3, 0.4]),
        (0.4,) * 3,
    ),
    _attribute_case(
        "object_int_array", "OBJECT", "ia", "Color", _set(_plane, "ia", [1, 2, 3]), (1.0, 2.0, 3.0)
    ),
    # An RNA boolean: Object Properties > Visibility > Camera, on.
    _attribute_case(
        "object_rna_boolean", "OBJECT", "visible_camera", "Color", _nothing, (1.0,) * 3
    ),
    # The object's RNA property by its path: Object Properties > Viewport Display > Color
    # (node_cases.build_scene sets (0.2, 0.5, 0.7, 1)).
    _attribute_case("object_rna_color", "OBJECT", "color", "Color", _nothing, (0.2, 0.5, 0.7)),
    # Not on the object: its mesh's.
    _attribute_case(
        "object_mesh_property", "OBJECT", "dtint", "Color", _set(_mesh, "dtint", 0.6), (0.6,) * 3
    ),
    # The object's own wins over its mesh's.
    _attribute_case(
        "object_before_mesh",
        "OBJECT",
        "tint",
        "Color",
        _both(_set(_plane, "tint", 0.25), _set(_mesh, "tint", 0.75)),
        (0.25,) * 3,
    ),
    # Nothing has it: (0, 0, 0, 0), the alpha too.
    _attribute_case("object_missing", "OBJECT", "nothing", "Color", _nothing, (0.0,) * 3),
    _attribute_case("object_missing_alpha", "OBJECT", "nothing", "Alpha", _nothing, (0.0,) * 3),
    # Instancer on an object that is no instance: the object's own.
    _attribute_case(
        "instancer_of_an_object",
        "INSTANCER",
        "tint",
        "Color",
        _set(_plane, "tint", 0.45),
        (0.45,) * 3,
    ),
    _attribute_case(
        "view_layer_array",
        "VIEW_LAYER",
        "look",
        "Color",
        _set(_layer, "look", [0.3, 0.1, 0.8]),
        (0.3, 0.1, 0.8),
    ),
    # Not on the view layer: the scene's.
    _attribute_case(
        "view_layer_scene", "VIEW_LAYER", "grade", "Fac", _set(_scene, "grade", 0.45), (0.45,) * 3
    ),
    # The view layer's wins over the scene's.
    _attribute_case(
        "view_layer_before_scene",
        "VIEW_LAYER",
        "grade",
        "Color",
        _both(_set(_layer, "grade", 0.15), _set(_scene, "grade", 0.85)),
        (0.15,) * 3,
    ),
    _attribute_case(
        "view_layer_missing_alpha", "VIEW_LAYER", "nothing", "Alpha", _nothing, (0.0,) * 3
    ),
]


@pytest.mark.parametrize(("case", "expected"), CASES, ids=lambda c: getattr(c, "name", ""))
def test_attribute_reads_as_in_cycles(case, expected, empty_scene, tmp_path):
    material = build_scene(empty_scene, case)
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), case.name)
    whitted = render(empty_scene, "WHITTED", str(tmp_path), case.name)
    warnings = []
    exported = convert_material(material, warnings, view_layer=bpy.context.view_layer)
    assert warnings == []
    if case.name.startswith("view_layer"):
        assert exported.program is None  # folded: a constant of the render
    # The value Cycles reads is the one the case means (the case tests what it says).
    np.testing.assert_allclose(cycles.reshape(-1, 3), [expected] * cycles[..., 0].size, atol=1e-6)
    error = float(np.abs(whitted - cycles).max())
    print(f"\n{case.name}: Cycles {cycles[0, 0]}, max |Whitted - Cycles| = {error:.2e}")
    assert error <= BOUND


# --- several objects and a collection instance in one render -------------------

WIDTH, HEIGHT = 48, 36
# An orthographic camera 6 units wide: 1/8 unit a pixel; the planes' edges (at
# multiples of 1/8) fall between pixel centres, so both renderers see the same pixels.
SCALE = 6.0


def _square(name, half=0.75):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(
        [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)], [], [(0, 1, 2, 3)]
    )
    return mesh


def _shared_material():
    # Emission = Instancer 'itint' + Object 'tint'.
    material = bpy.data.materials.new("Tinted")
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    emission = tree.nodes.new("ShaderNodeEmission")
    add = tree.nodes.new("ShaderNodeVectorMath")
    add.operation = "ADD"
    for socket, kind, name in ((0, "INSTANCER", "itint"), (1, "OBJECT", "tint")):
        node = tree.nodes.new("ShaderNodeAttribute")
        node.attribute_type = kind
        node.attribute_name = name
        tree.links.new(node.outputs["Vector"], add.inputs[socket])
    tree.links.new(add.outputs[0], emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    return material


def _instancing_scene(scene):
    plain_film(scene, WIDTH, HEIGHT)
    top_camera(scene, SCALE)
    material = _shared_material()
    # Two objects sharing the material, each with its own tint.
    for name, x, tint in (("Left", -2.0, (0.8, 0.1, 0.1)), ("Middle", 0.0, (0.1, 0.7, 0.2))):
        obj = bpy.data.objects.new(name, _square(name))
        obj.data.materials.append(material)
        obj.location = (x, 0.0, 0.0)
        obj["tint"] = tint
        scene.collection.objects.link(obj)
    # A collection instance on the right: the instanced square's tint plus its
    # instancer's itint.
    source = bpy.data.collections.new("Source")
    square = bpy.data.objects.new("Instanced", _square("Instanced"))
    square.data.materials.append(material)
    square["tint"] = (0.05, 0.1, 0.4)
    source.objects.link(square)
    empty = bpy.data.objects.new("Instancer", None)
    empty.instance_type = "COLLECTION"
    empty.instance_collection = source
    empty.location = (2.0, 0.0, 0.0)
    empty["itint"] = (0.5, 0.3, 0.0)
    scene.collection.objects.link(empty)
    return {"Left": (0.8, 0.1, 0.1), "Middle": (0.1, 0.7, 0.2), "Right": (0.55, 0.4, 0.4)}


def test_instances_read_their_own_and_their_instancers_values(empty_scene, tmp_path):
    expected = _instancing_scene(empty_scene)
    set_cycles(empty_scene)
    empty_scene.whitted.aa_samples = 1
    cycles = render_exr(empty_scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_exr(empty_scene, "WHITTED", str(tmp_path / "whitted.exr"))
    # The centre pixel of each square is its colour (the background is black).
    for column, name in (
        (WIDTH // 2 - 16, "Left"),
        (WIDTH // 2, "Middle"),
        (WIDTH // 2 + 16, "Right"),
    ):
        np.testing.assert_allclose(cycles[HEIGHT // 2, column], expected[name], atol=1e-6)
    error = float(np.abs(whitted - cycles).max())
    print(f"\ninstances: max |Whitted - Cycles| = {error:.2e} over {WIDTH}x{HEIGHT} pixels")
    assert error <= BOUND


# --- the viewport's sync ---------------------------------------------------------------


def test_a_property_edit_reaches_the_live_scene(native, empty_scene):
    # An object's and an instancer's custom property edited: the instances re-read them.
    expected = _instancing_scene(empty_scene)
    live = LiveSync(native, empty_scene)
    try:
        before = render_synced(native, live.sync, empty_scene)
        left = bpy.data.objects["Left"]

        def retint():
            left["tint"] = (0.2, 0.3, 0.9)
            left.update_tag()  # what the properties editor's edit does

        live.edit(retint)
        after = render_synced(native, live.sync, empty_scene)

        def regrade():
            bpy.data.objects["Instancer"]["itint"] = (0.0, 0.0, 0.0)
            bpy.data.objects["Instancer"].update_tag()

        live.edit(regrade)
        last = render_synced(native, live.sync, empty_scene)
    finally:
        live.close()
    rows, columns = before.shape[:2]
    y = rows // 2
    # The centres of the left and right squares (x = -2 and 2 of the camera's 6 units).
    left_x, right_x = columns // 2 - columns // 3, columns // 2 + columns // 3
    np.testing.assert_allclose(before[y, left_x, :3], expected["Left"], atol=1e-6)
    np.testing.assert_allclose(after[y, left_x, :3], (0.2, 0.3, 0.9), atol=1e-6)
    np.testing.assert_allclose(after[y, right_x, :3], expected["Right"], atol=1e-6)
    np.testing.assert_allclose(last[y, right_x, :3], (0.05, 0.1, 0.4), atol=1e-6)


def test_a_view_layer_property_edit_exports_the_material_again(native, empty_scene):
    # The scene's 'grade', read by the Fac of a View Layer attribute, edited: the
    # material, which folded it, is exported again.
    case = next(c for c, _ in CASES if c.name == "view_layer_scene")
    build_scene(empty_scene, case)
    live = LiveSync(native, empty_scene)
    try:
        before = render_synced(native, live.sync, empty_scene)

        def regrade():
            empty_scene["grade"] = 0.7
            empty_scene.update_tag()  # what the properties editor's edit does

        reports = live.edit(regrade)
        after = render_synced(native, live.sync, empty_scene)
    finally:
        live.close()
    assert sum(r.materials for r in reports) == 1
    centre = tuple(n // 2 for n in before.shape[:2])
    np.testing.assert_allclose(before[centre][:3], (0.45,) * 3, atol=1e-6)
    np.testing.assert_allclose(after[centre][:3], (0.7,) * 3, atol=1e-6)
