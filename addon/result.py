"""Whitted's render passes, and how finished tiles reach Blender's render result.

One table, PASSES, says which passes Whitted can write: each pass's Blender
name and channels, the property that enables it and the film buffer its pixels
come from. Everything else is read from it: the passes registered for the
compositor (update_render_passes), those added to a render's result, the
view-layer pass panels (ui/passes.py) and what each finished tile writes.
docs/PASSES.md defines every pass.

Combined is always written, and so is "Whitted Rays" unless its switch is off:
the rays traced for each pixel (camera, shadow, reflection, refraction and
transparent, and in media their scatter points' feelers and the rays through
their bounds), so an artist sees where the time goes.
"""

from dataclasses import dataclass

import bpy
import numpy as np

from . import cryptomatte, denoise
from .native_tables import bounds


@dataclass(frozen=True)
class PassSpec:
    """One render pass Whitted can write."""

    name: str  # Blender's pass name: render result, compositor socket, EXR layer
    # Blender's channel ids, one letter per channel ("RGBA", "XYZ", "Z"): as many as the
    # native film pass `source` has (whitted_native.FILM_PASSES; tests/blender/test_tables.py).
    channels: str
    kind: str  # register_pass's type: 'COLOR', 'VECTOR' or 'VALUE'
    # What enables it: a ViewLayer property ("use_pass_z"), one of view_layer.whitted
    # ("whitted.use_pass_rays") or of Cycles' view_layer.cycles where Blender has no
    # property of its own ("cycles.use_pass_volume_direct"), or "" for a pass that is
    # always written.
    toggle: str
    # The job buffer it is read from: "combined" (RenderJob.tile), "rays"
    # (RenderJob.cost_tile), or a native film pass (RenderJob.pass_tile).
    source: str
    first: int = 0  # its first channel within `source` (several passes share one)
    panel: str = ""  # the view-layer sub-panel its switch is drawn in (ui/passes.py)
    heading: str = ""  # the heading of its group of switches there
    label: str = ""  # the switch's label ("" for the property's own name)
    requires: tuple = ()  # other toggles that must be on too (drawn elsewhere)

    def switch(self, view_layer):
        """(what holds the pass's switch in `view_layer`, the property's name); what holds
        it is None where its add-on (Cycles, for its volume passes) is not enabled."""
        return _switch(view_layer, self.toggle)

    def enabled(self, view_layer):
        return all(_switched_on(view_layer, toggle) for toggle in (self.toggle, *self.requires))


def _switch(view_layer, toggle):
    owner, _, prop = toggle.rpartition(".")
    return (getattr(view_layer, owner, None) if owner else view_layer), prop


def _switched_on(view_layer, toggle):
    """Whether `toggle` (PassSpec.toggle's form; "" for always) is on in `view_layer`."""
    if not toggle:
        return True
    holder, prop = _switch(view_layer, toggle)
    return holder is not None and bool(getattr(holder, prop))


# Blender 3.x and 4.x name passes as Cycles did for years ("DiffDir"); Blender 5.0's
# Cycles, its compositor and EXR files use long names ("Diffuse Direct"), taken here
# from 5.0 on (checked: Cycles' multilayer EXR from 3.4.1, bpy 4.2.23 and 4.5 has the
# short names, from 5.0.1 the long ones).
LONG_NAMES = {
    "IndexOB": "Object Index",
    "IndexMA": "Material Index",
    "DiffDir": "Diffuse Direct",
    "DiffInd": "Diffuse Indirect",
    "DiffCol": "Diffuse Color",
    "GlossDir": "Glossy Direct",
    "GlossInd": "Glossy Indirect",
    "GlossCol": "Glossy Color",
    "TransDir": "Transmission Direct",
    "TransInd": "Transmission Indirect",
    "TransCol": "Transmission Color",
    "VolumeDir": "Volume Direct",
    "VolumeInd": "Volume Indirect",
    "Emit": "Emission",
    "Env": "Environment",
}


def blender_name(name):
    """This Blender's name of the pass Blender 3.x calls `name`."""
    return LONG_NAMES.get(name, name) if bpy.app.version >= (5, 0, 0) else name


COMBINED = PassSpec("Combined", "RGBA", "COLOR", "", "combined")
COST_PASS = "Whitted Rays"


def _light(name, toggle, source, heading, label):
    return PassSpec(
        blender_name(name),
        "RGB",
        "COLOR",
        toggle,
        source,
        panel="LIGHT",
        heading=heading,
        label=label,
    )


# Cycles' Shadow Catcher pass, switched by Cycles' own view-layer property (Blender has
# none; the same in 3.x and 5.x): per channel, the light on the shadow catchers with the
# other objects over that with the catchers alone (1 off the catchers). With it on,
# Combined leaves the catchers out, as Cycles' does (integrator/catcher.h).
SHADOW_CATCHER = _light(
    "Shadow Catcher", "cycles.use_pass_shadow_catcher", "shadow_catcher", "Other", "Shadow Catcher"
)
# The passes a denoised render writes denoised, as Cycles does (addon/denoise.py).
DENOISED_PASSES = (COMBINED, SHADOW_CATCHER)

