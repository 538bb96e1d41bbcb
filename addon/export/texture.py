"""Textures: what a material's texture nodes ask for, and the images' linear pixels.

The node mapping (material.py) records each texture as a small spec without
reading any pixels; `convert_textures` then reads every image once per render
into float32 numpy arrays of linear RGBA, rows bottom to top (Blender's
`Image.pixels` order, which the tracer uses as is): one for a plain image, one
per tile for a UDIM image.
"""

from dataclasses import dataclass

import bpy
import numpy as np

from ..native import load_native
from .nodes import warn

Color = tuple[float, float, float]

# What Cycles shows for an image it cannot load.
MISSING_COLOR = (1.0, 0.0, 1.0, 1.0)

# Blender's texture settings -> the tracer's; others fall back with a warning.
INTERPOLATIONS = {"Linear": "LINEAR", "Closest": "CLOSEST"}
EXTENSIONS = {"REPEAT": "REPEAT", "CLIP": "CLIP", "EXTEND": "EXTEND"}

# Colour spaces whose stored values are already linear (or are data, not colour).
LINEAR_SPACES = {"Linear", "Linear Rec.709", "Non-Color", "Raw"}


@dataclass(frozen=True)
class ImageTextureSpec:
    image: object  # bpy.types.Image (the original, not the evaluated copy)
    interpolation: str  # LINEAR | CLOSEST
    extension: str  # REPEAT | CLIP | EXTEND
    coordinates: str  # UV | GENERATED | OBJECT
    uv_map: str  # the UV map for UV coordinates; "" means the active render map

    @property
    def name(self):
        # One native texture per image and sampling settings; pixels are still read
        # once per image (convert_textures).
        return (
            f"image:{self.image.name_full}:{self.interpolation}:{self.extension}:{self.coordinates}"
        )


@dataclass(frozen=True)
class CheckerTextureSpec:
    color1: Color  # linear RGB
    color2: Color
    scale: float  # squares per unit of the coordinates
    coordinates: str  # GENERATED | UV | OBJECT
    uv_map: str

    @property
    def name(self):
        return f"checker:{self.color1}:{self.color2}:{self.scale}:{self.coordinates}"


@dataclass(frozen=True)
class ImageTextureData:
    # (tile number, float32[H,W,4] linear RGBA with straight alpha, rows bottom to top):
    # a plain image's one picture (number 0), or a UDIM image's tiles (udim).
    tiles: tuple
    udim: bool
    interpolation: str
    extension: str
    coordinates: str


def image_texture_spec(node, owner, warnings):
    """An Image Texture node's image and sampling as an ImageTextureSpec on UV
    coordinates, or None when it has no image (the caller then warns and uses the
    input's unlinked value). Its Vector and projection are the shader program's
    (nodes/values.py), which also tells the coordinates of a fixed texture."""
    if node.image is None:
        return None
    where = f"Whitted: {owner}, node '{node.name}'"
    interpolation = INTERPOLATIONS.get(node.interpolation)
    if interpolation is None:
        warn(warnings, f"{where}: {node.interpolation} interpolation is not supported; Linear")
        interpolation = "LINEAR"
    extension = EXTENSIONS.get(node.extension)
    if extension is None:
        warn(warnings, f"{where}: {node.extension} extension is not supported; Repeat")
        extension = "REPEAT"
    return ImageTextureSpec(
        # A material from the depsgraph holds evaluated copies; pixels live in the original.
        image=node.image.original,
        interpolation=interpolation,
        extension=extension,
        coordinates="UV",
        uv_map="",
    )


