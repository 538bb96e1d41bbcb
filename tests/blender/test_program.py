"""Lowering to shader programs (export/nodes/program.py) against the contract
(docs/notes/shader_program.md), checked on the emitted arrays without rendering:
which fields get outputs, constant folding, op and mode numbers, what the program
reads from the mesh and the instance; and each program run by the native program on
one hit against values computed here from Blender's definitions."""

import math

import bpy
import numpy as np
import pytest
from exported import exported_meshes, run_program
from whitted.export.instance import object_info
from whitted.export.material import convert_material
from whitted.export.mesh_layers import MeshNeeds
from whitted.export.nodes import ops
from whitted_tools.shader_graphs import new_material, output, principled

UV = (0.25, 0.75, 0.0, 0.0)


def compile_material(material, warnings=None):
    exported = convert_material(material, [] if warnings is None else warnings)
    return exported


def emission_of(build):
    """A material whose surface is an Emission of strength 1 whose Color is what
    `build(tree)` returns (an output socket)."""
    material = new_material("Node")
    tree = material.node_tree
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(build(tree), emission.inputs["Color"])
    tree.links.new(emission.outputs[0], output(material).inputs["Surface"])
    return material


def ops_of(program):
    return [int(row[0]) for row in program.code]


def run_field(exported, field, inputs):
    registers = run_program(exported.program, inputs)
    return registers[dict(exported.outputs)[field]]


def uv_inputs(uv=UV, **extra):
    return {ops.IN_UV: uv, **extra}


def test_constant_graph_has_no_program(warnings):
    material = emission_of(lambda tree: _math_chain(tree, None))
    exported = compile_material(material, warnings)
    assert exported.program is None
    assert exported.data.emission == pytest.approx((0.5 * 0.5 + 0.25,) * 3)


def _math_chain(tree, source):
    multiply = tree.nodes.new("ShaderNodeMath")
    multiply.operation = "MULTIPLY_ADD"
    multiply.inputs[0].default_value = 0.5
    multiply.inputs[1].default_value = 0.5
    multiply.inputs[2].default_value = 0.25
    if source is not None:
        tree.links.new(source, multiply.inputs[0])
    return multiply.outputs[0]


def test_only_varying_fields_get_outputs_and_constants_fold(warnings):
    def build(tree):
        uv = tree.nodes.new("ShaderNodeTexCoord")
        separate = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(uv.outputs["UV"], separate.inputs[0])
        return _math_chain(tree, separate.outputs["X"])

    exported = compile_material(emission_of(build), warnings)
    assert dict(exported.outputs).keys() == {"emission"}
    # INPUT uv, SWIZZLE x, MATH multiply-add: the constants are registers.
    assert ops_of(exported.program) == [ops.INPUT, ops.SWIZZLE, ops.MATH]
    row = exported.program.code[2]
    assert row[1] == ops.pack("MATH", operation="MULTIPLY_ADD")
    assert exported.uv_maps == ("",)
    value = run_field(exported, "emission", uv_inputs())
    assert value[0] == pytest.approx(0.25 * 0.5 + 0.25)
    assert warnings == []


def test_code_rows_follow_the_contract():
    def build(tree):
        image = tree.nodes.new("ShaderNodeTexImage")
        image.image = bpy.data.images.new("tex", 2, 2)
        image.projection = "BOX"
        image.projection_blend = 0.25
        return image.outputs["Color"]

    exported = compile_material(emission_of(build))
    program = exported.program
    assert program.code.dtype == np.uint32 and program.code.shape[1] == 8
    assert program.registers.dtype == np.float32 and program.registers.shape[1] == 4
    (image_row,) = [row for row in program.code if row[0] == ops.IMAGE]
    _op, mode, out, _a, b, c, d, e = (int(x) for x in image_row)
    assert mode == ops.pack("IMAGE", projection="BOX")
    assert program.registers[b][0] == pytest.approx(0.25)  # box blend, a constant register
    assert (c, d) == (ops.UNUSED, ops.UNUSED)
    assert program.textures[e] == exported.textures[0].name
    assert exported.textures[0].image.name == "tex"
    assert dict(exported.outputs)["emission"] == out


