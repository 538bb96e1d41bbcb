"""Render settings stored on each scene as `scene.whitted`.

The quality controls are the fields of properties.presets.Quality; the
presets set them all at once (operators.WHITTED_OT_apply_preset). A control that
sets a native setting takes its default and range from the native Settings
(native_tables.setting).
"""

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ..export.light import DEFAULT_LIGHT_SAMPLES
from ..native_tables import bounds, setting
from ..result import VIEWPORT_DISPLAYS
from .presets import PRESETS


class WhittedEstimate(bpy.types.PropertyGroup):
    """One preset's predicted render time and error against Reference (the Estimate
    button)."""

    preset: StringProperty(name="Preset", description="Key of the preset")
    seconds: FloatProperty(name="Seconds", description="Predicted render time", unit="TIME")
    error: FloatProperty(
        name="Error",
        description="Predicted RMSE of the render against the Reference preset's, as "
        "an 8-bit display shows them (sRGB, in levels of 255)",
    )
    rays_per_pixel: FloatProperty(name="Rays per Pixel", description="Measured on the probe")


class WhittedSceneProperties(bpy.types.PropertyGroup):
    max_depth: IntProperty(
        name="Max Depth",
        description="Reflection and refraction bounces after the camera ray; "
        "0 traces camera rays and shadow feelers only",
        **setting("max_depth"),
    )
    aa_mode: EnumProperty(
        name="Anti-Aliasing",
        description="Where a pixel's camera samples go",
        items=(
            ("REGULAR", "Regular", "An n x n regular grid of samples per pixel"),
            ("JITTERED", "Jittered", "An n x n grid with each sample moved at random in its cell"),
            (
                "ADAPTIVE",
                "Adaptive",
                "The pixel's corners; a square is split in four while its corners differ by "
                "more than the threshold, up to the depth (Whitted 1980)",
            ),
        ),
        **setting("aa_mode"),
    )
    aa_samples: IntProperty(
        name="AA Samples",
        description="Anti-aliasing samples per pixel along each axis (an n x n grid); "
        "regular and jittered",
        # A new scene's own: 2 x 2 (the native default, 1, is the plain tracer that the
        # native tests and benchmarks take).
        **setting("aa_samples", default=2),
    )
    aa_threshold: FloatProperty(
        name="AA Threshold",
        description="Adaptive: split a square when its corners differ by more than this "
        "(sum over R, G, B of the spread of the values clamped to [0, 1])",
        **setting("aa_threshold"),
        precision=3,
    )
    aa_depth: IntProperty(
        name="AA Depth",
        description="Adaptive: how many times a square may be split (at most "
        "(2^depth + 1)^2 samples per pixel)",
        **setting("aa_depth"),
    )
    glossy_samples: IntProperty(
        name="Glossy Samples",
        description="Rays per axis (n x n) drawn from a rough surface's reflection lobe "
        "where a ray first meets one (later glossy bounces of that ray send one each)",
        **setting("glossy_samples"),
    )
    emitter_samples: IntProperty(
        name="Emitter Samples",
        description="Shadow feelers per axis (n x n) from each shading point to the emissive "
        "meshes, picked by emitted power (one after a glossy bounce)",
        **setting("emitter_samples"),
    )
    local_model: EnumProperty(
        name="Local Model",
        description="How a surface reflects light",
        items=(
            (
                "BLENDER",
                "Blender",
                "The BSDFs as Cycles evaluates them: a rough metal's reflection is its "
                "GGX lobe, blurred by glossy rays and lit by the same lobe",
            ),
            (
                "LECTURE",
                "Lecture",
                "Phong shading and a perfect mirror, as Whitted's 1980 tracer and the "
                "lecture write it (rough reflection fades into a Phong highlight)",
            ),
        ),
        default="BLENDER",
    )
    light_samples: IntProperty(
        name="Shadow Samples",
        description="Shadow feelers per axis (n x n) of a sized light (area, radius or "
        "angle) whose own Shadow Samples are 0",
        default=DEFAULT_LIGHT_SAMPLES,
        **bounds("light_samples"),
    )
    fresnel: EnumProperty(
        name="Fresnel",
        description="How reflection and refraction share a transmissive surface's light",
        items=(
            ("OFF", "Off", "Fixed weights: reflectivity and transmissivity as given"),
            ("SCHLICK", "Schlick", "Schlick's approximation of the Fresnel equations"),
            ("EXACT", "Exact", "The exact dielectric Fresnel equations"),
        ),
        **setting("fresnel"),
    )
    glass_shadows: EnumProperty(
        name="Glass Shadows",
        description="What a shadow feeler does where it meets glass (a refractive surface); "
        "cut-outs (alpha, Transparent BSDF) always let it through",
        items=(
            (
                "OPAQUE",
                "Opaque",
                "Glass casts a full shadow, as in Cycles and Whitted's 1980 tracer (light "
                "focused through glass is a caustic, which neither traces)",
            ),
            (
                "TINTED",
                "Tinted",
                "Feelers pass glass weighted by its transmission colour: lighter, coloured "
                "shadows (Hall and Greenberg 1983)",
            ),
        ),
        **setting("glass_shadows"),
    )
    cutoff: FloatProperty(
        name="Cutoff",
        description="Adaptive depth control: a reflected or refracted ray whose weight on "
        "the pixel is below this is not traced; 0 traces every ray up to the max depth",
        **setting("cutoff"),
        precision=4,
    )
    texture_filter: EnumProperty(
        name="Texture Filter",
        description="How image textures are sampled",
        items=(
            ("AUTHORED", "As Authored", "Each Image Texture node's interpolation"),
            ("CLOSEST", "Closest", "The closest texel everywhere (cheaper, blocky)"),
        ),
        default="AUTHORED",
    )
    ambient_strength: FloatProperty(
        name="Ambient Strength",
        description="Scale of the ambient light Ia that the world's colour gives every "
        "surface (the Phong ambient term); 0 disables it",
        default=1.0,
        min=0.0,
        soft_max=2.0,
    )
    tile_size: IntProperty(
        name="Tile Size",
        description="Width and height in pixels of the tiles the threads render",
        **setting("tile_size"),
    )
    use_waves: BoolProperty(
        name="Trace in Waves",
        description="Trace a row of a tile's samples together, a generation of rays at a "
        "time, with the shadow rays towards each light as packets; off: the recursive "
        "kernel, the reference (the same image and passes up to float rounding)",
        **setting("waves"),
    )
    viewport_preset: EnumProperty(
        name="Viewport Quality",
        description="The quality preset the Rendered viewport refines up to (apart from "
        "the final render's controls above)",
        items=tuple((key, label, description) for key, label, description, _ in PRESETS),
        default="PREVIEW",
    )
    viewport_display: EnumProperty(
        name="Viewport Display",
        description="What the Rendered viewport shows: the image, the ray cost, or one of "
        "the render passes (docs/PASSES.md)",
        items=tuple(
            (display.key, display.label, display.description) for display in VIEWPORT_DISPLAYS
        ),
        default="IMAGE",
    )
    last_stats: StringProperty(
        name="Last Render Statistics",
        description="JSON statistics of the last Whitted render of this scene "
        "(the same as the WHITTED_STATS file)",
        default="",
    )
    last_ray_tree: StringProperty(
        name="Last Ray Tree",
        description="JSON ray tree of the last inspected pixel (Inspect Ray Tree): every "
        "ray with its kind, depth, ends, object, weight and contribution",
        default="",
    )
    estimates: CollectionProperty(
        type=WhittedEstimate,
        name="Estimates",
        description="Predicted render time and error of each preset (Estimate button)",
    )
    estimate_memory_mib: FloatProperty(
        name="Estimated Memory",
        description="Memory the full render is estimated to need beyond Blender's own, MiB "
        "(the memory guard's estimate)",
        default=0.0,
    )
    estimate_probe: StringProperty(
        name="Estimate Probe",
        description="The probe the estimates were made from",
        default="",
    )
    estimate_caveat: StringProperty(
        name="Estimate Caveat",
        description="How a render's geometry differs from the viewport's, which the "
        "estimates were measured on (modifiers with other render settings); empty when "
        "it does not",
        default="",
    )

    @classmethod
    def register(cls):
        bpy.types.Scene.whitted = PointerProperty(
            name="Whitted", description="Whitted render settings", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.Scene.whitted
