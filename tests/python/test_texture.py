"""Textures, UVs, alpha, visibility and border through the bindings, without Blender."""

import numpy as np
import pytest
import whitted_native as wn
from test_scene import finish, looking_down, quad

GLOW = dict(diffuse=(0, 0, 0), ambient=0.0)


def plane_with_uvs(scene, material):
    positions, triangles = quad(-1, 1, -1, 1, 0)
    corner_uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]], np.float32)
    scene.set_mesh("plane", positions, triangles, uvs=corner_uvs.reshape(2, 3, 2))
    scene.set_material("m", material)
    scene.set_instance("plane", "plane", np.eye(4), ["m"])


def test_image_texture_tints_the_diffuse_colour_by_uv():
    scene = wn.Scene()
    # A 2x1 image: red on the left half, green on the right.
    pixels = np.array([[[1, 0, 0, 1], [0, 1, 0, 1]]], np.float32)
    scene.set_texture("img", wn.ImageTexture(pixels, interpolation=wn.Interpolation.CLOSEST))
    plane_with_uvs(scene, wn.Material(diffuse=(1, 1, 1), ambient=1.0, diffuse_texture="img"))
    scene.ambient = (1.0, 1.0, 1.0)  # ambient * kd: the texture's colour exactly
    scene.camera = looking_down(5.0, 0.2)  # the window spans the plane, +-1
    image = finish(wn.RenderJob(scene, wn.Settings(width=4, height=4)))
    np.testing.assert_allclose(image[:, :2, :3], [[[1, 0, 0]] * 2] * 4)
    np.testing.assert_allclose(image[:, 2:, :3], [[[0, 1, 0]] * 2] * 4)


def test_udim_texture_shows_each_tile_where_the_uvs_fall():
    scene = wn.Scene()
    # Tile 1001 red, 1002 green; UVs (3u, v) across the plane: tile 1003 does not exist.
    tiles = [(1002, np.array([[[0, 1, 0, 1]]], np.float32))]
    tiles.append((1001, np.array([[[1, 0, 0, 1]]], np.float32)))
    scene.set_texture("udim", wn.UdimTexture(tiles, interpolation=wn.Interpolation.CLOSEST))
    positions, triangles = quad(-1, 1, -1, 1, 0)
    corner_uvs = np.array([[0, 0], [3, 0], [3, 1], [0, 0], [3, 1], [0, 1]], np.float32)
    scene.set_mesh("plane", positions, triangles, uvs=corner_uvs.reshape(2, 3, 2))
    scene.set_material("m", wn.Material(diffuse=(1, 1, 1), ambient=1.0, diffuse_texture="udim"))
    scene.set_instance("plane", "plane", np.eye(4), ["m"])
    scene.ambient = (1.0, 1.0, 1.0)
    scene.camera = looking_down(5.0, 0.2)
    image = finish(wn.RenderJob(scene, wn.Settings(width=6, height=2)))
    np.testing.assert_allclose(image[:, :2, :3], [[[1, 0, 0]] * 2] * 2)
    np.testing.assert_allclose(image[:, 2:4, :3], [[[0, 1, 0]] * 2] * 2)
    np.testing.assert_allclose(image[:, 4:, :3], [[[1, 0, 1]] * 2] * 2)  # magenta, as Cycles
    with pytest.raises(ValueError, match="twice"):
        wn.UdimTexture(tiles + tiles[:1])
    with pytest.raises(ValueError, match="1001 to 2000"):
        wn.UdimTexture([(1000, tiles[0][1])])


@pytest.mark.parametrize("mode, bits", [("L", 8), ("RGB", 8), ("RGBA", 8), ("I;16", 16)])
def test_decode_image_reads_pillows_png_bottom_row_first(mode, bits, tmp_path):
    from PIL import Image

    rng = np.random.default_rng(3)
    full = 2**bits - 1
    channels = {"L": 1, "RGB": 3, "RGBA": 4, "I;16": 1}[mode]
    codes = rng.integers(0, full + 1, size=(3, 5, channels))
    dtype = np.uint16 if bits == 16 else np.uint8
    array = codes.astype(dtype)
    Image.fromarray(array[..., 0] if channels == 1 else array).save(tmp_path / "t.png")
    decoded = wn.decode_image((tmp_path / "t.png").read_bytes())
    expected = np.ones((3, 5, 4), np.float32)
    expected[..., :3] = codes[..., :3] if channels >= 3 else codes[..., :1]
    expected[..., :3] *= np.float32(1.0 / full)
    if channels == 4:
        expected[..., 3] = codes[..., 3] * np.float32(1.0 / full)
    np.testing.assert_array_equal(decoded, expected[::-1])  # PNG rows run top to bottom


