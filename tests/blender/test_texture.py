"""Textures: image pixels in linear colour, packed and missing images, UV maps, and
renders of image, checker and alpha-cut-out materials with analytic pixels.

The render scenes are lit by one sun of strength pi straight down, so a
Lambertian surface of albedo kd facing it has radiance kd * E / pi = kd, and
seen by an orthographic camera looking down that fits the 2 x 2 plane at the
origin exactly: pixel (row, column) of an 8 x 8 render shows UV
((column + 0.5) / 8, (row + 0.5) / 8).
"""

import math
import os

import bpy
import numpy as np
import pytest
from exported import exported_meshes
from whitted.export.material import convert_material
from whitted.export.texture import MISSING_COLOR, image_pixels
from whitted_tools.material_scenes import top_camera

SIZE = 8  # render width and height in pixels
# Texels of a 2 x 2 test image, rows bottom to top, straight RGBA.
TEXELS = np.array(
    [
        [[0.8, 0.2, 0.1, 1.0], [0.1, 0.6, 0.2, 1.0]],
        [[0.2, 0.3, 0.9, 1.0], [0.5, 0.5, 0.5, 1.0]],
    ],
    dtype=np.float32,
)


def srgb_to_linear(values):
    # The sRGB EOTF (IEC 61966-2-1), written out again so the test does not reuse
    # the exporter's code.
    values = np.asarray(values, dtype=np.float64)
    return np.where(values <= 0.04045, values / 12.92, ((values + 0.055) / 1.055) ** 2.4)


def new_image(name, texels):
    """A generated (unsaved) byte image holding `texels`, float32[H,W,4]."""
    height, width, _ = texels.shape
    image = bpy.data.images.new(name, width, height, alpha=True)
    image.pixels.foreach_set(texels.reshape(-1))
    return image


def saved_png(image, path):
    """`image` written as a PNG at `path` and loaded back from the file."""
    image.filepath_raw = str(path)
    image.file_format = "PNG"
    image.save()
    return bpy.data.images.load(str(path))


def missing_image(path):
    """An image datablock whose file does not exist (as after moving a project)."""
    image = bpy.data.images.new(path.name, 4, 4)
    image.source = "FILE"
    image.filepath = str(path)
    return image


def stored_values(image):
    width, height = image.size
    flat = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(flat)
    return flat.reshape(height, width, 4)


@pytest.fixture
def lit_scene(empty_scene):
    """Sun of strength pi straight down, orthographic camera fitting the 2 x 2 plane
    at the origin, black world, one sample per pixel."""
    scene = empty_scene
    scene.world = None
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 1
    top_camera(scene, 2.0)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = math.pi
    sun.angle = 0.0
    scene.collection.objects.link(bpy.data.objects.new("Sun", sun))
    return scene


def add_plane(scene, name, material, size=2.0, height=0.0):
    bpy.ops.mesh.primitive_plane_add(size=size, location=(0.0, 0.0, height))
    plane = bpy.context.active_object
    plane.name = name
    plane.data.materials.append(material)
    return plane


