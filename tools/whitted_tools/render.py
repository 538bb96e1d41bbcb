"""Rendering a scene in Blender and reading its pixels back (Blender 3.4 and 5.0)."""

import bpy
import numpy as np


def render_exr(scene, path, engine=None, png=None):
    """Render `scene` (with `engine`, default its own) to a 32-bit float RGBA OpenEXR at
    `path` and return its linear pixels, float32[height, width, 4], rows bottom to top;
    with `png`, also save that image there through the scene's view transform.

    Blender 3.4 cannot read the Render Result's pixels from Python: the render goes
    through the file (linear: no view transform).
    """
    if engine is not None:
        scene.render.engine = engine
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.color_mode = "OPEN_EXR", "32", "RGBA"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(scene.render.filepath)
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        if png is not None:
            settings.file_format, settings.color_depth, settings.color_mode = "PNG", "8", "RGB"
            image.save_render(str(png), scene=scene)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)


def enable_every_pass(view_layer, result, contribution_depth):
    """Switch on every pass of the add-on's table (`result`, the add-on's result module)
    in `view_layer`, and the per-depth passes up to `contribution_depth`."""
    for spec in result.PASSES:
        holder, prop = spec.switch(view_layer)
        if prop and holder is not None:
            setattr(holder, prop, True)
    view_layer.whitted.use_pass_contributions = True
    view_layer.whitted.contribution_depth = contribution_depth


def use_multilayer_exr(image_settings):
    """Save renders as 32-bit float multilayer OpenEXR, every pass in the file. Blender
    5.0 chooses multilayer through the media type first: set as a plain OPEN_EXR format
    its file holds Combined alone."""
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = "MULTI_LAYER_IMAGE"
    image_settings.file_format = "OPEN_EXR_MULTILAYER"
    image_settings.color_depth = "32"


def save_side_by_side(images, path, gap=4, grey=0.18):
    """Linear RGBA renders of one size side by side in an 8-bit PNG at `path` (Whitted
    left, Cycles right, in the galleries), each over a mid grey where its film is
    transparent, so cut-outs show; `gap` pixels of white between them."""
    height, width, _ = images[0].shape
    pair = np.ones((height, len(images) * (width + gap) - gap, 4), dtype=np.float32)
    for index, image in enumerate(images):
        offset = index * (width + gap)
        alpha = image[..., 3:4]
        pair[:, offset : offset + width, :3] = image[..., :3] + (1.0 - alpha) * grey
    out = bpy.data.images.new("pair", pair.shape[1], height, float_buffer=True)
    try:
        out.pixels.foreach_set(pair.reshape(-1))
        scene = bpy.context.scene
        settings = scene.render.image_settings
        settings.file_format, settings.color_mode, settings.color_depth = "PNG", "RGB", "8"
        out.save_render(path, scene=scene)
    finally:
        bpy.data.images.remove(out)
