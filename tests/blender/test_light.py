"""Light export: Cycles' units, directions, area sizes, instances."""

import math
from dataclasses import replace

import bpy
import pytest
from exported import exported_lights
from whitted.export.light import (
    AREA_WATTS_TO_RADIANCE,
    DEFAULT_LIGHT_SAMPLES,
    shadow_switch,
)


def add_light(scene, light_type, name="Light", location=(0.0, 0.0, 0.0), **light_settings):
    light = bpy.data.lights.new(name, light_type)
    for key, value in light_settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def convert(warnings):
    return exported_lights(bpy.context.evaluated_depsgraph_get(), warnings)


def test_point_light_radiant_intensity(empty_scene, warnings):
    add_light(empty_scene, "POINT", location=(1.0, 2.0, 3.0), energy=1000.0, color=(1.0, 0.5, 0.25))
    (light,) = convert(warnings)
    # I = P / (4 pi) W/sr, times the colour.
    intensity = 1000.0 / (4.0 * math.pi)
    assert light.type == "POINT"
    assert light.name == "Light"
    assert light.color == pytest.approx((intensity, intensity * 0.5, intensity * 0.25))
    assert light.position == pytest.approx((1.0, 2.0, 3.0))
    assert light.cast_shadows is True
    assert warnings == []


def test_spot_light_cone_and_direction(empty_scene, warnings):
    obj = add_light(empty_scene, "SPOT", energy=100.0, spot_size=math.radians(60.0), spot_blend=0.3)
    # Rotated -90 degrees about Y: local -Z turns to world +X.
    obj.rotation_euler = (0.0, math.radians(-90.0), 0.0)
    (light,) = convert(warnings)
    assert light.type == "SPOT"
    # Not renormalised to the cone, as in Cycles.
    assert light.color == pytest.approx((100.0 / (4.0 * math.pi),) * 3)
    assert light.spot_size == pytest.approx(math.radians(60.0))
    assert light.spot_blend == pytest.approx(0.3)
    assert light.direction == pytest.approx((1.0, 0.0, 0.0), abs=1e-6)


def test_sun_irradiance_and_direction(empty_scene, warnings):
    obj = add_light(empty_scene, "SUN", energy=3.0, color=(1.0, 0.9, 0.8))
    obj.rotation_euler = (math.radians(45.0), 0.0, 0.0)
    (light,) = convert(warnings)
    # Strength is irradiance in W/m^2.
    assert light.color == pytest.approx((3.0, 2.7, 2.4))
    # -Z rotated 45 degrees about X: (0, sin 45, -cos 45).
    half = math.sqrt(0.5)
    assert light.direction == pytest.approx((0.0, half, -half), abs=1e-6)


def test_area_rectangle_radiance_uses_world_size(empty_scene, warnings):
    obj = add_light(empty_scene, "AREA", energy=120.0, shape="RECTANGLE", size=2.0, size_y=0.5)
    obj.scale = (2.0, 3.0, 1.0)
    (light,) = convert(warnings)
    # World size 4 x 1.5 = 6 m^2; L = P / (pi A) (P / (4 A) before 4.0).
    assert light.size == pytest.approx((4.0, 1.5))
    assert light.color == pytest.approx((120.0 * AREA_WATTS_TO_RADIANCE / 6.0,) * 3)
    assert light.shape == "RECTANGLE"
    assert light.axis_u == pytest.approx((1.0, 0.0, 0.0))
    assert light.axis_v == pytest.approx((0.0, 1.0, 0.0))
    assert light.direction == pytest.approx((0.0, 0.0, -1.0))
    assert light.samples == DEFAULT_LIGHT_SAMPLES


def test_area_disk_radiance(empty_scene, warnings):
    add_light(empty_scene, "AREA", energy=100.0, shape="DISK", size=2.0)
    (light,) = convert(warnings)
    # A disk of diameter 2: A = pi/4 * 2 * 2 = pi.
    assert light.shape == "ELLIPSE"
    assert light.size == pytest.approx((2.0, 2.0))
    assert light.color == pytest.approx((100.0 * AREA_WATTS_TO_RADIANCE / math.pi,) * 3)


