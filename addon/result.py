"""Whitted's render passes and how finished tiles reach Blender's render result.

Besides Combined, every render has the pass "Whitted Rays": the rays traced for
each pixel (camera, shadow, reflection, refraction and transparent), so an
artist sees where the time goes.
"""

import bpy

COST_PASS = "Whitted Rays"
# Every pass each render writes.
PASSES = ("Combined", COST_PASS)

# `RenderPass.rect.foreach_set` takes a (w*h, channels) array up to Blender 4.0
# (it counts the first dimension only; a flat array is refused) and a flat
# (w*h*channels,) one from 4.1 (checked here: 3.4.1 and 5.0.1; the change at 4.1
# as found by dream-textures PR #801). Both lengths report w*h, so go by version.
FLAT_RECT = bpy.app.version >= (4, 1, 0)


def register_passes(engine, scene, view_layer):
    """For RenderEngine.update_render_passes: the passes the compositor can read."""
    engine.register_pass(scene, view_layer, "Combined", 4, "RGBA", "COLOR")
    engine.register_pass(scene, view_layer, COST_PASS, 1, "X", "VALUE")


def add_passes(engine):
    """Before the first begin_result of a render: the passes beyond Combined."""
    engine.add_pass(COST_PASS, 1, "X")


def write_tile(engine, job, tile, region):
    """Copy finished tile (x, y, w, h) of `job` into the render result.

    The render result covers only the region (the render border), so its pixel
    (0, 0) is the region's corner. Rows run bottom to top in both.
    """
    x, y, width, height = tile
    result = engine.begin_result(x - region[0], y - region[1], width, height)
    passes = result.layers[0].passes
    _set_pass(passes["Combined"], job.tile(x, y, width, height))
    _set_pass(passes[COST_PASS], job.cost_tile(x, y, width, height))
    engine.end_result(result)


def _set_pass(render_pass, pixels):
    # `pixels` is C-contiguous float32[w*h, channels], the fast path of foreach_set;
    # the reshape is a view, not a copy.
    render_pass.rect.foreach_set(pixels.reshape(-1) if FLAT_RECT else pixels)