def test_varying_principled_emits_the_mapping_formulas():
    # A Base Color read from a colour attribute, metallic 0.5: diffuse and reflectivity
    # vary (the specular highlight is the dielectric part's, constant, in the Blender
    # local model).
    material = new_material("Painted metal")
    tree = material.node_tree
    bsdf = principled(material)
    bsdf.inputs["Metallic"].default_value = 0.5
    bsdf.inputs["Roughness"].default_value = 0.1
    attribute = tree.nodes.new("ShaderNodeAttribute")
    attribute.attribute_name = "paint"
    tree.links.new(attribute.outputs["Color"], bsdf.inputs["Base Color"])
    exported = compile_material(material)
    outputs = dict(exported.outputs)
    assert {"diffuse", "reflectivity"} <= outputs.keys()
    assert "shininess" not in outputs  # roughness constant: folded
    assert "roughness" not in outputs
    base = (0.2, 0.4, 0.6, 1.0)
    registers = run_program(exported.program, {ops.IN_ATTRIBUTE: base})
    # The constant mapping of the same base colour gives the same numbers.
    constant = new_material("Constant metal")
    constant_bsdf = principled(constant)
    constant_bsdf.inputs["Metallic"].default_value = 0.5
    constant_bsdf.inputs["Roughness"].default_value = 0.1
    constant_bsdf.inputs["Base Color"].default_value = base
    expected = convert_material(constant, []).data
    for field in ("diffuse", "specular", "reflectivity"):
        got = registers[outputs[field]][:3] if field in outputs else getattr(exported.data, field)
        assert tuple(got) == pytest.approx(getattr(expected, field), rel=1e-6)
    assert exported.data.roughness == pytest.approx(0.1)


def test_graph_driven_roughness_of_a_metal_gives_a_roughness_output():
    material = new_material("Rough metal map")
    tree = material.node_tree
    uv = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(uv.outputs["UV"], separate.inputs[0])
    bsdf = principled(material)
    bsdf.inputs["Metallic"].default_value = 1.0
    tree.links.new(separate.outputs["X"], bsdf.inputs["Roughness"])
    exported = compile_material(material)
    output = dict(exported.outputs)["roughness"]
    for roughness in (0.0, 0.3, 1.0):
        registers = run_program(exported.program, uv_inputs((roughness, 0.0, 0.0, 0.0)))
        assert registers[output][0] == pytest.approx(roughness)


def test_graph_driven_roughness_gives_a_shininess_output():
    material = new_material("Rough map")
    tree = material.node_tree
    uv = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(uv.outputs["UV"], separate.inputs[0])
    tree.links.new(separate.outputs["X"], principled(material).inputs["Roughness"])
    exported = compile_material(material)
    shininess = dict(exported.outputs)["shininess"]
    for roughness in (0.0, 0.05, 0.3, 1.0):
        registers = run_program(exported.program, uv_inputs((roughness, 0.0, 0.0, 0.0)))
        constant = new_material("c")
        principled(constant).inputs["Roughness"].default_value = roughness
        expected = convert_material(constant, []).data.shininess
        assert registers[shininess][0] == pytest.approx(expected, rel=1e-4)


MATH_CASES = [
    ("ADD", 0.3, 0.5, 0.0, 0.8),
    ("POWER", -2.0, 0.5, 0.0, 0.0),  # Cycles' safe power
    ("DIVIDE", 1.0, 0.0, 0.0, 0.0),  # safe divide
    ("WRAP", 1.3, 1.0, 0.0, 0.3),
    ("PINGPONG", 1.3, 1.0, 0.0, 0.7),
    ("SMOOTH_MIN", 0.3, 0.4, 0.2, 0.3 - (0.1 / 0.2) ** 3 * 0.2 / 6.0),
    ("COMPARE", 0.3, 0.3000001, 0.0, 1.0),
    ("ARCTAN2", 1.0, -1.0, 0.0, math.atan2(1.0, -1.0)),
]