def test_alpha_texture_cuts_out_and_a_missing_texture_is_an_error():
    scene = wn.Scene()
    pixels = np.array([[[1, 1, 1, 0], [1, 1, 1, 1]]], np.float32)  # left half transparent
    scene.set_texture("mask", wn.ImageTexture(pixels, interpolation=wn.Interpolation.CLOSEST))
    plane_with_uvs(scene, wn.Material(**GLOW, emission=(1, 1, 1), alpha_texture="mask"))
    scene.background = (0.0, 0.0, 1.0)
    scene.camera = looking_down(5.0, 0.2)  # the window spans the plane, +-1
    image = finish(wn.RenderJob(scene, wn.Settings(width=4, height=2)))
    np.testing.assert_allclose(image[:, :2, :3], [[[0, 0, 1]] * 2] * 2)
    np.testing.assert_allclose(image[:, 2:, :3], [[[1, 1, 1]] * 2] * 2)
    scene.set_material("m", wn.Material(diffuse_texture="nothing"))
    with pytest.raises(ValueError, match="missing texture"):
        wn.RenderJob(scene, wn.Settings(width=4, height=2))
    with pytest.raises(ValueError, match="shape"):
        wn.ImageTexture(np.zeros((2, 2, 3), np.float32))


def test_instance_visibility_flags_and_holdout():
    scene = wn.Scene()
    scene.set_mesh("plane", *quad(-1, 1, -1, 1, 0))
    scene.set_material("glow", wn.Material(**GLOW, emission=(1, 1, 1)))
    scene.background = (0.5, 0.5, 0.5)
    scene.camera = looking_down(5.0, 0.1)  # inside the plane
    settings = wn.Settings(width=2, height=2, transparent_background=True)
    hidden = wn.RayVisibility.SHADOW | wn.RayVisibility.REFLECTION
    scene.set_instance("plane", "plane", np.eye(4), ["glow"], visibility=hidden)
    image = finish(wn.RenderJob(scene, settings))
    np.testing.assert_array_equal(image, 0.0)  # unseen plane, transparent film
    scene.set_instance("plane", "plane", np.eye(4), ["glow"], holdout=True)
    image = finish(wn.RenderJob(scene, wn.Settings(width=2, height=2)))
    np.testing.assert_array_equal(image, 0.0)


def test_border_traces_only_its_pixels():
    scene = wn.Scene()
    scene.background = (1.0, 1.0, 1.0)
    job = wn.RenderJob(scene, wn.Settings(width=8, height=6, border=(2, 1, 5, 4)))
    image = finish(job)
    assert job.stats()["rays"]["camera"] == 9
    assert image[1:4, 2:5].min() == 1.0
    assert image.sum() == 9 * 4


def test_sized_light_makes_a_penumbra():
    scene = wn.Scene()
    scene.set_mesh("floor", *quad(-10, 10, -10, 10, 0))
    scene.set_mesh("blocker", *quad(-10, 0, -10, 10, 1))  # covers x < 0
    scene.set_material("white", wn.Material(ambient=0.0))
    scene.set_instance("floor", "floor", np.eye(4), ["white"])
    scene.set_instance("blocker", "blocker", np.eye(4), ["white"])
    light = wn.Light(color=(10, 10, 10), position=(0, 0, 2), radius=0.5, samples=8)
    assert light.radius == 0.5
    scene.set_light("l", light)
    scene.camera = looking_down(0.5, 1.0)  # between floor and blocker
    scene.camera.clip_start = 0.01
    row = finish(wn.RenderJob(scene, wn.Settings(width=64, height=1)))[0, :, 0]
    # Hard edge at x = 0 for a point light; with radius the light fades in over a band.
    partial = (row > 0.05 * row.max()) & (row < 0.95 * row.max())
    assert partial.sum() >= 4
    # Across the penumbra (x < 0.5 on the floor, the first 48 pixels) the light fades in;
    # within a step of the 8x8 strata it dims only slightly with distance.
    assert row[0] == 0.0
    assert np.all(np.diff(row[:48]) >= -0.01 * row.max())
