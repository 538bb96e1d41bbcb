"""Material export: the Principled BSDF (3.x and 4.x socket names), the other BSDFs,
Mix Shader, textures as the mapping records them, and the Whitted override."""

import dataclasses
import math
from dataclasses import dataclass, field

import bpy
import pytest
from whitted.export.material import MAX_SHININESS, convert_material, map_material
from whitted.export.texture import CheckerTextureSpec, ImageTextureSpec


def convert(material, warnings, local_model="BLENDER"):
    """The Whitted parameters a material exports with in `local_model`."""
    return convert_material(material, warnings, local_model=local_model).data


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


@pytest.mark.parametrize("local_model", ["LECTURE", "BLENDER"])
def test_default_principled_is_a_grey_dielectric(local_model, warnings):
    data = convert(node_material("Default"), warnings, local_model)
    # roughness 0.5 -> alpha 0.25 -> Blinn exponent 2 / 0.0625 - 2 = 30, Phong 30 / 4;
    # specular 0.5 -> 0.08 * 0.5 = 0.04. Lecture: too rough for a mirror (no layer), a
    # Phong highlight. Blender: all of it a clear layer of the IOR of that F0 and of the
    # roughness, its GGX lobe weighted per hit by the facets' Fresnel factors.
    if local_model == "LECTURE":
        assert_material(data, coat_specular=0.0, coat_reflectivity=0.0, specular=(0.04,) * 3)
    else:
        assert_material(
            data, coat_specular=0.0, coat_reflectivity=1.0, coat_roughness=0.5, specular=(0,) * 3
        )
        assert data.coat_ior == pytest.approx(1.5)  # (1 + sqrt(0.04)) / (1 - sqrt(0.04))
    assert_material(
        data,
        diffuse=(0.8, 0.8, 0.8),
        shininess=7.5,
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
        convert(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        reflectivity=color[:3],
        specular=(0.0, 0.0, 0.0),
        shininess=MAX_SHININESS,
    )


def test_rough_metal_moves_reflection_into_the_highlight_in_the_lecture_model(warnings):
    color = (0.9, 0.8, 0.7, 1.0)
    material = node_material("Metal", **{"Base Color": color, "Metallic": 1.0, "Roughness": 0.2})
    # sharp = 1 - 4 * 0.2 = 0.2 of the base colour is mirror, the rest highlight;
    # alpha = 0.04 -> Blinn exponent 2 / 0.0016 - 2 = 1248, Phong 1248 / 4.
    assert_material(
        convert(material, warnings, local_model="LECTURE"),
        reflectivity=tuple(0.2 * c for c in color[:3]),
        specular=tuple(0.8 * c for c in color[:3]),
        shininess=312.0,
        roughness=0.0,
    )


def test_a_rough_metal_is_a_glossy_lobe_in_the_blender_model(warnings):
    color = (0.9, 0.8, 0.7, 1.0)
    material = node_material("Metal", **{"Base Color": color, "Metallic": 1.0, "Roughness": 0.2})
    # All of the base colour is the GGX lobe's, for its rays and its lamp highlights.
    assert_material(
        convert(material, warnings),
        reflectivity=color[:3],
        specular=(0.0, 0.0, 0.0),
        roughness=0.2,
    )
    # Blender 4.0 made Multiscatter GGX the Principled BSDF's default distribution.
    assert convert(material, warnings).multiscatter == (bpy.app.version >= (4, 0, 0))


def test_glass(warnings):
    transmission = first_present(("Transmission Weight", "Transmission"))
    material = node_material(
        "Glass", **{transmission: 1.0, "IOR": 1.5, "Roughness": 0.0, "Base Color": (1, 1, 1, 1)}
    )
    assert_material(
        convert(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        transmissivity=(1.0, 1.0, 1.0),
        ior=1.5,
        shininess=MAX_SHININESS,
    )


def test_emission_color_times_strength(warnings):
    emission = first_present(("Emission Color", "Emission"))
    material = node_material("Lamp", **{emission: (1.0, 0.5, 0.0, 1.0), "Emission Strength": 4.0})
    assert_material(convert(material, warnings), emission=(4.0, 2.0, 0.0))


def test_linked_input_uses_its_value_and_warns(warnings):
    material = node_material("Textured", **{"Base Color": (0.2, 0.4, 0.6, 1.0)})
    tree = material.node_tree
    texture = tree.nodes.new("ShaderNodeParticleInfo")  # a node the program lacks
    tree.links.new(texture.outputs["Age"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    data = convert(material, warnings)
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
    assert convert(material, warnings).diffuse == pytest.approx((0.1, 0.2, 0.3))


def test_unsupported_shader_is_a_diffuse_of_its_colour_and_warns(warnings):
    # Not the viewport colour: the node's own colour input, as a Lambertian.
    material = node_material("Skin")
    material.diffuse_color = (0.3, 0.2, 0.1, 1.0)
    kind = "ShaderNodeSubsurfaceScattering"
    shader = surface_shader(material, kind, Color=(0.6, 0.5, 0.4, 1.0))
    data = convert(material, warnings)
    assert data.diffuse == pytest.approx((0.6, 0.5, 0.4))
    assert data.specular == (0.0, 0.0, 0.0)
    assert warnings == [
        f"Whitted: material 'Skin', node '{shader.name}': shader '{kind}' is not "
        "supported; approximated as a Diffuse BSDF of its 'Color'"
    ]


def test_hair_shaders_are_the_diffuse_of_their_colour(warnings):
    # Hair BSDF: its Color. Principled Hair: its Color, or the colour of the absorption
    # its melanin or coefficient gives (export/nodes/bsdfs.py hair_colour).
    material = node_material("Hair")
    surface_shader(material, "ShaderNodeBsdfHair", Color=(0.6, 0.5, 0.4, 1.0))
    assert convert(material, warnings).diffuse == pytest.approx((0.6, 0.5, 0.4))
    assert "a Hair BSDF is approximated as a Lambertian diffuse" in warnings[0]
    material = node_material("Auburn")
    hair = surface_shader(material, "ShaderNodeBsdfHairPrincipled")
    hair.parametrization = "MELANIN"
    hair.inputs["Melanin"].default_value = 0.6
    hair.inputs["Melanin Redness"].default_value = 0.8
    red, green, blue = convert(material, warnings).diffuse
    assert 0.0 < blue < green < red < 1.0  # reddish brown
    # An absorption from a colour (Cycles' mapping) gives that colour back.
    from whitted.export.nodes.bsdfs import HAIR_POLYNOMIAL, hair_colour

    r = 0.3
    poly = sum(c * r**k for k, c in enumerate(HAIR_POLYNOMIAL))
    colour = (0.5, 0.3, 0.1)
    sigma = tuple((math.log(c) / poly) ** 2 for c in colour)
    back = hair_colour("ABSORPTION", {"Absorption Coefficient": sigma, "Radial Roughness": r})
    assert back == pytest.approx(colour, rel=1e-6)


def test_no_surface_shader_renders_black(warnings):
    material = node_material("Empty")
    tree = material.node_tree
    tree.links.remove(tree.nodes["Material Output"].inputs["Surface"].links[0])
    data = convert(material, warnings)
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
        convert(material, warnings),
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
    node: object = None

    @property
    def is_linked(self):
        return bool(self.links)


@dataclass
class FakeLink:
    from_socket: FakeSocket
    is_muted: bool = False

    @property
    def from_node(self):
        return self.from_socket.node


class FakeInputs(dict):
    """A node's inputs: looked up by name, iterated as sockets (like Blender's)."""

    def __iter__(self):
        return iter(self.values())


@dataclass
class FakeNode:
    bl_idname: str
    name: str
    inputs: dict
    outputs: dict = field(default_factory=dict)
    distribution: str = "GGX"  # a Principled BSDF's microfacet distribution


@dataclass
class FakeNodeTree:
    output: FakeNode

    def get_output_node(self, target):
        return self.output


@dataclass
class FakeSettings:
    use_override: bool = False


@dataclass
class FakeMaterial:
    name: str
    node_tree: FakeNodeTree
    use_nodes: bool = True
    whitted: FakeSettings = field(default_factory=FakeSettings)


def fake_principled_material(inputs):
    principled = FakeNode(
        "ShaderNodeBsdfPrincipled",
        "Principled BSDF",
        FakeInputs({name: FakeSocket(name, value) for name, value in inputs.items()}),
    )
    bsdf = FakeSocket("BSDF", None, node=principled)
    surface = FakeSocket("Surface", None, [FakeLink(bsdf)])
    output = FakeNode("ShaderNodeOutputMaterial", "Material Output", {"Surface": surface})
    return FakeMaterial("Fake", FakeNodeTree(output))


COMMON_INPUTS = {
    "Base Color": (0.5, 0.4, 0.3, 1.0),
    "Metallic": 0.25,
    "Roughness": 0.2,
    "IOR": 1.33,
    "Emission Strength": 2.0,
    "Alpha": 0.75,
}
BLENDER_3_INPUTS = {
    **COMMON_INPUTS,
    "Specular": 0.5,
    "Specular Tint": 0.0,
    "Transmission": 0.5,
    "Emission": (1.0, 0.5, 0.0, 1.0),
    "Clearcoat": 0.0,
}
BLENDER_4_INPUTS = {
    **COMMON_INPUTS,
    "Specular IOR Level": 0.5,
    "Specular Tint": (1.0, 1.0, 1.0, 1.0),
    "Transmission Weight": 0.5,
    "Emission Color": (1.0, 0.5, 0.0, 1.0),
    "Coat Weight": 0.0,
}
# Dielectric reflectance at normal incidence: 3.x 0.08 * Specular; 4.x from the
# IOR, ((1.33 - 1) / (1.33 + 1))^2, times 2 * Specular IOR Level.
F0 = {"3.x": 0.08 * 0.5, "4.x": (0.33 / 2.33) ** 2}


@pytest.mark.parametrize(
    ("version", "inputs"), [("3.x", BLENDER_3_INPUTS), ("4.x", BLENDER_4_INPUTS)]
)
@pytest.mark.parametrize("local_model", ["LECTURE", "BLENDER"])
def test_principled_mapping_by_socket_name(version, inputs, local_model, warnings):
    data = convert(fake_principled_material(inputs), warnings, local_model)
    base = (0.5, 0.4, 0.3)
    # The metal part (0.25 of the base colour): in the Lecture model a mirror of its
    # sharp share and a Phong highlight of the rest; in the Blender model all of it
    # the GGX lobe's, of roughness 0.2.
    lecture = local_model == "LECTURE"
    metal_mirror, metal_highlight = (0.25 * 0.2, 0.25 * 0.8) if lecture else (0.25, 0.0)
    # metallic 0.25, transmission 0.5, roughness 0.2 (sharp = 0.2, alpha = 0.04). The
    # sharp part of the opaque dielectric share, 0.75 * 0.5, is a layer's mirror of the
    # IOR of F0 (Lecture; in the Blender model all of it, the layer's GGX lobe); the
    # highlight keeps the rest.
    sharp = 0.2 if lecture else 1.0
    kept = 1.0 - 0.5 * sharp
    assert_material(
        data,
        coat_reflectivity=0.375 * sharp,
        coat_specular=0.0,
        coat_ior={"3.x": 1.5, "4.x": 1.33}[version],
        coat_shininess=312.0,  # (2 / 0.04^2 - 2) / 4
        coat_roughness=0.0 if lecture else 0.2,
    )
    assert_material(
        data,
        diffuse=tuple(0.75 * 0.5 * c for c in base),
        reflectivity=tuple(metal_mirror * c for c in base),
        specular=tuple(0.75 * F0[version] * kept + metal_highlight * c for c in base),
        roughness=0.0 if lecture else 0.2,
        shininess=312.0,
        transmissivity=tuple(0.5 * 0.75 * c for c in base),
        ior=1.33,
        emission=(2.0, 1.0, 0.0),
        ambient=1.0,
        alpha=0.75,
    )
    assert warnings == []


@pytest.mark.parametrize(
    ("version", "inputs", "tint"),
    [
        # 3.x: a float that blends white towards base colour / its luminance.
        ("3.x", {**BLENDER_3_INPUTS, "Specular Tint": 1.0}, "hue"),
        # 4.x: a colour that multiplies F0.
        ("4.x", {**BLENDER_4_INPUTS, "Specular Tint": (1.0, 0.5, 0.25, 1.0)}, (1.0, 0.5, 0.25)),
    ],
)
def test_principled_specular_tint(version, inputs, tint, warnings):
    inputs = {**inputs, "Metallic": 0.0}
    data = convert(fake_principled_material(inputs), warnings)
    base = (0.5, 0.4, 0.3)
    if tint == "hue":
        luminance = 0.2126 * 0.5 + 0.7152 * 0.4 + 0.0722 * 0.3
        tint = tuple(c / luminance for c in base)
    assert_material(data, specular=tuple(F0[version] * t for t in tint))


def test_principled_coat(warnings):
    # 3.x: Cycles' clearcoat lobe is a quarter of Clearcoat, IOR 1.5; roughness 0.03
    # (the default when absent) -> sharp 0.88 of it a mirror, the rest a highlight (the
    # Lecture model; the Blender model below).
    data = convert(
        fake_principled_material({**BLENDER_3_INPUTS, "Clearcoat": 0.5}), warnings, "LECTURE"
    )
    plain = convert(fake_principled_material(BLENDER_3_INPUTS), [], "LECTURE")
    assert_material(
        data,
        coat_reflectivity=0.125 * 0.88,
        coat_specular=0.125 * 0.12,
        coat_shininess=10000.0,
        coat_ior=1.5,
        diffuse=plain.diffuse,
    )
    # Without a coat, the sharp dielectric share is the layer's mirror, in the coat fields;
    # beneath a coat, in the layer fields (of the same IOR), and none without a coat.
    assert plain.coat_specular == 0.0
    assert plain.coat_reflectivity == pytest.approx(0.375 * 0.2)
    assert_material(data, layer_reflectivity=(0.375 * 0.2,) * 3, layer_ior=plain.coat_ior)
    assert_material(plain, layer_reflectivity=(0.0,) * 3)
    assert warnings == [
        "Whitted: material 'Fake', node 'Principled BSDF': 'Clearcoat' is approximated: a "
        "Phong highlight and a mirror of the coat's roughness, weighted by its Fresnel "
        "factor at the view (docs/SUPPORT.md)"
    ]
    # The Blender model: all of the coat is its lobe, of its roughness: 3.x's Clearcoat
    # is GTR1's, as Cycles 3.x's clearcoat closure; a specular layer in the coat fields
    # (no Clearcoat) stays GGX's.
    glossy = convert(fake_principled_material({**BLENDER_3_INPUTS, "Clearcoat": 0.5}), [])
    assert_material(glossy, coat_reflectivity=0.125, coat_specular=0.0, coat_roughness=0.03)
    assert glossy.coat_model == "GTR1"
    assert convert(fake_principled_material(BLENDER_3_INPUTS), []).coat_model == "GGX"
    # Beneath it, all of the opaque dielectric share is the layer's, of the base roughness.
    assert_material(glossy, layer_reflectivity=(0.375,) * 3, roughness=0.2)
    # 4.x: Coat Weight, IOR and Tint; what lies beneath is seen through the tint.
    inputs = {
        **BLENDER_4_INPUTS,
        "Coat Weight": 0.5,
        "Coat Roughness": 0.1,
        "Coat IOR": 1.3,
        "Coat Tint": (0.5, 1.0, 1.0, 1.0),
    }
    data = convert(fake_principled_material(inputs), [], "LECTURE")
    plain = convert(fake_principled_material(BLENDER_4_INPUTS), [], "LECTURE")
    assert_material(
        data,
        coat_reflectivity=0.5 * 0.6,
        coat_specular=0.5 * 0.4,
        coat_shininess=4999.5,  # roughness 0.1: (2 / 0.01^2 - 2) / 4
        coat_ior=1.3,
        diffuse=(0.75 * plain.diffuse[0], plain.diffuse[1], plain.diffuse[2]),
        # The specular layer beneath, seen through the tint too.
        layer_reflectivity=(0.75 * 0.375 * 0.2, 0.375 * 0.2, 0.375 * 0.2),
        layer_ior=plain.coat_ior,
    )
    # 4.x's Coat is a GGX dielectric layer.
    assert convert(fake_principled_material(inputs), []).coat_model == "GGX"


def surface_shader(material, bl_idname, **inputs):
    """A new node of type `bl_idname`, linked to the material's output, inputs set."""
    tree = material.node_tree
    node = tree.nodes.new(bl_idname)
    for name, value in inputs.items():
        node.inputs[name].default_value = value
    tree.links.new(node.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    return node


def test_diffuse_bsdf_is_lambert(warnings):
    material = node_material("Diffuse")
    surface_shader(material, "ShaderNodeBsdfDiffuse", Color=(0.3, 0.2, 0.1, 1.0))
    assert_material(
        convert(material, warnings),
        diffuse=(0.3, 0.2, 0.1),
        specular=(0.0, 0.0, 0.0),
        reflectivity=(0.0, 0.0, 0.0),
        transmissivity=(0.0, 0.0, 0.0),
        alpha=1.0,
    )
    assert warnings == []


def test_rough_diffuse_bsdf_is_oren_nayar(warnings):
    material = node_material("Rough")
    surface_shader(material, "ShaderNodeBsdfDiffuse", Color=(0.3, 0.2, 0.1, 1.0), Roughness=0.5)
    exported = map_material(material, warnings)
    energy = bpy.app.version >= (4, 3, 0)  # Cycles 4.3 added its multiple scattering
    assert exported.data.diffuse_model == ("OREN_NAYAR_ENERGY" if energy else "OREN_NAYAR")
    assert exported.data.diffuse_roughness == pytest.approx(0.5)
    assert exported.data.diffuse == pytest.approx((0.3, 0.2, 0.1))
    assert warnings == []


def test_sharp_glossy_is_a_mirror(warnings):
    material = node_material("Mirror")
    surface_shader(material, "ShaderNodeBsdfGlossy", Color=(0.9, 0.8, 0.7, 1.0), Roughness=0.0)
    assert_material(
        convert(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        reflectivity=(0.9, 0.8, 0.7),
        specular=(0.0, 0.0, 0.0),
        shininess=MAX_SHININESS,
    )


def test_rough_glossy_is_a_highlight_in_the_lecture_model(warnings):
    material = node_material("Satin")
    surface_shader(material, "ShaderNodeBsdfGlossy", Color=(0.9, 0.8, 0.7, 1.0), Roughness=0.5)
    # roughness 0.5: sharp = 0, alpha = 0.25 -> Phong exponent (2 / 0.0625 - 2) / 4.
    assert_material(
        convert(material, warnings, local_model="LECTURE"),
        reflectivity=(0.0, 0.0, 0.0),
        specular=(0.9, 0.8, 0.7),
        shininess=7.5,
    )


def test_rough_glossy_is_its_lobe_in_the_blender_model(warnings):
    material = node_material("Satin")
    node = surface_shader(
        material, "ShaderNodeBsdfGlossy", Color=(0.9, 0.8, 0.7, 1.0), Roughness=0.5
    )
    node.distribution = "GGX"
    assert_material(
        convert(material, warnings),
        reflectivity=(0.9, 0.8, 0.7),
        specular=(0.0, 0.0, 0.0),
        roughness=0.5,
    )
    assert not convert(material, warnings).multiscatter
    node.distribution = "MULTI_GGX"
    assert convert(material, warnings).multiscatter


def test_glass_bsdf(warnings):
    material = node_material("Glass")
    surface_shader(
        material, "ShaderNodeBsdfGlass", Color=(1.0, 0.9, 0.8, 1.0), Roughness=0.0, IOR=1.5
    )
    # F0 of IOR 1.5: (0.5 / 2.5)^2 = 0.04.
    assert_material(
        convert(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        transmissivity=(1.0, 0.9, 0.8),
        reflectivity=(0.0, 0.0, 0.0),
        specular=(0.04, 0.04, 0.04),
        ior=1.5,
    )


def test_refraction_bsdf(warnings):
    material = node_material("Refraction")
    surface_shader(material, "ShaderNodeBsdfRefraction", Color=(0.5, 0.6, 0.7, 1.0), IOR=1.33)
    assert_material(
        convert(material, warnings),
        diffuse=(0.0, 0.0, 0.0),
        transmissivity=(0.5, 0.6, 0.7),
        specular=(0.0, 0.0, 0.0),
        ior=1.33,
    )


def test_transparent_bsdf_is_coverage(warnings):
    material = node_material("Transparent")
    surface_shader(material, "ShaderNodeBsdfTransparent", Color=(1.0, 1.0, 1.0, 1.0))
    assert_material(convert(material, warnings), alpha=0.0, diffuse=(0.0, 0.0, 0.0))
    assert warnings == []


def test_grey_transparent_bsdf_passes_its_grey(warnings):
    material = node_material("Smoked")
    surface_shader(material, "ShaderNodeBsdfTransparent", Color=(0.25, 0.25, 0.25, 1.0))
    assert_material(convert(material, warnings), alpha=0.75)


def test_coloured_transparent_bsdf_warns(warnings):
    material = node_material("Tinted")
    surface_shader(material, "ShaderNodeBsdfTransparent", Color=(0.9, 0.6, 0.3, 1.0))
    assert_material(convert(material, warnings), alpha=0.4)
    assert "mean grey" in warnings[0]


def test_emission_bsdf(warnings):
    material = node_material("Emission")
    surface_shader(material, "ShaderNodeEmission", Color=(1.0, 0.5, 0.25, 1.0), Strength=2.0)
    assert_material(convert(material, warnings), emission=(2.0, 1.0, 0.5), diffuse=(0.0, 0.0, 0.0))


def mix_shader(material, factor, first, second):
    """A Mix Shader of two new shader nodes ((bl_idname, inputs) pairs), linked to
    the output; returns (mix, first node, second node)."""
    tree = material.node_tree
    mix = surface_shader(material, "ShaderNodeMixShader")
    mix.inputs[0].default_value = factor
    nodes = []
    for index, (bl_idname, inputs) in enumerate((first, second), start=1):
        node = tree.nodes.new(bl_idname)
        for name, value in inputs.items():
            node.inputs[name].default_value = value
        tree.links.new(node.outputs[0], mix.inputs[index])
        nodes.append(node)
    return mix, *nodes


def test_mix_shader_blends_linearly(warnings):
    material = node_material("Mix")
    mix_shader(
        material,
        0.25,
        ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.4, 0.0, 1.0)}),
        ("ShaderNodeEmission", {"Color": (1.0, 1.0, 1.0, 1.0), "Strength": 4.0}),
    )
    assert_material(
        convert(material, warnings),
        diffuse=(0.6, 0.3, 0.0),
        emission=(1.0, 1.0, 1.0),
        alpha=1.0,
    )
    assert warnings == []


def test_mix_with_transparent_is_coverage_of_the_other_shader(warnings):
    material = node_material("Leaf")
    mix_shader(
        material,
        0.25,
        ("ShaderNodeBsdfTransparent", {}),
        ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.6, 0.1, 1.0)}),
    )
    # A quarter of the surface is there, and what is there is the diffuse shader.
    assert_material(convert(material, warnings), alpha=0.25, diffuse=(0.2, 0.6, 0.1))


def test_mix_with_unsupported_factor_warns_and_uses_its_unlinked_value(warnings):
    material = node_material("Noisy")
    mix, *_ = mix_shader(
        material,
        0.25,
        ("ShaderNodeBsdfDiffuse", {"Color": (1.0, 0.0, 0.0, 1.0)}),
        ("ShaderNodeBsdfDiffuse", {"Color": (0.0, 0.0, 1.0, 1.0)}),
    )
    noise = material.node_tree.nodes.new("ShaderNodeParticleInfo")
    material.node_tree.links.new(noise.outputs["Age"], mix.inputs[0])
    assert_material(convert(material, warnings), diffuse=(0.75, 0.0, 0.25))
    assert warnings == [
        f"Whitted: material 'Noisy', node '{noise.name}': ShaderNodeParticleInfo is not "
        "supported; "
        f"input '{mix.inputs[0].name}' of '{mix.name}' uses its unlinked value"
    ]


def test_mix_factor_from_image_alpha_over_transparent_is_an_alpha_texture(warnings):
    material = node_material("Cutout")
    mix, *_ = mix_shader(
        material, 0.0, ("ShaderNodeBsdfTransparent", {}), ("ShaderNodeBsdfDiffuse", {})
    )
    image = material.node_tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("leaf", 2, 2, alpha=True)
    material.node_tree.links.new(image.outputs["Alpha"], mix.inputs[0])
    exported = convert_material(material, warnings)
    assert exported.data.alpha_texture == exported.textures[0].name
    assert exported.data.alpha == 1.0
    assert exported.data.diffuse == pytest.approx((0.8, 0.8, 0.8))
    assert warnings == []


def test_unsupported_node_in_both_mix_inputs_warns_once(warnings):
    material = node_material("Twice")
    mix, hair, _ = mix_shader(
        material, 0.5, ("ShaderNodeSubsurfaceScattering", {}), ("ShaderNodeBsdfDiffuse", {})
    )
    material.node_tree.links.new(hair.outputs[0], mix.inputs[2])
    convert(material, warnings)
    assert len(warnings) == 1
    assert "ShaderNodeSubsurfaceScattering" in warnings[0]


def test_empty_mix_input_is_black(warnings):
    material = node_material("Half")
    mix, *_ = mix_shader(
        material,
        0.5,
        ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.8, 0.8, 1.0)}),
        ("ShaderNodeBsdfDiffuse", {}),
    )
    material.node_tree.links.remove(mix.inputs[2].links[0])
    assert_material(convert(material, warnings), diffuse=(0.4, 0.4, 0.4), alpha=1.0)