def test_area_radiance_factor_follows_the_blender_version():
    # Blender 4.0 changed Cycles' area light from L = P / (4 A) to L = P / (pi A).
    expected = 1.0 / math.pi if bpy.app.version >= (4, 0, 0) else 0.25
    assert expected == AREA_WATTS_TO_RADIANCE


def test_area_square_uses_size_for_both_axes(empty_scene, warnings):
    add_light(empty_scene, "AREA", energy=16.0, shape="SQUARE", size=2.0, size_y=9.0)
    (light,) = convert(warnings)
    assert light.size == pytest.approx((2.0, 2.0))
    assert light.color == pytest.approx((16.0 * AREA_WATTS_TO_RADIANCE / 4.0,) * 3)


def test_shadowless_light_uses_the_switch_cycles_reads(empty_scene, warnings):
    obj = add_light(empty_scene, "POINT")
    owner, switch = shadow_switch(obj.data)
    # Blender 3.x's Cycles: light.cycles.cast_shadow; 4.0+: light.use_shadow.
    expected_owner = obj.data.cycles if bpy.app.version < (4, 0, 0) else obj.data
    assert (owner, switch) == (
        expected_owner,
        "cast_shadow" if bpy.app.version < (4, 0, 0) else "use_shadow",
    )
    setattr(owner, switch, False)
    (light,) = convert(warnings)
    assert light.cast_shadows is False


def test_point_radius_and_samples(empty_scene, warnings):
    obj = add_light(empty_scene, "POINT", energy=100.0, shadow_soft_size=0.25)
    obj.scale = (2.0, 2.0, 2.0)
    (light,) = convert(warnings)
    # The radius is not scaled by the object (as in Cycles) and does not change I.
    assert light.radius == pytest.approx(0.25)
    assert light.color == pytest.approx((100.0 / (4.0 * math.pi),) * 3)
    assert light.samples == DEFAULT_LIGHT_SAMPLES
    obj.data.whitted.samples = 7
    obj.data.update_tag()  # custom properties do not tag the light for re-evaluation
    (light,) = convert(warnings)
    assert light.samples == 7


def test_size_zero_lights_send_one_feeler(empty_scene, warnings):
    add_light(empty_scene, "POINT", name="Point", shadow_soft_size=0.0).data.whitted.samples = 9
    add_light(empty_scene, "SUN", name="Sun", angle=0.0).data.whitted.samples = 9
    assert [light.samples for light in convert(warnings)] == [1, 1]


def test_sun_angle(empty_scene, warnings):
    add_light(empty_scene, "SUN", energy=2.0, angle=math.radians(10.0))
    (light,) = convert(warnings)
    assert light.angle == pytest.approx(math.radians(10.0))
    # Normalised: the strength stays the irradiance whatever the angle.
    assert light.color == pytest.approx((2.0, 2.0, 2.0))
    assert light.samples == DEFAULT_LIGHT_SAMPLES


def test_ray_visibility_and_max_bounces_are_exported(empty_scene, warnings):
    obj = add_light(empty_scene, "POINT")
    obj.visible_glossy = False
    obj.data.cycles.max_bounces = 2
    (light,) = convert(warnings)
    assert (light.diffuse, light.glossy, light.max_bounces) == (True, False, 2)


def test_area_spread_is_exported(empty_scene, warnings):
    # Rendered as Cycles' soft box (tests/blender/test_cycles_lights.py), no longer warned.
    add_light(empty_scene, "AREA", spread=math.radians(90.0))
    (light,) = convert(warnings)
    assert light.spread == pytest.approx(math.radians(90.0))
    assert warnings == []


def test_area_of_size_zero_is_skipped(empty_scene, warnings):
    add_light(empty_scene, "AREA", size=0.0)
    assert convert(warnings) == []
    assert "no area" in warnings[0]


def test_exposure_and_normalize_when_blender_has_them(empty_scene, warnings):
    light_data = bpy.data.lights.new("probe", "AREA")
    if not hasattr(light_data, "exposure"):
        pytest.skip(f"Blender {bpy.app.version_string} lights have no exposure/normalize")
    add_light(empty_scene, "AREA", energy=40.0, size=2.0, exposure=1.0, normalize=False)
    (light,) = convert(warnings)
    # x 2^1 for the exposure; not normalised: L = P / pi whatever the area.
    assert light.color == pytest.approx((80.0 / math.pi,) * 3)