# Every pass Whitted can write, in the order Cycles lists them (its
# list_render_passes); the names and channels are Blender's (Cycles'), so the
# compositor's Render Layers node and EXR readers see what they expect.
PASSES = (
    COMBINED,
    PassSpec("Depth", "Z", "VALUE", "use_pass_z", "depth", panel="DATA", heading="Include"),
    PassSpec("Mist", "Z", "VALUE", "use_pass_mist", "mist", panel="DATA", heading="Include"),
    PassSpec(
        "Position",
        "XYZ",
        "VECTOR",
        "use_pass_position",
        "position",
        panel="DATA",
        heading="Include",
    ),
    PassSpec(
        "Normal", "XYZ", "VECTOR", "use_pass_normal", "normal", panel="DATA", heading="Include"
    ),
    PassSpec("UV", "UVA", "VECTOR", "use_pass_uv", "uv", panel="DATA", heading="Include"),
    PassSpec(
        blender_name("IndexOB"),
        "X",
        "VALUE",
        "use_pass_object_index",
        "object_index",
        panel="DATA",
        heading="Indexes",
    ),
    PassSpec(
        blender_name("IndexMA"),
        "X",
        "VALUE",
        "use_pass_material_index",
        "material_index",
        panel="DATA",
        heading="Indexes",
    ),
    _light("DiffDir", "use_pass_diffuse_direct", "diffuse_direct", "Diffuse", "Direct"),
    _light("DiffInd", "use_pass_diffuse_indirect", "diffuse_indirect", "Diffuse", "Indirect"),
    _light("DiffCol", "use_pass_diffuse_color", "diffuse_color", "Diffuse", "Color"),
    _light("GlossDir", "use_pass_glossy_direct", "glossy_direct", "Glossy", "Direct"),
    _light("GlossInd", "use_pass_glossy_indirect", "glossy_indirect", "Glossy", "Indirect"),
    _light("GlossCol", "use_pass_glossy_color", "glossy_color", "Glossy", "Color"),
    _light(
        "TransDir", "use_pass_transmission_direct", "transmission_direct", "Transmission", "Direct"
    ),
    _light(
        "TransInd",
        "use_pass_transmission_indirect",
        "transmission_indirect",
        "Transmission",
        "Indirect",
    ),
    _light(
        "TransCol", "use_pass_transmission_color", "transmission_color", "Transmission", "Color"
    ),
    # Cycles' volume passes, switched by Cycles' own view-layer properties (Blender has none):
    # the light media scatter once towards the camera ray; Indirect is black, as Cycles' is
    # with Volume Bounces 0 (light scattered twice is not simulated).
    _light("VolumeDir", "cycles.use_pass_volume_direct", "volume_direct", "Volume", "Direct"),
    _light("VolumeInd", "cycles.use_pass_volume_indirect", "volume_indirect", "Volume", "Indirect"),
    _light("Emit", "use_pass_emit", "emission", "Other", "Emission"),
    _light("Env", "use_pass_environment", "environment", "Other", "Environment"),
    SHADOW_CATCHER,
    # Cycles' Denoising Data passes: the image before denoising (Combined itself when the
    # render is not denoised) and the denoiser's guides (addon/denoise.py).
    PassSpec(
        "Noisy Image",
        "RGBA",
        "COLOR",
        "whitted.use_pass_denoising_data",
        "noisy",
        panel="DATA",
        heading="Denoising",
        label="Denoising Data",
    ),
    # ... and the Shadow Catcher pass before denoising, where the render has one.
    PassSpec(
        "Noisy Shadow Catcher",
        "RGB",
        "COLOR",
        "whitted.use_pass_denoising_data",
        "shadow_catcher",
        requires=(SHADOW_CATCHER.toggle,),
    ),
    PassSpec(
        "Denoising Normal",
        "XYZ",
        "VECTOR",
        "whitted.use_pass_denoising_data",
        "denoising_normal",
    ),
    PassSpec(
        "Denoising Albedo",
        "RGB",
        "COLOR",
        "whitted.use_pass_denoising_data",
        "denoising_albedo",
    ),
    PassSpec(COST_PASS, "X", "VALUE", "whitted.use_pass_rays", "rays", panel="WHITTED"),
    PassSpec(
        "Whitted Cut Weight",
        "X",
        "VALUE",
        "whitted.use_pass_cut_weight",
        "cut_weight",
        panel="WHITTED",
    ),
    PassSpec(
        "Debug Sample Count",
        "X",
        "VALUE",
        "whitted.use_pass_sample_count",
        "sample_count",
        panel="WHITTED",
    ),
)
# The per-depth passes: "Whitted Depth 0" .. "Whitted Depth N-1" and "Whitted Depth
# N+", N = view_layer.whitted.contribution_depth; made by contribution_passes().
CONTRIBUTIONS_TOGGLE = "whitted.use_pass_contributions"
# The deepest N can be: native Settings.contribution_depth's maximum (None where the
# native module does not import; see native_tables).
MAX_CONTRIBUTION_DEPTH = bounds("contribution_depth").get("max")