def convert_textures(specs, warnings, texture_filter="AUTHORED"):
    """Texture name -> ImageTextureData or CheckerTextureSpec (the checker needs no
    data of its own), reading each image's pixels once.

    `texture_filter` (scene.whitted.texture_filter) is AUTHORED, each node's own
    interpolation, or CLOSEST, which overrides them all.
    """
    tiles_by_image = {}
    textures = {}
    for name, spec in specs.items():
        if isinstance(spec, CheckerTextureSpec):
            textures[name] = spec
            continue
        key = spec.image.name_full
        if key not in tiles_by_image:
            tiles_by_image[key] = image_tiles(spec.image, warnings)
        textures[name] = ImageTextureData(
            tiles=tiles_by_image[key],
            udim=spec.image.source == "TILED",
            interpolation=spec.interpolation if texture_filter == "AUTHORED" else texture_filter,
            extension=spec.extension,
            coordinates=spec.coordinates,
        )
    return textures


# The share of an image's mean colour value below which a negative texel is set to 0
# without a report (_sanitise_texels).
NEGLIGIBLE_NEGATIVE = 0.01


def image_tiles(image, warnings):
    """An image's pictures as ImageTextureData.tiles: a plain image's pixels
    (image_pixels) as tile 0, or every tile of a UDIM image (udim_tiles)."""
    if image.source == "TILED":
        return udim_tiles(image, warnings)
    return ((0, image_pixels(image, warnings)),)


def image_pixels(image, warnings):
    """An image's pixels as float32[H,W,4] linear RGBA, rows bottom to top; a UDIM
    image's first tile (what Image.pixels holds).

    A packed image reads from its packed file, like any other. An image that
    cannot be loaded is one magenta pixel, reported by name.
    """
    # `size` loads the image if needed; (0, 0) means Blender could not load it.
    width, height = image.size
    if width == 0 or height == 0:
        warn(
            warnings,
            f"Whitted: image '{image.name}' ({image.filepath or 'no file'}) could not be "
            "loaded; it renders magenta",
        )
        return _missing_pixels()
    flat = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(flat)
    channels = flat.size // (width * height)
    return linear_rgba(image, flat.reshape(height, width, channels), image.is_float, warnings)


def udim_tiles(image, warnings):
    """A UDIM image's tiles as ((number, pixels), ...), in image.tiles' order.

    The first tile is Image.pixels (Blender reads it, whatever its format); the others,
    which Blender does not hand to Python, are read from the image's packed files or
    from its files (the filepath's <UDIM> or <UVTILE> made the tile's) and decoded by
    whitted_native.decode_image. A tile that cannot be read renders magenta, as Cycles
    renders it, reported by name.
    """
    packed = {packed.tile_number: packed.packed_file for packed in image.packed_files}
    tiles = []
    for index, tile in enumerate(image.tiles):
        if index == 0:
            tiles.append((tile.number, image_pixels(image, warnings)))
            continue
        source = "packed" if tile.number in packed else udim_tile_path(image, tile.number)
        try:
            data = packed[tile.number].data if tile.number in packed else _file_bytes(source)
            stored = load_native().decode_image(data)
        except (OSError, ValueError) as error:
            warn(
                warnings,
                f"Whitted: image '{image.name}': UDIM tile {tile.number} ({source}) could "
                f"not be read ({error}); it renders magenta",
            )
            tiles.append((tile.number, _missing_pixels()))
            continue
        # Decoded values are as stored in the file: a 16-bit PNG too, which Blender would
        # hold as float and make linear on load.
        tiles.append((tile.number, linear_rgba(image, stored, False, warnings)))
    return tuple(tiles)


def udim_tile_path(image, number):
    """The absolute path of a UDIM image's tile `number`: its filepath's <UDIM> token as
    the number (1002), or its <UVTILE> token as u<column>_v<row> (u2_v1), both 1-based."""
    path = bpy.path.abspath(image.filepath, library=image.library)
    column, row = (number - 1001) % 10, (number - 1001) // 10
    return path.replace("<UDIM>", str(number)).replace("<UVTILE>", f"u{column + 1}_v{row + 1}")


def _file_bytes(path):
    with open(path, "rb") as file:
        return file.read()