def test_unnormalized_point_and_sun_scale_by_cycles_light_area(empty_scene, warnings):
    if not hasattr(bpy.data.lights.new("probe", "POINT"), "normalize"):
        pytest.skip(f"Blender {bpy.app.version_string} lights have no normalize")
    add_light(empty_scene, "POINT", name="A", energy=100.0, normalize=False)
    add_light(empty_scene, "POINT", name="B", energy=100.0, shadow_soft_size=0.5, normalize=False)
    add_light(empty_scene, "SUN", name="C", energy=2.0, angle=math.radians(10.0), normalize=False)
    point, sphere, sun = convert(warnings)
    # I = P / (4 pi) x Cycles' area: 4 for radius 0, 4 pi r^2 for a sphere.
    assert point.color == pytest.approx((100.0 / math.pi,) * 3)
    assert sphere.color == pytest.approx((100.0 * 0.25,) * 3)
    # E = S x pi sin^2(angle / 2).
    assert sun.color == pytest.approx((2.0 * math.pi * math.sin(math.radians(5.0)) ** 2,) * 3)


def test_temperature_tints_like_cycles(empty_scene, warnings):
    if not hasattr(bpy.data.lights.new("probe", "POINT"), "use_temperature"):
        pytest.skip(f"Blender {bpy.app.version_string} lights have no temperature")
    obj = add_light(empty_scene, "POINT", energy=4.0 * math.pi, use_temperature=True)
    obj.data.temperature = 3000.0
    (light,) = convert(warnings)
    # Cycles multiplies the colour by Blender's own blackbody colour.
    assert light.color == pytest.approx(tuple(obj.data.temperature_color), rel=1e-6)
    assert light.color[0] > light.color[2]


def test_hidden_light_is_skipped(empty_scene, warnings):
    add_light(empty_scene, "POINT", name="Shown")
    add_light(empty_scene, "POINT", name="Hidden").hide_render = True
    assert [light.name for light in convert(warnings)] == ["Shown"]


def test_instanced_lights_get_their_own_names_and_positions(empty_scene, warnings):
    source = bpy.data.collections.new("Lamps")
    obj = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    source.objects.link(obj)
    for i in range(3):
        instancer = bpy.data.objects.new(f"Instancer {i}", None)
        instancer.instance_type = "COLLECTION"
        instancer.instance_collection = source
        instancer.location = (float(i), 0.0, 0.0)
        empty_scene.collection.objects.link(instancer)
    lights = convert(warnings)
    assert len({light.name for light in lights}) == 3
    assert sorted(light.position[0] for light in lights) == pytest.approx([0.0, 1.0, 2.0])


def test_zero_scale_light_is_skipped_with_a_warning(empty_scene, warnings):
    add_light(empty_scene, "SUN").scale = (1.0, 1.0, 0.0)
    assert convert(warnings) == []
    assert "zero scale" in warnings[0]


def lamp_tree(scene, light_type="POINT", energy=1000.0):
    """A lamp with its node tree on; (its object, the tree, its Emission node)."""
    obj = add_light(scene, light_type, energy=energy)
    obj.data.use_nodes = True
    tree = obj.data.node_tree
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    return obj, tree, emission


def test_a_lamp_tree_of_constants_folds_to_one_factor(empty_scene, warnings):
    # Mix Shader (0.25) of two Emissions: Cycles' lamp emits the mix of both; Whitted folds
    # it to the factor of the lamp's power, with no program.
    _, tree, emission = lamp_tree(empty_scene)
    emission.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    emission.inputs["Strength"].default_value = 2.0
    other = tree.nodes.new("ShaderNodeEmission")
    other.inputs["Color"].default_value = (0.2, 0.4, 1.0, 1.0)
    other.inputs["Strength"].default_value = 4.0
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.25
    tree.links.new(emission.outputs[0], mix.inputs[1])
    tree.links.new(other.outputs[0], mix.inputs[2])
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputLight")
    tree.links.new(mix.outputs[0], output.inputs["Surface"])
    (light,) = convert(warnings)
    factor = (0.75 * 2.0 + 0.25 * 0.8, 0.75 * 1.0 + 0.25 * 1.6, 0.75 * 0.5 + 0.25 * 4.0)
    intensity = 1000.0 / (4.0 * math.pi)
    assert light.color == pytest.approx(tuple(intensity * f for f in factor), rel=1e-6)
    assert light.program is None
    assert warnings == []