def diffuse_material(name, color=(0.8, 0.8, 0.8, 1.0)):
    """A material whose surface is a Diffuse BSDF; returns (material, the BSDF)."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = color
    tree.links.new(diffuse.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    return material, diffuse


def image_material(name, image, interpolation="Closest"):
    material, diffuse = diffuse_material(name)
    tree = material.node_tree
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = interpolation
    tree.links.new(texture.outputs["Color"], diffuse.inputs["Color"])
    return material


def expected_quadrants(texels):
    """The 8 x 8 image of a 2 x 2 texture sampled with Closest at pixel centres."""
    return np.repeat(np.repeat(texels, SIZE // 2, axis=0), SIZE // 2, axis=1)


def test_srgb_png_is_read_as_linear(tmp_path, warnings):
    image = saved_png(new_image("colours", TEXELS), tmp_path / "colours.png")
    assert image.colorspace_settings.name == "sRGB"
    stored = stored_values(image)
    # Blender hands a byte image's values over as stored (8-bit sRGB codes / 255).
    np.testing.assert_allclose(stored, TEXELS, atol=1.0 / 255.0)
    pixels = image_pixels(image, warnings)
    np.testing.assert_allclose(pixels[..., :3], srgb_to_linear(stored[..., :3]), rtol=1e-5)
    np.testing.assert_array_equal(pixels[..., 3], stored[..., 3])
    assert warnings == []


def test_srgb_conversion_gives_the_same_bits_every_export(warnings):
    # Every byte code, in an image whose pixels numpy copies to arrays that lie in
    # memory differently from export to export: the conversion must not depend on
    # where (numpy's float32 power took SIMD or scalar paths by alignment, and two
    # exports of one image differed in the last bit; test_sync caught it).
    codes = np.arange(256, dtype=np.float32) / 255.0
    texels = np.stack([codes, codes[::-1], np.roll(codes, 7), np.ones(256, np.float32)], -1)
    image = bpy.data.images.new("codes", 16, 16)
    image.pixels.foreach_set(texels.ravel())
    first = image_pixels(image, warnings)
    for shift in range(1, 8):
        spacer = np.empty(shift, dtype=np.float32)  # moves the next allocations
        assert np.array_equal(image_pixels(image, warnings), first), shift
        del spacer
    # Each code's value is the EOTF computed in double, then rounded once.
    stored = stored_values(image)[..., :3].astype(np.float64)
    np.testing.assert_array_equal(first[..., :3], srgb_to_linear(stored).astype(np.float32))
    assert warnings == []


def test_non_color_image_is_read_as_is(tmp_path, warnings):
    image = saved_png(new_image("data", TEXELS), tmp_path / "data.png")
    image.colorspace_settings.name = "Non-Color"
    np.testing.assert_array_equal(image_pixels(image, warnings), stored_values(image))


def _float_image(name, pixels):
    height, width, _ = pixels.shape
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    image.pixels.foreach_set(pixels.reshape(-1))
    return image


def test_broken_texels_become_0_and_only_visible_ones_are_reported(warnings):
    pixels = np.ones((8, 16, 4), dtype=np.float32)
    pixels[1, 2, 0] = -0.003  # an HDR tool's ringing: set to 0, not reported
    pixels[2, 3, 1] = -0.004
    read = image_pixels(_float_image("ringing", pixels), warnings)
    assert read[1, 2, 0] == 0.0 and read[2, 3, 1] == 0.0 and warnings == []
    pixels[3, 4, :3] = -4.0  # a broken texel, reported
    pixels[5, 6, 2] = np.nan
    pixels[6, 7, 0] = np.inf
    read = image_pixels(_float_image("broken", pixels), warnings)
    assert np.isfinite(read).all() and read.min() == 0.0
    assert read[3, 4, :3].tolist() == [0.0, 0.0, 0.0]
    assert len(warnings) == 1 and "image 'broken' has 3 texel(s)" in warnings[0]


def test_blenders_studio_hdris_read_without_a_warning(warnings):
    # Each holds tiny negative texels (forest.exr 784, the most negative -0.0016).
    folder = bpy.utils.system_resource("DATAFILES", path="studiolights/world")
    image = bpy.data.images.load(os.path.join(folder, "forest.exr"))
    read = image_pixels(image, warnings)
    assert read[..., :3].min() == 0.0 and warnings == []


def test_missing_image_is_magenta_and_reported(tmp_path, warnings):
    image = missing_image(tmp_path / "gone.png")
    pixels = image_pixels(image, warnings)
    np.testing.assert_array_equal(pixels.reshape(-1, 4), [MISSING_COLOR])
    assert len(warnings) == 1
    assert "image 'gone.png'" in warnings[0]
    assert "magenta" in warnings[0]


def test_mapped_box_projected_image_is_not_reported(warnings):
    # glTF's KHR_texture_transform imports as a Mapping node into the Image Texture's
    # Vector: the shader program evaluates it, and every projection, so nothing is
    # reported (it was: "coordinates from 'Mapping' are not supported").
    material = image_material("Mapped", new_image("cells", TEXELS))
    tree = material.node_tree
    texture = tree.nodes["Image Texture"]
    texture.projection = "BOX"
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Location"].default_value = (0.5, 0.0, 0.0)
    tree.links.new(tree.nodes.new("ShaderNodeUVMap").outputs["UV"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    exported = convert_material(material, warnings)
    assert exported.program is not None
    assert warnings == []


def test_image_texture_renders_its_linear_colours(lit_scene, tmp_path, render_pixels):
    image = saved_png(new_image("colours", TEXELS), tmp_path / "colours.png")
    add_plane(lit_scene, "Plane", image_material("Photo", image))
    pixels = render_pixels(lit_scene)
    expected = srgb_to_linear(expected_quadrants(stored_values(image))[..., :3])
    np.testing.assert_allclose(pixels[..., :3], expected, rtol=1e-4, atol=1e-5)


def test_packed_image_renders_without_its_file(lit_scene, tmp_path, render_pixels):
    path = tmp_path / "packed.png"
    image = saved_png(new_image("packed", TEXELS), path)
    stored = stored_values(image)
    image.pack()
    path.unlink()
    image.reload()  # from the packed file: the one on disk is gone
    add_plane(lit_scene, "Plane", image_material("Packed", image))
    pixels = render_pixels(lit_scene)
    expected = srgb_to_linear(expected_quadrants(stored)[..., :3])
    np.testing.assert_allclose(pixels[..., :3], expected, rtol=1e-4, atol=1e-5)


def test_missing_image_renders_magenta(lit_scene, tmp_path, render_pixels):
    image = missing_image(tmp_path / "gone.png")
    add_plane(lit_scene, "Plane", image_material("Missing", image))
    pixels = render_pixels(lit_scene)
    np.testing.assert_allclose(pixels[..., :3], np.broadcast_to((1.0, 0.0, 1.0), (8, 8, 3)))


def checker_color(point, scale):
    """Blender's checker (svm_checker): color1 where the parities of the scaled
    coordinates' cells agree, as in intern/cycles/kernel/svm/checker.h."""
    cells = [abs(math.floor((c * scale + 0.000001) * 0.999999)) for c in point]
    return 1 if (cells[0] % 2 == cells[1] % 2) == (cells[2] % 2 == 1) else 2