def contribution_passes(depth):
    """The per-depth passes for contribution depth N = `depth`: one per depth below
    N, then one for N and beyond, all read from the native "contributions" pass."""
    return tuple(
        PassSpec(
            f"Whitted Depth {d}{'+' if d == depth else ''}",
            "RGB",
            "COLOR",
            CONTRIBUTIONS_TOGGLE,
            "contributions",
            first=3 * d,
        )
        for d in range(depth + 1)
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
    passes = tuple(spec for spec in PASSES if spec.enabled(view_layer))
    if view_layer.whitted.use_pass_contributions:
        passes += contribution_passes(view_layer.whitted.contribution_depth)
    return passes + cryptomatte_passes(view_layer)


# The passes read from the film's image and ray cost, not from a film pass of their own.
IMAGE_SOURCES = frozenset(("combined", "rays", "noisy"))


def configure(settings, scene, view_layer, passes, guides=False):
    """Ask native `settings` for the film passes that `passes` are read from (and the
    denoiser's guides when `guides`), with the view layer's alpha threshold, the
    world's mist and the contribution depth, and for the Cryptomatte kinds the view
    layer enables."""
    sources = set(denoise.GUIDE_SOURCES) if guides else set()
    for spec in passes:
        if spec.source not in IMAGE_SOURCES:
            sources.add(spec.source)
    settings.passes = sorted(s for s in sources if not s.startswith(CRYPTOMATTE_SOURCE))
    settings.contribution_depth = view_layer.whitted.contribution_depth
    settings.pass_alpha_threshold = view_layer.pass_alpha_threshold
    settings.mist = mist_of(scene.world)
    cryptomatte_settings(settings, view_layer)


# Blender's mist falloffs as the exponent of ((distance - start) / depth).
MIST_FALLOFF = {"QUADRATIC": 2.0, "LINEAR": 1.0, "INVERSE_QUADRATIC": 0.5}


def mist_of(world):
    """(start, depth, falloff exponent) of the world's mist (World > Mist Pass)."""
    if world is None:
        return (0.0, 100.0, 1.0)  # what Cycles' film has without a world
    mist = world.mist_settings
    # Blender's mist is in scene units (metres with the default unit scale), as are
    # Whitted's distances.
    return (mist.start, mist.depth, MIST_FALLOFF[mist.falloff])


@dataclass(frozen=True)
class ViewportDisplay:
    """Something the Rendered viewport can show (scene.whitted.viewport_display)."""

    key: str  # the enum item
    label: str
    description: str
    kind: str  # RenderJob.display's kind: "image", "cost" or a film pass
    first: int = 0  # its first channel in that pass
    passes: tuple = ()  # the film passes the viewport's job keeps for it


# A Direct or Indirect pass is shown divided by its Color, as the render writes it
# when both are enabled.
_COLOR_OF = {
    "diffuse": "diffuse_color",
    "glossy": "glossy_color",
    "transmission": "transmission_color",
}


def _display_of(spec):
    key = spec.name.upper().replace(" ", "_").replace("+", "_AND_BEYOND")
    passes = (spec.source,)
    component, _, kind = spec.source.partition("_")
    if kind in ("direct", "indirect") and component in _COLOR_OF:  # the volume's have none
        passes += (_COLOR_OF[component],)
    description = f'The "{spec.name}" pass, live (docs/PASSES.md)'
    return ViewportDisplay(key, spec.name, description, spec.source, spec.first, passes)


VIEWPORT_DISPLAYS = (
    ViewportDisplay("IMAGE", "Image", "The rendered image", "image"),
    ViewportDisplay(
        "COST",
        "Ray Cost",
        "Rays traced per pixel as a heat map (the Whitted Rays pass, live): where the time "
        "of a frame goes",
        "cost",
    ),
    *(_display_of(spec) for spec in PASSES if spec.source not in IMAGE_SOURCES),
    # The viewport keeps all depths apart, up to the deepest the passes can.
    *(
        _display_of(spec)
        for spec in (contribution_passes(MAX_CONTRIBUTION_DEPTH) if MAX_CONTRIBUTION_DEPTH else ())
    ),
)


def viewport_display(key):
    """The ViewportDisplay of enum item `key`."""
    return next(display for display in VIEWPORT_DISPLAYS if display.key == key)


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


def write_tile(engine, job, tile, region, passes, replaced=None):
    """Copy finished tile (x, y, w, h) of `job` into the render result; `replaced`:
    {pass name: the tile's pixels in place of the job's} (the denoised images).

    The render result covers only the region (the render border), so its pixel
    (0, 0) is the region's corner. Rows run bottom to top in both.
    """
    x, y, width, height = tile
    result = engine.begin_result(x - region[0], y - region[1], width, height)
    layer = result.layers[0].passes
    for spec in passes:
        if replaced and spec.name in replaced:
            pixels = replaced[spec.name]
        else:
            pixels = _pixels(job, spec, x, y, width, height)
        _set_pass(layer[spec.name], pixels)
    engine.end_result(result)


def _pixels(job, spec, x, y, width, height):
    if spec.source in ("combined", "noisy"):
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
