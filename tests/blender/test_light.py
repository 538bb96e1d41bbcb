"""Light export: Cycles' units, directions, area sizes, instances."""

import math

import bpy
import pytest
from whitted.export.light import AREA_SAMPLES, convert_lights


def add_light(scene, light_type, name="Light", location=(0.0, 0.0, 0.0), **light_settings):
    light = bpy.data.lights.new(name, light_type)
    for key, value in light_settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def convert(warnings):
    return convert_lights(bpy.context.evaluated_depsgraph_get(), warnings)


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
    # World size 4 x 1.5 = 6 m^2; L = P / (4 A) = 120 / 24 = 5 W/(m^2 sr).
    assert light.size == pytest.approx((4.0, 1.5))
    assert light.color == pytest.approx((5.0, 5.0, 5.0))
    assert light.shape == "RECTANGLE"
    assert light.axis_u == pytest.approx((1.0, 0.0, 0.0))
    assert light.axis_v == pytest.approx((0.0, 1.0, 0.0))
    assert light.direction == pytest.approx((0.0, 0.0, -1.0))
    assert light.samples == AREA_SAMPLES


def test_area_disk_radiance(empty_scene, warnings):
    add_light(empty_scene, "AREA", energy=100.0, shape="DISK", size=2.0)
    (light,) = convert(warnings)
    # A disk of diameter 2: A = pi/4 * 2 * 2 = pi.
    assert light.shape == "ELLIPSE"
    assert light.size == pytest.approx((2.0, 2.0))
    assert light.color == pytest.approx((100.0 / (4.0 * math.pi),) * 3)


def test_area_square_uses_size_for_both_axes(empty_scene, warnings):
    add_light(empty_scene, "AREA", energy=16.0, shape="SQUARE", size=2.0, size_y=9.0)
    (light,) = convert(warnings)
    assert light.size == pytest.approx((2.0, 2.0))
    assert light.color == pytest.approx((1.0, 1.0, 1.0))


def test_shadowless_light(empty_scene, warnings):
    add_light(empty_scene, "POINT", use_shadow=False)
    (light,) = convert(warnings)
    assert light.cast_shadows is False


def test_exposure_and_normalize_when_blender_has_them(empty_scene, warnings):
    light_data = bpy.data.lights.new("probe", "AREA")
    if not hasattr(light_data, "exposure"):
        pytest.skip(f"Blender {bpy.app.version_string} lights have no exposure/normalize")
    add_light(empty_scene, "AREA", energy=40.0, size=2.0, exposure=1.0, normalize=False)
    (light,) = convert(warnings)
    # x 2^1 for the exposure; not normalised: L = P / 4 whatever the area.
    assert light.color == pytest.approx((20.0, 20.0, 20.0))


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