@pytest.mark.parametrize(("operation", "a", "b", "c", "expected"), MATH_CASES)
def test_math_node_on_a_varying_input(operation, a, b, c, expected):
    def build(tree):
        uv = tree.nodes.new("ShaderNodeTexCoord")
        separate = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(uv.outputs["UV"], separate.inputs[0])
        node = tree.nodes.new("ShaderNodeMath")
        node.operation = operation
        node.inputs[1].default_value = b
        node.inputs[2].default_value = c
        tree.links.new(separate.outputs["X"], node.inputs[0])
        return node.outputs[0]

    exported = compile_material(emission_of(build))
    (row,) = [r for r in exported.program.code if r[0] == ops.MATH]
    assert int(row[1]) == ops.pack("MATH", operation=operation)
    value = run_field(exported, "emission", uv_inputs((a, 0.0, 0.0, 0.0)))
    assert value[0] == pytest.approx(expected, abs=1e-6)


@pytest.mark.parametrize("blend", ["MIX", "MULTIPLY", "SCREEN", "OVERLAY", "HUE", "SOFT_LIGHT"])
def test_mix_rgb_blend_modes_are_numbered_by_identifier(blend):
    def build(tree):
        coords = tree.nodes.new("ShaderNodeTexCoord")
        mix = tree.nodes.new("ShaderNodeMixRGB")
        mix.blend_type = blend
        mix.use_clamp = True
        mix.inputs["Color2"].default_value = (0.9, 0.2, 0.4, 1.0)
        tree.links.new(coords.outputs["UV"], mix.inputs["Color1"])
        return mix.outputs[0]

    exported = compile_material(emission_of(build))
    (row,) = [r for r in exported.program.code if r[0] == ops.MIX]
    assert int(row[1]) == ops.pack("MIX", blend_type=blend, clamp=True)