def _missing_pixels():
    return np.array(MISSING_COLOR, dtype=np.float32).reshape(1, 1, 4)


def linear_rgba(image, stored, is_float, warnings):
    """float32[H,W,C] values of `image` (C = 1 to 4; `is_float`: already scene linear,
    as Blender holds float images) as float32[H,W,4] linear RGBA with its broken texels
    set to 0."""
    height, width, channels = stored.shape
    pixels = np.ones((height, width, 4), dtype=np.float32)
    # Grey (1 channel) fills R, G and B; a missing alpha channel is opaque.
    pixels[..., :3] = stored[..., : min(channels, 3)]
    if channels == 4:
        pixels[..., 3] = stored[..., 3]
    if image.alpha_mode == "NONE":
        pixels[..., 3] = 1.0
    _to_linear(image, pixels, is_float, warnings)
    _sanitise_texels(image, pixels, warnings)
    return pixels


def _sanitise_texels(image, pixels, warnings):
    """NaN, infinite and negative colour texels become 0 (an HDRI's broken texels: a
    world lit by one would light the scene with them); a non-colour (data) image keeps
    its negative values, which vectors need.

    NaN and infinite texels are always reported, negative ones only where one is
    below NEGLIGIBLE_NEGATIVE of the image's mean colour value: the ringing of HDR tools
    about a bright sun leaves tiny negatives in most HDRIs (Blender's own studio HDRIs
    hold 3 to 5,053 texels, the most negative -0.004, against means near 1), which no
    image shows and which set to 0 change nothing a viewer could see.
    """
    broken = ~np.isfinite(pixels)
    negative = np.zeros_like(broken)
    if not image.colorspace_settings.is_data:
        negative[..., :3] = pixels[..., :3] < 0.0
    colour = pixels[..., :3][~(broken[..., :3] | negative[..., :3])]
    floor = -NEGLIGIBLE_NEGATIVE * (float(colour.mean()) if colour.size else 0.0)
    reported = broken.any(axis=2) | (negative & (pixels < floor)).any(axis=2)
    pixels[broken | negative] = 0.0
    count = int(reported.sum())
    if count:
        warn(
            warnings,
            f"Whitted: image '{image.name}' has {count} texel(s) with NaN, infinite or "
            "negative values; they render black",
        )


def _to_linear(image, pixels, is_float, warnings):
    # Blender converts float images to scene linear when it loads them, but returns
    # a byte image's values as stored, in the image's colour space (checked in 3.4
    # and 5.0: a saved sRGB PNG of 0.5 reads back 128/255).
    space = image.colorspace_settings.name
    if is_float or image.colorspace_settings.is_data or space in LINEAR_SPACES:
        return
    if space != "sRGB":
        warn(
            warnings,
            f"Whitted: image '{image.name}': colour space '{space}' is not supported; "
            "it is read as sRGB",
        )
    rgb = pixels[..., :3]
    # A byte image stores k/255: its values are looked up in a table of the EOTF made
    # in float64, the same bits whatever the array. (numpy's float32 power ran the
    # same values through SIMD or scalar code depending on where the array lay in
    # memory, and two exports of one image differed in the last bit: a render must be
    # a pure function of the scene.) Values off that grid go through the same function.
    codes = np.rint(rgb * 255.0)
    if np.array_equal(codes / np.float32(255.0), rgb):
        table = [_srgb_eotf(float(np.float32(k / 255.0))) for k in range(256)]
        np.copyto(rgb, np.array(table, dtype=np.float32)[codes.astype(np.intp)])
        return
    linear = np.vectorize(_srgb_eotf, otypes=[np.float64])(rgb.astype(np.float64))
    np.copyto(rgb, linear, casting="same_kind")


def _srgb_eotf(c):
    """The sRGB EOTF (IEC 61966-2-1) of one float, with Python's own float64 pow: linear
    below 0.04045, a 2.4 power above."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
