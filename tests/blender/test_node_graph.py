"""Node graphs as Blender evaluates them (export/nodes/graph.py, shaders.py): node
groups inlined (nested, with their defaults), reroutes, muted nodes, the active
output, Add and Mix Shader trees, constant folding, and the fallbacks."""

import bpy
import pytest
from whitted.export.material import convert_material
from whitted_tools.shader_graphs import (
    first_input,
    gltf_wrapper_material,
    group_node,
    new_group,
    new_material,
    output,
    principled,
)


def convert(material, warnings):
    return convert_material(material, warnings)


def test_textured_material_inside_a_group_is_a_diffuse_texture(warnings):
    image = bpy.data.images.new("albedo", 4, 4)
    material, _, _texture = gltf_wrapper_material("Imported", image)
    exported = convert(material, warnings)
    (spec,) = exported.textures
    assert spec.image == image
    assert exported.data.diffuse_texture == spec.name
    assert exported.data.diffuse == pytest.approx((1.0, 1.0, 1.0))
    # Roughness 0.25 from the group node's input: alpha 0.0625 -> (2 / 0.0039 - 2) / 4.
    assert exported.data.shininess == pytest.approx((2.0 / 0.0625**2 - 2.0) / 4.0, rel=1e-5)
    assert warnings == []


def test_group_input_left_unlinked_takes_the_group_nodes_value(warnings):
    tree, group_in, group_out = new_group(
        "Tint",
        inputs=[("Color", "NodeSocketColor", (0.9, 0.9, 0.9, 1.0))],
        outputs=[("Color", "NodeSocketColor")],
    )
    tree.links.new(group_in.outputs["Color"], group_out.inputs["Color"])
    material = new_material("Grouped")
    group = group_node(material, tree)
    group.inputs["Color"].default_value = (0.2, 0.4, 0.6, 1.0)
    material.node_tree.links.new(group.outputs["Color"], principled(material).inputs["Base Color"])
    assert convert(material, warnings).data.diffuse == pytest.approx((0.2, 0.4, 0.6))


def test_groups_nested_three_deep_with_reroutes_and_maths_fold(warnings):
    # Innermost: Value * 0.5; each level passes it on through a reroute.
    inner, inner_in, inner_out = new_group(
        "Inner", inputs=[("Value", "NodeSocketFloat", 0.0)], outputs=[("Value", "NodeSocketFloat")]
    )
    math = inner.nodes.new("ShaderNodeMath")
    math.operation = "MULTIPLY"
    math.inputs[1].default_value = 0.5
    inner.links.new(inner_in.outputs["Value"], math.inputs[0])
    inner.links.new(math.outputs[0], inner_out.inputs["Value"])
    trees = [inner]
    for level in ("Middle", "Outer"):
        tree, tree_in, tree_out = new_group(
            level,
            inputs=[("Value", "NodeSocketFloat", 0.0)],
            outputs=[("Value", "NodeSocketFloat")],
        )
        node = tree.nodes.new("ShaderNodeGroup")
        node.node_tree = trees[-1]
        reroute = tree.nodes.new("NodeReroute")
        tree.links.new(tree_in.outputs["Value"], reroute.inputs[0])
        tree.links.new(reroute.outputs[0], node.inputs["Value"])
        tree.links.new(node.outputs["Value"], tree_out.inputs["Value"])
        trees.append(tree)
    material = new_material("Deep")
    outer = group_node(material, trees[-1])
    outer.inputs["Value"].default_value = 0.8  # -> metallic 0.4
    material.node_tree.links.new(outer.outputs["Value"], principled(material).inputs["Metallic"])
    principled(material).inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    data = convert(material, warnings).data
    assert data.diffuse == pytest.approx((0.6, 0.6, 0.6))
    assert warnings == []


def test_muted_node_passes_its_input_through(warnings):
    material = new_material("Muted")
    tree = material.node_tree
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.3, 0.2, 0.1, 1.0)
    invert = tree.nodes.new("ShaderNodeInvert")
    invert.mute = True
    tree.links.new(rgb.outputs[0], invert.inputs["Color"])
    tree.links.new(invert.outputs[0], principled(material).inputs["Base Color"])
    assert convert(material, warnings).data.diffuse == pytest.approx((0.3, 0.2, 0.1))
    invert.mute = False
    assert convert(material, warnings).data.diffuse == pytest.approx((0.7, 0.8, 0.9))