@pytest.mark.parametrize("coordinates", ["Generated", "UV"])
def test_checker_texture_renders_both_colours_in_place(lit_scene, render_pixels, coordinates):
    material, diffuse = diffuse_material("Checker")
    tree = material.node_tree
    checker = tree.nodes.new("ShaderNodeTexChecker")
    colors = {1: (0.9, 0.1, 0.1), 2: (0.1, 0.1, 0.9)}
    checker.inputs["Color1"].default_value = (*colors[1], 1.0)
    checker.inputs["Color2"].default_value = (*colors[2], 1.0)
    checker.inputs["Scale"].default_value = 2.0
    if coordinates == "UV":
        coords = tree.nodes.new("ShaderNodeTexCoord")
        tree.links.new(coords.outputs["UV"], checker.inputs["Vector"])
    tree.links.new(checker.outputs["Color"], diffuse.inputs["Color"])
    add_plane(lit_scene, "Plane", material)
    pixels = render_pixels(lit_scene)
    for row in range(SIZE):
        for column in range(SIZE):
            u, v = (column + 0.5) / SIZE, (row + 0.5) / SIZE
            # Generated coordinates span the bounds; a flat plane's Z is the middle.
            # UV coordinates have Z = 0. On this plane, both have X = u and Y = v.
            point = (u, v, 0.5 if coordinates == "Generated" else 0.0)
            expected = colors[checker_color(point, 2.0)]
            np.testing.assert_allclose(pixels[row, column, :3], expected, rtol=1e-5)


def test_named_uv_map_is_exported(lit_scene, warnings):
    plane = add_plane(lit_scene, "Plane", diffuse_material("Decal")[0])
    mesh = plane.data
    flipped = mesh.uv_layers.new(name="Flipped")
    uvs = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    mesh.uv_layers[0].data.foreach_get("uv", uvs)
    flipped.data.foreach_set("uv", 1.0 - uvs)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    by_map = {
        uv_map: exported_meshes(depsgraph, warnings, {"Decal": uv_map}).meshes[0].uvs
        for uv_map in ("", "Flipped", "Missing")
    }
    np.testing.assert_allclose(by_map["Flipped"], 1.0 - by_map[""])
    np.testing.assert_array_equal(by_map["Missing"], by_map[""])
    assert warnings == [
        f"Whitted: object '{plane.name}' has no UV map 'Missing'; using the active render one"
    ]
    # Without a textured material, no UVs are exported.
    assert exported_meshes(depsgraph, warnings).meshes[0].uvs is None


def cut_out_scene(scene, card_material):
    """A white floor under a card at height 1 that fills the camera's view."""
    floor, _ = diffuse_material("Floor", (0.8, 0.8, 0.8, 1.0))
    add_plane(scene, "Floor", floor, size=4.0)
    add_plane(scene, "Card", card_material, height=1.0)


CARD = (0.7, 0.2, 0.1)


def test_alpha_texture_cuts_out_for_camera_and_shadow_rays(lit_scene, render_pixels):
    material = bpy.data.materials.new("Card")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    principled = tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (*CARD, 1.0)
    # No highlight: the card is Lambertian.
    specular = next(n for n in ("Specular IOR Level", "Specular") if n in principled.inputs)
    principled.inputs[specular].default_value = 0.0
    # Left half transparent, right half opaque.
    texels = np.array([[[1.0, 1.0, 1.0, 0.0], [1.0, 1.0, 1.0, 1.0]]], dtype=np.float32)
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = new_image("mask", texels)
    texture.interpolation = "Closest"
    tree.links.new(texture.outputs["Alpha"], principled.inputs["Alpha"])
    cut_out_scene(lit_scene, material)
    pixels = render_pixels(lit_scene)
    # Through the hole: the floor, lit, because the sun's feelers pass the hole too.
    np.testing.assert_allclose(pixels[:, : SIZE // 2, :3], np.full((8, 4, 3), 0.8), rtol=1e-4)
    np.testing.assert_allclose(pixels[:, SIZE // 2 :, :3], np.broadcast_to(CARD, (8, 4, 3)))
    np.testing.assert_allclose(pixels[..., 3], 1.0)


def test_half_transparent_card_shows_half_of_the_half_shadowed_floor(lit_scene, render_pixels):
    material, diffuse = diffuse_material("Card", (*CARD, 1.0))
    tree = material.node_tree
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = 0.5
    transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
    tree.links.new(transparent.outputs[0], mix.inputs[1])
    tree.links.new(diffuse.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    cut_out_scene(lit_scene, material)
    pixels = render_pixels(lit_scene)
    # Half the card, plus half of the floor that gets half the sun through the card.
    expected = 0.5 * np.array(CARD) + 0.5 * 0.5 * 0.8
    np.testing.assert_allclose(pixels[..., :3], np.broadcast_to(expected, (8, 8, 3)), rtol=1e-4)
