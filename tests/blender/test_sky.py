"""The Sky Texture node (issue 47, part 3): every model Blender offers, in a world seen
by an equirectangular camera, against Cycles rendering the same world, and the world's
sun disc exposed for the world light (WorldData.sun)."""

import math

import bpy
import numpy as np
import pytest
from whitted.export.camera import panorama_settings
from whitted.export.world import convert_world
from whitted_tools.cycles_scenes import render_rgba, set_cycles_direct_light

V5 = bpy.app.version >= (5, 0, 0)
# Blender's models by version; the scattering model is NISHITA before 5.0.
SCATTERING = "SINGLE_SCATTERING" if V5 else "NISHITA"
MODELS = ("PREETHAM", "HOSEK_WILKIE", SCATTERING) + (("MULTIPLE_SCATTERING",) if V5 else ())
ELEVATIONS = (2.0, 15.0, 60.0)
WIDTH, HEIGHT = 128, 64


def sky_world(scene, model, elevation, **settings):
    """A world whose Background is a Sky Texture of `model`, the sun at `elevation`
    degrees (Sun Elevation, or Sun Direction for Preetham and Hosek/Wilkie) and 30
    degrees of rotation; `settings` set on the node."""
    world = bpy.data.worlds.new("Sky")
    if not V5:
        world.use_nodes = True
    scene.world = world
    tree = world.node_tree
    sky = tree.nodes.new("ShaderNodeTexSky")
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    sky.sky_type = model
    rotation = math.radians(30.0)
    sky.sun_elevation = math.radians(elevation)
    sky.sun_rotation = rotation
    e = math.radians(elevation)
    sky.sun_direction = (math.cos(e) * math.sin(rotation), math.cos(e) * math.cos(rotation),
                         math.sin(e))  # fmt: skip
    for name, value in settings.items():
        setattr(sky, name, value)
    return world, sky


def panorama(scene):
    """An equirectangular camera at the origin seeing every direction (the centre of the
    image towards +X), WIDTH x HEIGHT, the world opaque."""
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.rotation_euler = (math.radians(90.0), 0.0, math.radians(-90.0))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.data.type = "PANO"
    panorama_settings(camera.data).panorama_type = "EQUIRECTANGULAR"
    set_cycles_direct_light(scene, samples=1)  # one ray at each pixel's centre, as ours
    scene.whitted.aa_samples = 1


def luminance(image):
    return image[..., :3] @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def figures(whitted, cycles):
    """(summed luminance ratio, median and 95th percentile of the per-pixel relative
    difference in luminance, over the pixels Cycles sees brighter than 1e-3 of its
    brightest)."""
    ours, theirs = luminance(whitted), luminance(cycles)
    ratio = float(ours.sum() / theirs.sum())
    lit = theirs > 1e-3 * theirs.max()
    relative = np.abs(ours - theirs)[lit] / theirs[lit]
    return ratio, float(np.median(relative)), float(np.percentile(relative, 95))


def render_both(scene, tmp_path):
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    assert np.all(np.isfinite(whitted)) and whitted[..., :3].min() >= 0.0
    return whitted, cycles


# The figures measured (Blender 3.4.1 and bpy 5.0.1, 128 x 64, disc off; the table in
# docs/SUPPORT.md): Preetham the same pixels; Nishita (3.4) and Single Scattering (5.0),
# their sky baked on Cycles' texels and read as its kernel reads them, per pixel within
# 2.5e-4 of Cycles at 1024 x 512 (summed luminance within 1e-4); Multiple Scattering
# (5.0) likewise, 95th percentile 4e-5, all within 0.4%; Hosek/Wilkie from the authors'
# RGB dataset (Cycles cooks their XYZ one, which no package here ships; the two fits
# differ) at 2, 15, 60 degrees: summed luminance 0.9825, 0.9958, 0.9973, per-pixel
# median 0.024, 0.005, 0.005, 95th percentile 0.043, 0.022, 0.007 (3.4.1): looser
# than Preetham's bounds at 2 degrees, where the fits differ most near the horizon.
BOUNDS = {  # model: (summed luminance, median per-pixel, 95th percentile per-pixel)
    "PREETHAM": (0.01, 0.01, 0.03),
    "NISHITA": (0.002, 0.001, 0.002),
    "SINGLE_SCATTERING": (0.002, 0.001, 0.002),
    "HOSEK_WILKIE": (0.02, 0.03, 0.05),
    "MULTIPLE_SCATTERING": (0.002, 0.001, 0.002),
}


@pytest.mark.parametrize("elevation", ELEVATIONS)
@pytest.mark.parametrize("model", MODELS)
def test_each_sky_model_as_cycles(empty_scene, tmp_path, warnings, model, elevation):
    scene = empty_scene
    panorama(scene)
    world, _ = sky_world(scene, model, elevation, sun_disc=False)
    exported = convert_world(world, 1.0, warnings)
    assert exported.program is not None
    assert not warnings
    whitted, cycles = render_both(scene, tmp_path)
    ratio, median, high = figures(whitted, cycles)
    print(f"\n{model} at {elevation} degrees: luminance ratio {ratio:.4f}, per-pixel "
          f"median {median:.4f}, 95th percentile {high:.4f}")  # fmt: skip
    total, typical, worst = BOUNDS[model]
    assert abs(ratio - 1.0) < total
    assert median < typical and high < worst