def test_a_lamp_tree_feeding_nothing_lights_nothing(empty_scene, warnings):
    _, tree, _ = lamp_tree(empty_scene)
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputLight")
    tree.links.remove(output.inputs["Surface"].links[0])
    (light,) = convert(warnings)
    assert light.color == (0.0, 0.0, 0.0)
    assert light.program is None


@pytest.mark.parametrize("light_type", ["POINT", "SPOT", "AREA"])
def test_light_falloff_on_a_lamp_is_a_program_of_the_ray_length(empty_scene, warnings, light_type):
    # Linear Light Falloff scales the strength by the distance to the lit point: the lamp
    # carries a program (native scene/light.cpp lamp_emission); its colour is its power.
    _, tree, emission = lamp_tree(empty_scene, light_type)
    falloff = tree.nodes.new("ShaderNodeLightFalloff")
    falloff.inputs["Strength"].default_value = 3.0
    tree.links.new(falloff.outputs["Linear"], emission.inputs["Strength"])
    (light,) = convert(warnings)
    assert warnings == []
    assert "LIGHT_FALLOFF" in light.program.describe()
    bare = replace(light, program=None, program_output=0)
    tree.links.remove(emission.inputs["Strength"].links[0])
    emission.inputs["Strength"].default_value = 1.0
    (plain,) = convert(warnings)
    assert bare == plain


def test_quadratic_light_falloff_without_smoothing_is_the_lamps_own_law(empty_scene, warnings):
    # Quadratic with Smooth 0 is its Strength whatever the distance: folded, no program.
    _, tree, emission = lamp_tree(empty_scene)
    falloff = tree.nodes.new("ShaderNodeLightFalloff")
    falloff.inputs["Strength"].default_value = 3.0
    falloff.inputs["Smooth"].default_value = 0.0
    tree.links.new(falloff.outputs["Quadratic"], emission.inputs["Strength"])
    (light,) = convert(warnings)
    assert light.program is None
    assert light.color == pytest.approx((3000.0 / (4.0 * math.pi),) * 3)


@pytest.mark.parametrize(
    ("light_type", "node", "output", "why"),
    [
        ("SUN", "ShaderNodeLightFalloff", "Linear", "a sun's program is not evaluated"),
        ("POINT", "ShaderNodeTexNoise", "Fac", "a coordinate or a path input"),
    ],
)
def test_a_lamp_tree_whitted_cannot_run_is_warned_and_lights_plain(
    empty_scene, warnings, light_type, node, output, why
):
    # A Noise Texture reads the lamp's Generated coordinates, which Whitted does not give
    # a lamp; a sun runs no program: each is warned by the light's name and lights with its
    # colour and power, as before.
    _, tree, emission = lamp_tree(empty_scene, light_type, energy=2.0)
    source = tree.nodes.new(node)
    tree.links.new(source.outputs[output], emission.inputs["Strength"])
    (light,) = convert(warnings)
    assert light.program is None
    assert light.color == pytest.approx(
        (2.0,) * 3 if light_type == "SUN" else (2.0 / (4.0 * math.pi),) * 3
    )
    (message,) = warnings
    assert "light 'Light''s node tree is not read" in message
    assert why in message


def test_an_ies_texture_without_a_profile_is_named_and_lights_as_cycles(empty_scene, warnings):
    # An IES Texture with no text or file: Cycles' node gives 100 x Strength there
    # (tests/blender/test_ies.py renders a missing file against Cycles); Whitted folds it
    # into the lamp's colour and names the node.
    _, tree, emission = lamp_tree(empty_scene)
    ies = tree.nodes.new("ShaderNodeTexIES")
    emission.inputs["Strength"].default_value = 0.5
    tree.links.new(ies.outputs["Fac"], emission.inputs["Strength"])
    (light,) = convert(warnings)
    assert light.program is None
    assert light.color == pytest.approx((1000.0 * 100.0 / (4.0 * math.pi),) * 3)
    assert any("no IES text" in w and "light 'Light'" in w for w in warnings)
