"""Whitted's render passes, and how finished tiles reach Blender's render result.

One table, PASSES, says which passes Whitted can write: each pass's Blender
name and channels, the property that enables it and the film buffer its pixels
come from. Everything else is read from it: the passes registered for the
compositor (update_render_passes), those added to a render's result, the
view-layer pass panels (ui/passes.py) and what each finished tile writes.
docs/PASSES.md defines every pass.

Combined is always written, and so is "Whitted Rays" unless its switch is off:
the rays traced for each pixel (camera, shadow, reflection, refraction and
transparent), so an artist sees where the time goes.
"""

from dataclasses import dataclass

import bpy
import numpy as np

from . import cryptomatte


@dataclass(frozen=True)
class PassSpec:
    """One render pass Whitted can write."""

    name: str  # Blender's pass name: render result, compositor socket, EXR layer
    channels: str  # Blender's channel ids, one letter per channel ("RGBA", "XYZ", "Z")
    kind: str  # register_pass's type: 'COLOR', 'VECTOR' or 'VALUE'
    # What enables it: a ViewLayer property ("use_pass_z"), one of view_layer.whitted
    # ("whitted.use_pass_rays"), or "" for a pass that is always written.
    toggle: str
    # The job buffer it is read from: "combined" (RenderJob.tile), "rays"
    # (RenderJob.cost_tile), or a native film pass (RenderJob.pass_tile).
    source: str
    first: int = 0  # its first channel within `source` (several passes share one)
    panel: str = ""  # the view-layer sub-panel its switch is drawn in (ui/passes.py)
    heading: str = ""  # the heading of its group of switches there
    label: str = ""  # the switch's label ("" for the property's own name)

    def enabled(self, view_layer):
        if not self.toggle:
            return True
        owner, _, prop = self.toggle.rpartition(".")
        return bool(getattr(view_layer.whitted if owner else view_layer, prop))


COMBINED = PassSpec("Combined", "RGBA", "COLOR", "", "combined")
COST_PASS = "Whitted Rays"


# Every pass Whitted can write. The names and channels are Blender's, so the
# compositor's Render Layers node and EXR readers see what they expect.
PASSES = (
    COMBINED,
    PassSpec(COST_PASS, "X", "VALUE", "whitted.use_pass_rays", "rays", panel="WHITTED"),
)

# `RenderPass.rect.foreach_set` takes a (w*h, channels) array up to Blender 4.0
# (it counts the first dimension only; a flat array is refused) and a flat
# (w*h*channels,) one from 4.1 (checked here: 3.4.1 and 5.0.1; the change at 4.1
# as found by dream-textures PR #801). Both lengths report w*h, so go by version.
FLAT_RECT = bpy.app.version >= (4, 1, 0)


# Cryptomatte: (kind, the ViewLayer property that enables it, the job's name of the kind).
# Its passes are as many as the view layer's depth asks for (cryptomatte_passes).
CRYPTOMATTE = (
    ("CryptoObject", "use_pass_cryptomatte_object", "object"),
    ("CryptoMaterial", "use_pass_cryptomatte_material", "material"),
    ("CryptoAsset", "use_pass_cryptomatte_asset", "asset"),
)
CRYPTOMATTE_SOURCE = "cryptomatte:"


def cryptomatte_passes(view_layer):
    """The Cryptomatte passes of `view_layer`: per enabled kind, one RGBA pass per two
    ranks of pass_cryptomatte_depth, named as Blender names them (CryptoObject00, ...)."""
    depth = view_layer.pass_cryptomatte_depth
    return tuple(
        PassSpec(name, "RGBA", "COLOR", toggle, CRYPTOMATTE_SOURCE + source, first=4 * i)
        for kind, toggle, source in CRYPTOMATTE
        if getattr(view_layer, toggle)
        for i, name in enumerate(cryptomatte.pass_names(kind, depth))
    )


def cryptomatte_settings(settings, view_layer):
    """Set native `settings` to keep the Cryptomatte kinds `view_layer` enables."""
    kinds = [getattr(view_layer, toggle) for _, toggle, _ in CRYPTOMATTE]
    settings.cryptomatte_kinds = sum(1 << k for k, on in enumerate(kinds) if on)
    settings.cryptomatte_depth = view_layer.pass_cryptomatte_depth if any(kinds) else 0


def add_cryptomatte_metadata(engine, view_layer, names):
    """The header fields of each enabled Cryptomatte layer (cryptomatte.metadata), on
    the render's result: Blender's Cryptomatte node, Nuke and Natron read them.
    `names`: {kind: the names of its ids} (export.instance.cryptomatte_names)."""
    result = engine.get_result()
    for kind, toggle, _ in CRYPTOMATTE:
        if getattr(view_layer, toggle):
            for field, value in cryptomatte.metadata(view_layer.name, kind, names[kind]).items():
                result.stamp_data_add_field(field, value)


def enabled_passes(view_layer):
    """The passes a render of `view_layer` writes, Combined first."""
    static = tuple(spec for spec in PASSES if spec.enabled(view_layer))
    return static + cryptomatte_passes(view_layer)


def register_passes(engine, scene, view_layer):
    """For RenderEngine.update_render_passes: the passes the compositor can read."""
    for spec in enabled_passes(view_layer):
        engine.register_pass(
            scene, view_layer, spec.name, len(spec.channels), spec.channels, spec.kind
        )


def add_passes(engine, passes):
    """Before the first begin_result of a render: the passes beyond Combined."""
    for spec in passes:
        if spec is not COMBINED:
            engine.add_pass(spec.name, len(spec.channels), spec.channels)


def write_tile(engine, job, tile, region, passes):
    """Copy finished tile (x, y, w, h) of `job` into the render result.

    The render result covers only the region (the render border), so its pixel
    (0, 0) is the region's corner. Rows run bottom to top in both.
    """
    x, y, width, height = tile
    result = engine.begin_result(x - region[0], y - region[1], width, height)
    layer = result.layers[0].passes
    for spec in passes:
        _set_pass(layer[spec.name], _pixels(job, spec, x, y, width, height))
    engine.end_result(result)


def _pixels(job, spec, x, y, width, height):
    if spec.source == "combined":
        return job.tile(x, y, width, height)
    if spec.source == "rays":
        return job.cost_tile(x, y, width, height)
    if spec.source.startswith(CRYPTOMATTE_SOURCE):
        # Two ranks (id, coverage, id, coverage) a pass; an odd depth's last pass has one.
        ranks = job.cryptomatte_tile(spec.source[len(CRYPTOMATTE_SOURCE) :], x, y, width, height)
        out = np.zeros((width * height, 4), dtype=np.float32)
        columns = ranks[:, spec.first : spec.first + 4]
        out[:, : columns.shape[1]] = columns
        return out
    pixels = job.pass_tile(spec.source, x, y, width, height)
    if spec.first == 0 and pixels.shape[1] == len(spec.channels):
        return pixels
    # One of several passes sharing the buffer: a contiguous copy of its columns.
    return pixels[:, spec.first : spec.first + len(spec.channels)].copy()


def _set_pass(render_pass, pixels):
    # `pixels` is C-contiguous float32[w*h, channels], the fast path of foreach_set;
    # the reshape is a view, not a copy.
    render_pass.rect.foreach_set(pixels.reshape(-1) if FLAT_RECT else pixels)
