"""Material export: the Principled BSDF (3.x and 4.x socket names) as Whitted parameters."""

from dataclasses import dataclass, field

import bpy
import pytest
from whitted.export.material import MAX_SHININESS, convert_material


def node_material(name, **inputs):
    """A material with a Principled BSDF whose inputs (by this Blender's names) are set."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    node = material.node_tree.nodes["Principled BSDF"]
    for socket_name, value in inputs.items():
        node.inputs[socket_name].default_value = value
    return material


def first_present(node_name_options):
    node = bpy.data.materials.new("probe")
    if bpy.app.version < (5, 0, 0):
        node.use_nodes = True
    inputs = node.node_tree.nodes["Principled BSDF"].inputs
    return next(name for name in node_name_options if name in inputs)


def assert_material(data, **expected):
    for key, value in expected.items():
        assert getattr(data, key) == pytest.approx(value, rel=1e-5, abs=1e-6), key


def test_default_principled_is_a_grey_dielectric(warnings):
    data = convert_material(node_material("Default"), warnings)
    # roughness 0.5 -> alpha 0.25 -> shininess 2 / 0.0625 - 2 = 30;
    # specular 0.5 -> 0.08 * 0.5 = 0.04.
    assert_material(
        data,
        diffuse=(0.8, 0.8, 0.8),
        specular=(0.04, 0.04, 0.04),
        shininess=30.0,
        ambient=1.0,
        reflectivity=(0.0, 0.0, 0.0),
        transmissivity=(0.0, 0.0, 0.0),
        emission=(0.0, 0.0, 0.0),
    )
    assert warnings == []


def test_polished_metal_is_a_tinted_mirror(warnings):
    color = (0.9, 0.8, 0.7, 1.0)
    material = node_material("Metal", **{"Base Color": color, "Metallic": 1.0, "Roughness": 0.0})
    assert_material(
        convert_material(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        reflectivity=color[:3],
        specular=(0.0, 0.0, 0.0),
        shininess=MAX_SHININESS,
    )


def test_rough_metal_moves_reflection_into_the_highlight(warnings):
    color = (0.9, 0.8, 0.7, 1.0)
    material = node_material("Metal", **{"Base Color": color, "Metallic": 1.0, "Roughness": 0.2})
    # sharp = 1 - 4 * 0.2 = 0.2 of the base colour is mirror, the rest highlight;
    # alpha = 0.04 -> shininess 2 / 0.0016 - 2 = 1248.
    assert_material(
        convert_material(material, warnings),
        reflectivity=tuple(0.2 * c for c in color[:3]),
        specular=tuple(0.8 * c for c in color[:3]),
        shininess=1248.0,
    )


def test_glass(warnings):
    transmission = first_present(("Transmission Weight", "Transmission"))
    material = node_material(
        "Glass", **{transmission: 1.0, "IOR": 1.5, "Roughness": 0.0, "Base Color": (1, 1, 1, 1)}
    )
    assert_material(
        convert_material(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        transmissivity=(1.0, 1.0, 1.0),
        ior=1.5,
        shininess=MAX_SHININESS,
    )


def test_emission_color_times_strength(warnings):
    emission = first_present(("Emission Color", "Emission"))
    material = node_material("Lamp", **{emission: (1.0, 0.5, 0.0, 1.0), "Emission Strength": 4.0})
    assert_material(convert_material(material, warnings), emission=(4.0, 2.0, 0.0))


def test_linked_input_uses_its_value_and_warns(warnings):
    material = node_material("Textured", **{"Base Color": (0.2, 0.4, 0.6, 1.0)})
    tree = material.node_tree
    texture = tree.nodes.new("ShaderNodeTexChecker")
    tree.links.new(texture.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    data = convert_material(material, warnings)
    assert data.diffuse == pytest.approx((0.2, 0.4, 0.6))
    assert len(warnings) == 1
    assert "'Textured'" in warnings[0]
    assert "'Principled BSDF'" in warnings[0]
    assert "Base Color" in warnings[0]


def test_reroute_between_shader_and_output_is_followed(warnings):
    material = node_material("Rerouted", **{"Base Color": (0.1, 0.2, 0.3, 1.0)})
    tree = material.node_tree
    reroute = tree.nodes.new("NodeReroute")
    output = tree.nodes["Material Output"]
    tree.links.new(tree.nodes["Principled BSDF"].outputs[0], reroute.inputs[0])
    tree.links.new(reroute.outputs[0], output.inputs["Surface"])
    assert convert_material(material, warnings).diffuse == pytest.approx((0.1, 0.2, 0.3))


def test_other_shader_uses_viewport_colour_and_warns(warnings):
    material = node_material("Diffuse")
    material.diffuse_color = (0.3, 0.2, 0.1, 1.0)
    material.metallic = 0.0
    tree = material.node_tree
    shader = tree.nodes.new("ShaderNodeBsdfDiffuse")
    tree.links.new(shader.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    data = convert_material(material, warnings)
    assert data.diffuse == pytest.approx((0.3, 0.2, 0.1))
    assert "is not a Principled BSDF" in warnings[0]


def test_no_surface_shader_renders_black(warnings):
    material = node_material("Empty")
    tree = material.node_tree
    tree.links.remove(tree.nodes["Material Output"].inputs["Surface"].links[0])
    data = convert_material(material, warnings)
    assert data.diffuse == (0.0, 0.0, 0.0)
    assert "no surface shader" in warnings[0]


def test_material_without_nodes_uses_viewport_display(warnings):
    if bpy.app.version >= (5, 0, 0):
        pytest.skip("Blender 5.0 materials always use nodes")
    material = bpy.data.materials.new("Viewport")
    material.use_nodes = False
    material.diffuse_color = (0.5, 0.25, 0.125, 1.0)
    material.metallic = 0.5
    material.roughness = 0.0
    material.specular_intensity = 0.25
    assert_material(
        convert_material(material, warnings),
        diffuse=(0.25, 0.125, 0.0625),
        reflectivity=(0.25, 0.125, 0.0625),
        # (1 - metallic) * 0.08 * specular; the metal part is all mirror at roughness 0.
        specular=(0.01, 0.01, 0.01),
    )


# Stand-ins for a material's node tree, so that both Blender 3.x and 4.x socket
# names can be fed to the exporter whichever Blender runs the test.
@dataclass
class FakeSocket:
    name: str
    default_value: object
    links: list = field(default_factory=list)

    @property
    def is_linked(self):
        return bool(self.links)


@dataclass
class FakeLink:
    from_node: object
    is_muted: bool = False


@dataclass
class FakeNode:
    bl_idname: str
    name: str
    inputs: dict


@dataclass
class FakeNodeTree:
    output: FakeNode

    def get_output_node(self, target):
        return self.output


@dataclass
class FakeMaterial:
    name: str
    node_tree: FakeNodeTree
    use_nodes: bool = True


def fake_principled_material(inputs):
    principled = FakeNode(
        "ShaderNodeBsdfPrincipled",
        "Principled BSDF",
        {name: FakeSocket(name, value) for name, value in inputs.items()},
    )
    surface = FakeSocket("Surface", None, [FakeLink(principled)])
    output = FakeNode("ShaderNodeOutputMaterial", "Material Output", {"Surface": surface})
    return FakeMaterial("Fake", FakeNodeTree(output))


COMMON_INPUTS = {
    "Base Color": (0.5, 0.4, 0.3, 1.0),
    "Metallic": 0.25,
    "Roughness": 0.2,
    "IOR": 1.33,
    "Emission Strength": 2.0,
}
BLENDER_3_INPUTS = {
    **COMMON_INPUTS,
    "Specular": 0.5,
    "Transmission": 0.5,
    "Emission": (1.0, 0.5, 0.0, 1.0),
}
BLENDER_4_INPUTS = {
    **COMMON_INPUTS,
    "Specular IOR Level": 0.5,
    "Transmission Weight": 0.5,
    "Emission Color": (1.0, 0.5, 0.0, 1.0),
}


@pytest.mark.parametrize("inputs", [BLENDER_3_INPUTS, BLENDER_4_INPUTS], ids=["3.x", "4.x"])
def test_principled_mapping_by_socket_name(inputs, warnings):
    data = convert_material(fake_principled_material(inputs), warnings)
    base = (0.5, 0.4, 0.3)
    # metallic 0.25, transmission 0.5, roughness 0.2 (sharp = 0.2, alpha = 0.04).
    assert_material(
        data,
        diffuse=tuple(0.75 * 0.5 * c for c in base),
        reflectivity=tuple(0.25 * 0.2 * c for c in base),
        specular=tuple(0.75 * 0.08 * 0.5 + 0.25 * 0.8 * c for c in base),
        shininess=1248.0,
        transmissivity=tuple(0.5 * 0.75 * c for c in base),
        ior=1.33,
        emission=(2.0, 1.0, 0.0),
        ambient=1.0,
    )
    assert warnings == []