def test_muted_link_uses_the_socket_value(warnings):
    material = new_material("Cut")
    tree = material.node_tree
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.3, 0.2, 0.1, 1.0)
    bsdf = principled(material)
    bsdf.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    link = tree.links.new(rgb.outputs[0], bsdf.inputs["Base Color"])
    link.is_muted = True
    assert convert(material, warnings).data.diffuse == pytest.approx((0.5, 0.5, 0.5))


def test_the_output_cycles_renders_is_used(warnings):
    material = new_material("Two outputs")
    tree = material.node_tree
    eevee = output(material)
    eevee.target = "EEVEE"
    cycles = tree.nodes.new("ShaderNodeOutputMaterial")
    cycles.target = "CYCLES"
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (0.0, 1.0, 0.0, 1.0)
    tree.links.new(emission.outputs[0], cycles.inputs["Surface"])
    assert convert(material, warnings).data.emission == pytest.approx((0.0, 1.0, 0.0))


def test_principled_plus_emission_through_add_shader(warnings):
    material = new_material("Glowing")
    tree = material.node_tree
    bsdf = principled(material)
    bsdf.inputs["Base Color"].default_value = (0.5, 0.25, 0.125, 1.0)
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1.0, 0.5, 0.0, 1.0)
    emission.inputs["Strength"].default_value = 3.0
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(bsdf.outputs[0], add.inputs[0])
    tree.links.new(emission.outputs[0], add.inputs[1])
    tree.links.new(add.outputs[0], output(material).inputs["Surface"])
    data = convert(material, warnings).data
    alone = convert(bsdf_only(bsdf), []).data
    assert data.diffuse == pytest.approx((0.5, 0.25, 0.125))
    assert data.specular == pytest.approx(alone.specular)
    assert data.shininess == pytest.approx(alone.shininess)  # Emission has no highlight
    assert data.emission == pytest.approx((3.0, 1.5, 0.0))
    assert data.alpha == 1.0
    assert warnings == []


def bsdf_only(bsdf):
    """A material of a Principled BSDF with the same inputs as `bsdf`."""
    material = new_material("Alone")
    target = principled(material)
    for socket in bsdf.inputs:
        if hasattr(socket, "default_value") and socket.name in target.inputs:
            target.inputs[socket.identifier].default_value = socket.default_value
    return material


def test_principled_mixed_with_velvet_or_sheen(warnings):
    material = new_material("Cloth")
    tree = material.node_tree
    bsdf = principled(material)
    bsdf.inputs["Base Color"].default_value = (0.8, 0.2, 0.2, 1.0)
    kind = "ShaderNodeBsdfVelvet" if bpy.app.version < (4, 0, 0) else "ShaderNodeBsdfSheen"
    velvet = tree.nodes.new(kind)
    velvet.inputs["Color"].default_value = (0.2, 0.2, 0.8, 1.0)
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = 0.5
    tree.links.new(bsdf.outputs[0], mix.inputs[1])
    tree.links.new(velvet.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], output(material).inputs["Surface"])
    data = convert(material, warnings).data
    # Each lobe keeps its shape: the Principled's diffuse (3.x: Burley's) and the velvet's
    # sheen (Ashikhmin's; 4.x's Sheen defaults to Microfiber, approximated by it, warned),
    # each weighted by the mix.
    assert data.diffuse == pytest.approx((0.4, 0.1, 0.1))
    assert data.sheen == pytest.approx((0.1, 0.1, 0.4))
    assert data.sheen_roughness == pytest.approx(velvet.inputs[1].default_value)
    assert data.diffuse_model == ("BURLEY" if bpy.app.version < (4, 0, 0) else "LAMBERT")
    if bpy.app.version < (4, 0, 0):
        assert warnings == []
    else:
        assert len(warnings) == 1 and "Microfiber" in warnings[0]
        assert f"'{velvet.name}'" in warnings[0]