def test_color_ramp_table_and_value():
    def build(tree):
        coords = tree.nodes.new("ShaderNodeTexCoord")
        separate = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(coords.outputs["UV"], separate.inputs[0])
        ramp = tree.nodes.new("ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].color = (1.0, 0.0, 0.0, 1.0)
        ramp.color_ramp.elements.new(0.5).color = (0.0, 1.0, 0.0, 1.0)
        tree.links.new(separate.outputs["X"], ramp.inputs[0])
        return ramp.outputs["Color"]

    material = emission_of(build)
    exported = compile_material(material)
    (row,) = [r for r in exported.program.code if r[0] == ops.COLOR_RAMP]
    offset = int(row[7])
    constants = exported.program.constants
    assert constants[offset] == 3.0
    ramp = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeValToRGB")
    for t in (0.1, 0.5, 0.8):
        value = run_field(exported, "emission", uv_inputs((t, 0.0, 0.0, 0.0)))
        assert value[:3] == pytest.approx(tuple(ramp.color_ramp.evaluate(t))[:3], abs=1e-6)


def test_rgb_curves_are_sampled_with_the_curves_own_evaluate():
    def build(tree):
        coords = tree.nodes.new("ShaderNodeTexCoord")
        curves = tree.nodes.new("ShaderNodeRGBCurve")
        points = curves.mapping.curves[3].points
        points[0].location = (0.0, 0.2)
        points.new(0.5, 0.9)
        curves.mapping.update()
        tree.links.new(coords.outputs["UV"], curves.inputs["Color"])
        return curves.outputs[0]

    material = emission_of(build)
    exported = compile_material(material)
    (row,) = [r for r in exported.program.code if r[0] == ops.CURVE]
    table = exported.program.constants[int(row[7]) : int(row[7]) + 4 * 256]
    node = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeRGBCurve")
    mapping = node.mapping
    for i in (0, 64, 128, 255):
        assert table[i] == pytest.approx(mapping.evaluate(mapping.curves[3], i / 255.0), abs=1e-6)
    value = run_field(exported, "emission", uv_inputs((0.5, 0.25, 0.0, 0.0)))
    combined = mapping.evaluate(mapping.curves[0], mapping.evaluate(mapping.curves[3], 0.5))
    assert value[0] == pytest.approx(combined, abs=2e-3)


def test_modes_read_back_as_the_nodes_settings():
    # Mix (vector, non-uniform), Layer Weight's Facing and an inverted Bump: their modes
    # are packed by name (ops.pack), and each reads back as the node's setting.
    material = new_material("Modes")
    tree = material.node_tree
    bsdf = principled(material)
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    weight = tree.nodes.new("ShaderNodeLayerWeight")
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type, mix.factor_mode = "VECTOR", "NON_UNIFORM"
    tree.links.new(coordinates.outputs["UV"], mix.inputs[1])  # Factor_Vector
    tree.links.new(weight.outputs["Facing"], mix.inputs[5])  # B_Vector
    tree.links.new(mix.outputs[1], bsdf.inputs["Base Color"])
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coordinates.outputs["UV"], separate.inputs[0])
    bump = tree.nodes.new("ShaderNodeBump")
    bump.invert = True
    tree.links.new(separate.outputs["X"], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    code = compile_material(material).program.code

    def modes(op):
        return [ops.unpack(op, int(row[1])) for row in code if row[0] == getattr(ops, op)]

    assert {"factor_mode": "NON_UNIFORM"} in modes("MIX_VALUE")
    assert modes("LAYER_WEIGHT") == [{"output": "FACING"}]
    assert modes("BUMP") == [{"invert": True}]


def test_inputs_the_program_reads_are_recorded():
    material = new_material("Reads")
    tree = material.node_tree
    bsdf = principled(material)
    color = tree.nodes.new("ShaderNodeVertexColor")
    color.layer_name = "Paint"
    tree.links.new(color.outputs["Color"], bsdf.inputs["Base Color"])
    info = tree.nodes.new("ShaderNodeObjectInfo")
    tree.links.new(info.outputs["Random"], bsdf.inputs["Roughness"])
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    normal_map.uv_map = "Detail"
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("normals", 2, 2)
    tree.links.new(image.outputs["Color"], normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    exported = compile_material(material)
    assert exported.attributes == (("COLOR", "Paint"),)
    assert exported.object_info
    assert exported.uv_maps == ("", "Detail")  # the image reads the active map
    assert exported.tangents == (1,)
    outputs = dict(exported.outputs)
    assert "normal" in outputs
    (row,) = [r for r in exported.program.code if r[0] == ops.NORMAL_MAP]
    assert int(row[1]) == ops.pack("NORMAL_MAP", space="TANGENT")
    assert int(row[7]) == 1
    modes = {int(r[1]) for r in exported.program.code if r[0] == ops.INPUT}
    assert {ops.IN_ATTRIBUTE + 0, ops.IN_OBJECT_RANDOM, ops.IN_UV + 0} <= modes
    # The diffuse lobe under the mapped normal fades as this Blender's Cycles fades it.
    if bpy.app.version < (4, 0, 0):
        assert exported.data.bump_shadowing == "CHIANG"
    else:
        assert exported.data.bump_shadowing == "MICROFACET"
        material.cycles.use_bump_map_correction = False
        assert compile_material(material).data.bump_shadowing == "SMOOTH_SIDE"


def test_an_unsupported_node_warns_and_its_input_uses_the_unlinked_value(warnings):
    def build(tree):
        particle = tree.nodes.new("ShaderNodeParticleInfo")
        return particle.outputs["Location"]

    exported = compile_material(emission_of(build), warnings)
    assert exported.program is None
    assert exported.data.emission == pytest.approx((1.0, 1.0, 1.0))  # Emission's own colour
    assert "ShaderNodeParticleInfo is not supported" in warnings[0]


def mesh_with_data():
    """A plane with two UV maps, a corner colour attribute and a point float."""
    bpy.ops.mesh.primitive_plane_add(size=2.0)
    plane = bpy.context.active_object
    mesh = plane.data
    second = mesh.uv_layers.new(name="Detail")
    uvs = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    mesh.uv_layers[0].data.foreach_get("uv", uvs)
    second.data.foreach_set("uv", 1.0 - uvs)
    paint = mesh.color_attributes.new("Paint", "FLOAT_COLOR", "CORNER")
    colors = np.tile(np.float32([0.1, 0.2, 0.3, 0.5]), len(mesh.loops))
    paint.data.foreach_set("color", colors)
    height = mesh.attributes.new("height", "FLOAT", "POINT")
    height.data.foreach_set("value", np.arange(len(mesh.vertices), dtype=np.float32))
    material = new_material("Needs")
    mesh.materials.append(material)
    return plane, material


def test_meshes_carry_what_the_programs_read(warnings):
    _plane, material = mesh_with_data()
    needs = {
        material.name: MeshNeeds(
            uv_sets=("", "Detail"),
            attributes=(("COLOR", "Paint"), ("ATTRIBUTE", "height")),
            tangents=True,
        )
    }
    depsgraph = bpy.context.evaluated_depsgraph_get()
    (mesh,) = exported_meshes(depsgraph, warnings, needs=needs).meshes
    assert len(mesh.uv_sets) == 2 and mesh.uv_sets[0].shape == (2, 3, 2)
    np.testing.assert_allclose(mesh.uv_sets[1], 1.0 - mesh.uv_sets[0])
    paint, height = mesh.attributes
    np.testing.assert_allclose(paint, np.broadcast_to((0.1, 0.2, 0.3, 0.5), (2, 3, 4)), rtol=1e-6)
    # A float attribute in all of rgb (alpha 1), by each corner's vertex.
    corners = mesh.triangles
    np.testing.assert_array_equal(height[..., 0], corners.astype(np.float32))
    np.testing.assert_array_equal(height[..., 1], height[..., 0])
    assert len(mesh.tangents) == 2
    tangent = mesh.tangents[0]
    assert tangent.shape == (2, 3, 4)
    # The default plane's U runs along +X: tangent (1, 0, 0), bitangent sign +1.
    np.testing.assert_allclose(tangent[..., :3], np.broadcast_to((1, 0, 0), (2, 3, 3)), atol=1e-6)
    np.testing.assert_allclose(tangent[..., 3], 1.0)
    assert warnings == []
    # Without needs, none of it.
    (bare,) = exported_meshes(depsgraph, []).meshes
    assert (bare.uv_sets, bare.attributes, bare.tangents) == ((), (), ())


def test_missing_attribute_reads_zero_and_warns(warnings):
    _plane, material = mesh_with_data()
    needs = {material.name: MeshNeeds(attributes=(("ATTRIBUTE", "nowhere"),))}
    depsgraph = bpy.context.evaluated_depsgraph_get()
    (mesh,) = exported_meshes(depsgraph, warnings, needs=needs).meshes
    np.testing.assert_array_equal(mesh.attributes[0], 0.0)
    assert "no attribute 'nowhere'" in warnings[0]


def test_object_info_of_an_instance(warnings):
    plane, material = mesh_with_data()
    plane.location = (1.0, 2.0, 3.0)
    plane.pass_index = 7
    plane.color = (0.5, 0.25, 0.125, 1.0)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    export = exported_meshes(depsgraph, warnings, info={material.name})
    (instance,) = export.instances
    location, random, index, color = (
        instance.info[:3],
        instance.info[3],
        instance.info[4],
        instance.info[5:],
    )
    assert location == pytest.approx((1.0, 2.0, 3.0))
    assert 0.0 <= random <= 1.0
    assert index == 7.0
    assert color == pytest.approx((0.5, 0.25, 0.125, 1.0))
    # Read by no material, it is sent only for a pass index (the IndexOB pass).
    (indexed,) = exported_meshes(depsgraph, warnings).instances
    assert indexed.info[4] == 7.0
    plane.pass_index = 0
    depsgraph = bpy.context.evaluated_depsgraph_get()
    (bare,) = exported_meshes(depsgraph, warnings).instances
    assert bare.info is None
    # The same object gives the same random number every time.
    for again in depsgraph.object_instances:  # valid only while iterating
        if again.object.name == plane.name:
            assert object_info(again)[3] == random