def test_image_on_base_color_is_a_diffuse_texture(warnings):
    material = node_material("Photo", **{"Base Color": (0.1, 0.1, 0.1, 1.0)})
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("photo", 4, 4)
    image.interpolation = "Closest"
    image.extension = "CLIP"
    tree.links.new(image.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    exported = convert_material(material, warnings)
    (spec,) = exported.textures
    assert isinstance(spec, ImageTextureSpec)
    assert (spec.image, spec.interpolation, spec.extension) == (image.image, "CLOSEST", "CLIP")
    assert (spec.coordinates, spec.uv_map) == ("UV", "")
    assert exported.uv_map == ""
    # The texture multiplies kd, which is the diffuse weight (1) times white.
    assert exported.data.diffuse_texture == spec.name
    assert exported.data.diffuse == pytest.approx((1.0, 1.0, 1.0))
    assert warnings == []


def test_image_alpha_on_principled_alpha_is_an_alpha_texture(warnings):
    material = node_material("Fence", Alpha=0.3)
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("fence", 4, 4, alpha=True)
    tree.links.new(image.outputs["Alpha"], tree.nodes["Principled BSDF"].inputs["Alpha"])
    exported = convert_material(material, warnings)
    assert exported.data.alpha_texture == exported.textures[0].name
    assert exported.data.diffuse_texture == ""
    assert exported.data.alpha == 1.0


def test_uv_map_node_names_the_map(warnings):
    material = node_material("Decal")
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("decal", 4, 4)
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = "Decal UVs"
    tree.links.new(uv.outputs["UV"], image.inputs["Vector"])
    tree.links.new(image.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    assert convert_material(material, warnings).uv_map == "Decal UVs"


def test_image_without_image_warns_and_uses_the_unlinked_colour(warnings):
    material = node_material("Blank", **{"Base Color": (0.1, 0.2, 0.3, 1.0)})
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    tree.links.new(image.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    exported = convert_material(material, warnings)
    assert exported.data.diffuse == pytest.approx((0.1, 0.2, 0.3))
    assert exported.textures == ()
    assert "no image" in warnings[0]


def test_unsupported_texture_settings_warn(warnings):
    material = node_material("Smart")
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("smart", 4, 4)
    image.interpolation = "Cubic"
    tree.links.new(image.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    (spec,) = convert_material(material, warnings).textures
    assert (spec.interpolation, spec.coordinates) == ("LINEAR", "UV")
    assert any("Cubic interpolation is not supported; Linear" in w for w in warnings)


def test_graph_needing_a_program_gets_one(warnings):
    # A Mapping node needs the shader program: the material gets one, reading the image.
    material = node_material("Smart", **{"Base Color": (0.1, 0.2, 0.3, 1.0)})
    tree = material.node_tree
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.new("smart", 4, 4)
    mapping = tree.nodes.new("ShaderNodeMapping")
    tree.links.new(mapping.outputs[0], image.inputs["Vector"])
    tree.links.new(image.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    with_program = convert_material(material, warnings)
    assert with_program.program is not None
    assert warnings == []
    assert [t.image for t in with_program.textures] == [image.image]


@pytest.mark.parametrize(
    ("output", "coordinates"), [(None, "GENERATED"), ("UV", "UV"), ("Object", "OBJECT")]
)
def test_checker_texture(output, coordinates, warnings):
    material = node_material("Checker")
    tree = material.node_tree
    checker = tree.nodes.new("ShaderNodeTexChecker")
    checker.inputs["Color1"].default_value = (1.0, 0.0, 0.0, 1.0)
    checker.inputs["Color2"].default_value = (0.0, 0.0, 1.0, 1.0)
    checker.inputs["Scale"].default_value = 3.0
    if output is not None:
        coords = tree.nodes.new("ShaderNodeTexCoord")
        tree.links.new(coords.outputs[output], checker.inputs["Vector"])
    tree.links.new(checker.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    exported = convert_material(material, warnings)
    assert exported.textures == (
        CheckerTextureSpec((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), 3.0, coordinates, ""),
    )
    assert exported.data.diffuse_texture == exported.textures[0].name
    assert exported.uv_map == ("" if coordinates == "UV" else None)
    assert warnings == []


def test_override_starts_from_the_mapping_and_wins(warnings):
    color = (0.9, 0.6, 0.3, 1.0)
    material = node_material("Override", **{"Base Color": color, "Roughness": 0.1})
    derived = map_material(material, []).data
    settings = material.whitted
    settings.use_override = True
    # The panel shows what the mapping derived: kd = 0.9 * (1, 2/3, 1/3).
    assert settings.diffuse_weight == pytest.approx(0.9)
    assert tuple(settings.diffuse_color) == pytest.approx((1.0, 2.0 / 3.0, 1.0 / 3.0))
    assert settings.shininess == pytest.approx(derived.shininess)
    assert_material(
        convert(material, warnings),
        diffuse=derived.diffuse,
        specular=derived.specular,
        shininess=derived.shininess,
        ambient=derived.ambient,
        reflectivity=derived.reflectivity,
        transmissivity=derived.transmissivity,
        ior=derived.ior,
    )
    # Edits in the panel are what the exporter uses.
    settings.diffuse_weight = 0.5
    settings.reflectivity = (0.25, 0.25, 0.25)
    settings.ior = 2.0
    assert_material(
        convert(material, warnings),
        diffuse=(0.5, 1.0 / 3.0, 1.0 / 6.0),
        reflectivity=(0.25, 0.25, 0.25),
        ior=2.0,
    )
    # Switched off, the nodes rule again.
    settings.use_override = False
    assert convert(material, warnings) == derived


def test_any_vector_linked_into_normal_is_the_shading_normal(warnings):
    # Not only a Normal Map's, a Bump's or a Bevel's: the program computes the normal
    # from whatever feeds it (here the Incoming direction), as Cycles reads its Normal.
    material = node_material("Bumpy")
    diffuse = surface_shader(material, "ShaderNodeBsdfDiffuse")
    geometry = material.node_tree.nodes.new("ShaderNodeNewGeometry")
    material.node_tree.links.new(geometry.outputs["Incoming"], diffuse.inputs["Normal"])
    exported = convert_material(material, warnings)
    assert set(dict(exported.outputs)) == {"normal"}
    assert warnings == []


def test_sheen_and_a_bumped_coat_need_a_program(warnings):
    from whitted.export.nodes import ops

    material = node_material("Velvety")
    tree = material.node_tree
    bsdf = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    sheen = next(s for s in bsdf.inputs if s.name in ("Sheen Weight", "Sheen"))
    sheen.default_value = 0.5
    coat = next(s for s in bsdf.inputs if s.name in ("Coat Weight", "Clearcoat"))
    coat.default_value = 1.0
    bump = tree.nodes.new("ShaderNodeBump")
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coordinates.outputs["Object"], separate.inputs[0])
    tree.links.new(separate.outputs["X"], bump.inputs["Height"])
    coat_normal = next(s for s in bsdf.inputs if s.name in ("Coat Normal", "Clearcoat Normal"))
    tree.links.new(bump.outputs["Normal"], coat_normal)
    exported = convert_material(material, warnings)
    outputs = dict(exported.outputs)
    # Sheen brightens the diffuse colour by the view angle; the coat's normal is bumped.
    assert set(outputs) == {"diffuse", "coat_normal"}
    codes = [int(row[0]) for row in exported.program.code]
    assert ops.LAYER_WEIGHT in codes and ops.BUMP in codes
    assert any(f"'{sheen.name}' is approximated" in w for w in warnings)
    assert exported.data.coat_reflectivity > 0.0
    # The base's normal is not mapped: only Cycles 3.x's lift turns it (and fades it).
    assert exported.data.bump_shadowing == ("CHIANG" if bpy.app.version < (4, 0, 0) else "NONE")


@pytest.mark.parametrize("method", ["BUMP", "BOTH", "DISPLACEMENT"])
def test_a_displacement_is_a_bump_or_moves_vertices(method, warnings):
    # Cycles' Displacement methods (Material > Settings): Bump Only (the default) shades
    # the output's Displacement as a bump of the closures' normal; Displacement Only
    # moves the vertices (a program run per vertex: sync/displace.py) and bumps nothing;
    # Displacement and Bump does both. One lowering of the output's Displacement serves
    # both (tests/blender/test_surface_vs_cycles.py compares the bump, test_displacement.py
    # the moved vertices).
    from whitted.export.nodes import ops

    material = node_material("Displaced")
    settings = material if hasattr(material, "displacement_method") else material.cycles
    settings.displacement_method = method
    tree = material.node_tree
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    displacement = tree.nodes.new("ShaderNodeDisplacement")
    height = tree.nodes.new("ShaderNodeTexNoise").outputs["Fac"]
    tree.links.new(height, displacement.inputs["Height"])
    tree.links.new(displacement.outputs["Displacement"], output.inputs["Displacement"])
    exported = convert_material(material, warnings)
    assert warnings == []
    outputs = dict(exported.outputs or ())
    codes = [] if exported.program is None else [int(row[0]) for row in exported.program.code]
    assert ("normal" in outputs and ops.BUMP in codes) == (method != "DISPLACEMENT")
    moved = exported.displacement
    if method == "BUMP":
        assert moved is None
        return
    assert moved.method == method
    code = [int(row[0]) for row in moved.program.code]
    assert ops.NOISE in code and ops.BUMP not in code
    assert moved.output < len(moved.program.registers)


def test_the_exporters_fields_are_the_native_tables(warnings):
    # The shader lowering's fields (how closures mix each: shaders.py) are the fields a
    # native program may drive, no more and no fewer; the exported data, the native
    # material's parameters; and a full export becomes a native material as it is.
    from whitted.export.material import MaterialExport
    from whitted.export.nodes.shaders import LINEAR_FIELDS, WEIGHTED_FIELDS
    from whitted.export.volume import VOLUME_FIELDS
    from whitted.native import load_native
    from whitted.sync.native_data import native_material

    native = load_native()
    # The surface's fields, the medium's (export/volume.py) and the displacement's
    # (export/material.py Displacement: a program of its own, run at the vertices).
    lowered = [*LINEAR_FIELDS, *WEIGHTED_FIELDS, "alpha", "normal", "coat_normal", "tangent"]
    lowered += [*VOLUME_FIELDS, "displacement"]
    assert sorted(lowered) == sorted(name for name, _ in native.MATERIAL_FIELDS)
    exported = convert_material(node_material("Tables", Roughness=0.4), warnings)
    data = dataclasses.asdict(exported.data)
    own = {f.name for f in dataclasses.fields(MaterialExport)}
    assert set(data) | (own & {n for n, _ in native.MATERIAL_PARAMS}) == {
        n for n, _ in native.MATERIAL_PARAMS
    }
    made = native_material(native, exported)
    for name, value in data.items():
        shown = getattr(made, name)
        shown = shown.name if hasattr(type(shown), "__members__") else shown
        numeric = not isinstance(value, (str, bool))
        assert shown == (pytest.approx(value, rel=1e-6) if numeric else value), name