def test_mix_factor_driven_by_a_graph_folds(warnings):
    material = new_material("Driven")
    tree = material.node_tree
    value = tree.nodes.new("ShaderNodeValue")
    value.outputs[0].default_value = 0.5
    ramp = tree.nodes.new("ShaderNodeValToRGB")  # black -> white, linear
    tree.links.new(value.outputs[0], ramp.inputs[0])
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (1.0, 0.0, 0.0, 1.0)
    glow = tree.nodes.new("ShaderNodeEmission")
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(ramp.outputs["Color"], mix.inputs[0])
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(glow.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], output(material).inputs["Surface"])
    data = convert(material, warnings).data
    # Colour -> float is the colour's luminance: grey 0.5 -> 0.5.
    assert data.diffuse == pytest.approx((0.5, 0.0, 0.0))
    assert data.emission == pytest.approx((0.5, 0.5, 0.5))
    assert warnings == []


def test_add_and_mix_trees_of_any_depth(warnings):
    material = new_material("Deep tree")
    tree = material.node_tree
    shaders = []
    for k in range(4):
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        emission.inputs["Strength"].default_value = float(k + 1)
        shaders.append(emission)
    add_low = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(shaders[0].outputs[0], add_low.inputs[0])
    tree.links.new(shaders[1].outputs[0], add_low.inputs[1])
    add_high = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(shaders[2].outputs[0], add_high.inputs[0])
    tree.links.new(shaders[3].outputs[0], add_high.inputs[1])
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = 0.25
    tree.links.new(add_low.outputs[0], mix.inputs[1])
    tree.links.new(add_high.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], output(material).inputs["Surface"])
    # 0.75 * (1 + 2) + 0.25 * (3 + 4)
    assert convert(material, warnings).data.emission == pytest.approx((4.0, 4.0, 4.0))


def test_unsupported_node_warns_once_by_name(warnings):
    material = new_material("Procedural")
    tree = material.node_tree
    bsdf = principled(material)
    bsdf.inputs["Base Color"].default_value = (0.1, 0.2, 0.3, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.4
    wave = tree.nodes.new("ShaderNodeParticleInfo")  # a node the program lacks
    wave.name = "Ripples"
    tree.links.new(wave.outputs["Velocity"], bsdf.inputs["Base Color"])
    tree.links.new(wave.outputs["Random"], bsdf.inputs["Roughness"])
    data = convert(material, warnings).data
    assert data.diffuse == pytest.approx((0.1, 0.2, 0.3))
    # One warning per node and input it feeds, naming both.
    assert len(warnings) == 2
    assert all("node 'Ripples': ShaderNodeParticleInfo is not supported" in w for w in warnings)
    assert any("'Base Color'" in w for w in warnings)
    assert any("'Roughness'" in w for w in warnings)


def test_alpha_mask_card_through_a_group(warnings):
    image = bpy.data.images.new("leaf", 4, 4, alpha=True)
    tree, group_in, group_out = new_group(
        "Card",
        inputs=[("Alpha", "NodeSocketFloat", 1.0)],
        outputs=[("Shader", "NodeSocketShader")],
    )
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    tree.links.new(group_in.outputs["Alpha"], bsdf.inputs["Alpha"])
    tree.links.new(bsdf.outputs[0], group_out.inputs["Shader"])
    material = new_material("Leaf")
    group = group_node(material, tree)
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Alpha"], group.inputs["Alpha"])
    material.node_tree.links.new(group.outputs[0], output(material).inputs["Surface"])
    exported = convert(material, warnings)
    assert exported.program is None
    assert exported.data.alpha_texture == exported.textures[0].name
    assert exported.data.alpha == 1.0


def test_specular_socket_names_are_read_through_groups(warnings):
    # A group input feeding Specular / Specular IOR Level.
    tree, group_in, group_out = new_group(
        "Spec", inputs=[("Level", "NodeSocketFloat", 0.0)], outputs=[("Shader", "NodeSocketShader")]
    )
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    tree.links.new(group_in.outputs["Level"], first_input(bsdf, ("Specular IOR Level", "Specular")))
    tree.links.new(bsdf.outputs[0], group_out.inputs["Shader"])
    material = new_material("Spec")
    group = group_node(material, tree)
    group.inputs["Level"].default_value = 0.0
    material.node_tree.links.new(group.outputs[0], output(material).inputs["Surface"])
    assert convert(material, warnings).data.specular == pytest.approx((0.0, 0.0, 0.0))