def rotated_about_z(v, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def test_the_sun_disc_as_cycles(empty_scene, tmp_path, warnings):
    # A large disc (8 degrees: several pixels) so that pixel centres sample it alike;
    # the node's own Texture Mapping turns the sky 40 degrees about Z (the Sky node's
    # Vector socket is unavailable in Blender 3.4 and 5.0: its mapping is the only one).
    scene = empty_scene
    panorama(scene)
    world, sky = sky_world(scene, SCATTERING, 20.0, sun_size=math.radians(8.0))
    sky.texture_mapping.rotation = (0.0, 0.0, math.radians(40.0))
    whitted, cycles = render_both(scene, tmp_path)
    ours, theirs = luminance(whitted), luminance(cycles)
    disc = theirs > 100.0 * np.median(theirs)
    assert disc.sum() >= 4  # the disc covers pixels
    assert np.array_equal(ours > 100.0 * np.median(ours), disc)
    ratio = ours[disc].sum() / theirs[disc].sum()
    sky_ratio, median, high = figures(whitted * ~disc[..., None], cycles * ~disc[..., None])
    print(
        f"\nsun disc ({disc.sum()} pixels): luminance ratio {ratio:.4f}; the sky around it "
        f"{sky_ratio:.4f}, per-pixel median {median:.4f}, 95th percentile {high:.4f}"
    )
    assert abs(ratio - 1.0) < 0.02 and abs(sky_ratio - 1.0) < 0.01
    # Its direction, exposed for the world light: the sun of Sun Elevation and Rotation
    # in the sky's space, the mapping's rotation undone.
    sun = convert_world(world, 1.0, warnings).sun
    e, r = sky.sun_elevation, sky.sun_rotation
    in_sky = (math.cos(e) * math.sin(r), math.cos(e) * math.cos(r), math.sin(e))
    assert sun[0] == pytest.approx(rotated_about_z(in_sky, -40.0), abs=1e-5)
    assert sun[1] == pytest.approx(math.radians(8.0))


@pytest.mark.parametrize(
    "settings",
    [{"sun_disc": False}, {"sun_elevation": math.radians(-10.0)}, {"sun_intensity": 0.0}],
)
def test_no_sun_without_a_visible_disc(empty_scene, warnings, settings):
    world, _ = sky_world(empty_scene, SCATTERING, 20.0, **settings)
    assert convert_world(world, 1.0, warnings).sun is None


def test_a_sky_mixed_out_gives_no_sun(empty_scene, warnings):
    world, sky = sky_world(empty_scene, SCATTERING, 20.0)
    tree = world.node_tree
    mix = tree.nodes.new("ShaderNodeMixRGB")
    mix.inputs["Fac"].default_value = 1.0
    mix.inputs["Color2"].default_value = (0.2, 0.3, 0.4, 1.0)
    tree.links.new(sky.outputs["Color"], mix.inputs["Color1"])
    tree.links.new(mix.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    assert convert_world(world, 1.0, warnings).sun is None


@pytest.mark.parametrize("model", MODELS)
def test_finite_and_non_negative_everywhere(empty_scene, native, warnings, model):
    # Sun below, at and above the horizon; every direction of a grid of 6-degree steps
    # (the horizon and the poles among them). Each call copies the op's table (Nishita's is
    # large): on a 3-degree grid this test was the suite's slowest, 109 s of a loaded
    # 3.4 run's 1,438 s (session 36); this grid has a quarter of the directions.
    from whitted.export.nodes import ops

    for elevation in (-30.0, -1.0, 0.0, 0.3, 45.0, 90.0):
        world, _ = sky_world(empty_scene, model, elevation)
        exported = convert_world(world, 1.0, warnings)
        code = exported.program.code
        row = next(r for r in code if r[0] == ops.SKY)
        table = exported.program.constants[row[7] :].tolist()
        lat, lon = np.meshgrid(np.linspace(-90, 90, 31), np.linspace(-180, 180, 31))
        lat, lon = np.radians(lat).ravel(), np.radians(lon).ravel()
        directions = np.stack(
            [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=1
        )
        for d in directions:
            value = native.fold_op(ops.SKY, row[1], [(*d, 0.0)], table)
            assert all(math.isfinite(x) and x >= 0.0 for x in value), (elevation, d, value)


@pytest.mark.parametrize("texture", ["ShaderNodeTexNoise", "ShaderNodeTexGradient"])
def test_a_procedural_world_is_cycles(texture, empty_scene, tmp_path):
    # A world whose Background colour is a procedural texture of its default coordinates
    # (Generated: the ray's direction in the world, as Cycles gives a world), seen in
    # every direction: the world's program runs the surfaces' ops.
    world = bpy.data.worlds.new("Procedural")
    if not V5:
        world.use_nodes = True
    empty_scene.world = world
    tree = world.node_tree
    node = tree.nodes.new(texture)
    if texture == "ShaderNodeTexGradient":
        node.gradient_type = "QUADRATIC"  # x^2 of the direction, 0 where x < 0
    tree.links.new(node.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    panorama(empty_scene)
    whitted, cycles = render_both(empty_scene, tmp_path)
    ratio, median, p95 = figures(whitted, cycles)
    print(f"\n{texture} world: ratio {ratio:.4f}, per pixel median {median:.2e}, 95% {p95:.2e}")
    assert abs(ratio - 1.0) < 1e-3
    assert p95 < 1e-3
