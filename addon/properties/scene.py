"""Render settings stored on each scene as `scene.whitted`.

The quality controls are the fields of properties.presets.Quality; the
presets set them all at once (operators.WHITTED_OT_apply_preset), and a new scene
holds the NEW_SCENE preset's values. A control that sets a native setting takes its
range from the native Settings (native_tables.setting).
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

from ..native_tables import bounds, setting
from ..result import VIEWPORT_DISPLAYS
from .presets import NEW_SCENE, PRESETS, preset

# A new scene's quality control values: the NEW_SCENE preset's.
NEW = preset(NEW_SCENE)


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
        **setting("max_depth", default=NEW.max_depth),
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
        **setting("aa_mode", default=NEW.aa_mode),
    )
    aa_samples: IntProperty(
        name="AA Samples",
        description="Camera samples per pixel along each axis (an n x n grid): regular and "
        "jittered; with a noise threshold, the most a pixel takes",
        **setting("aa_samples", default=NEW.aa_samples),
    )
    aa_threshold: FloatProperty(
        name="AA Threshold",
        description="Adaptive: split a square when its corners differ by more than this "
        "(sum over R, G, B of the spread of the values clamped to [0, 1])",
        **setting("aa_threshold", default=NEW.aa_threshold),
        precision=3,
    )
    aa_depth: IntProperty(
        name="AA Depth",
        description="Adaptive: how many times a square may be split (at most "
        "(2^depth + 1)^2 samples per pixel)",
        **setting("aa_depth", default=NEW.aa_depth),
    )
    adaptive_sampling: BoolProperty(
        name="Noise Threshold",
        description="Stop taking camera samples in a pixel once its noise is below the "
        "threshold (Cycles' adaptive sampling): converged pixels stop early, noisy ones "
        "take up to the n x n grid; off: every pixel takes the grid",
        default=NEW.adaptive_sampling,
    )
    noise_threshold: FloatProperty(
        name="Noise Threshold",
        description="The noise a pixel may keep (Cycles' metric: its error relative to "
        "its brightness); lower is cleaner and slower; 0: every pixel takes the grid",
        **setting("noise_threshold", default=NEW.noise_threshold),
        precision=4,
        step=0.1,
    )
    adaptive_min_samples: IntProperty(
        name="Min Samples",
        description="Camera samples every pixel takes before its noise is checked "
        "(0: automatic, as Cycles, from the threshold)",
        **setting("adaptive_min_samples", default=NEW.adaptive_min_samples),
    )
    seed: IntProperty(
        name="Seed",
        description="Which of the equally good sets of random samples the render draws "
        "(Cycles' Seed): another seed moves the noise, not the image",
        **setting("seed"),
    )
    use_animated_seed: BoolProperty(
        name="Use Animated Seed",
        description="A seed of its own for each frame, so an animation's noise does not "
        "stand still while the scene moves",
        default=False,
    )
    time_limit: FloatProperty(
        name="Time Limit",
        description="Stop sampling after this long (with a noise threshold; each pixel "
        "keeps the samples it took); 0: no limit",
        default=0.0,
        min=0.0,
        unit="TIME_ABSOLUTE",
    )
    use_denoising: BoolProperty(
        name="Denoise",
        description="Denoise the final render with Intel Open Image Denoise, guided by "
        "the albedo and normal of the first rough surface the camera sees, through "
        "mirrors and glass (not in the Lecture local model)",
        default=True,
    )
    use_viewport_denoising: BoolProperty(
        name="Denoise Viewport",
        description="Denoise the Rendered viewport with Intel Open Image Denoise once it "
        "reaches its last sample",
        default=False,
    )
    denoising_input_passes: EnumProperty(
        name="Passes",
        description="The passes the denoiser reads besides the noisy image",
        items=(
            ("RGB", "None", "The noisy image alone"),
            ("RGB_ALBEDO", "Albedo", "The image and the albedo"),
            ("RGB_ALBEDO_NORMAL", "Albedo and Normal", "The image, the albedo and the normal"),
        ),
        default="RGB_ALBEDO_NORMAL",
    )
    denoising_prefilter: EnumProperty(
        name="Prefilter",
        description="Whether the denoiser first cleans its albedo and normal inputs "
        "(noisy where the camera sees them through depth of field or motion blur)",
        items=(
            ("NONE", "None", "The albedo and normal are taken as they are (noise-free)"),
            ("FAST", "Fast", "The image's filter cleans the albedo and normal itself"),
            ("ACCURATE", "Accurate", "Denoise the albedo and normal first"),
        ),
        default="ACCURATE",
    )
    denoising_quality: EnumProperty(
        name="Quality",
        description="The denoiser's network: higher quality is slower",
        items=(
            ("HIGH", "High", "The best quality"),
            ("BALANCED", "Balanced", "Faster, a little less accurate"),
            ("FAST", "Fast", "The fastest"),
        ),
        default="HIGH",
    )
    glossy_samples: IntProperty(
        name="Glossy Samples",
        description="Rays per axis (n x n) drawn from a rough surface's reflection lobe "
        "where a ray first meets one (later glossy bounces of that ray send one each)",
        **setting("glossy_samples", default=NEW.glossy_samples),
    )
    emitter_samples: IntProperty(
        name="Emitter Samples",
        description="Shadow feelers per axis (n x n) from each shading point to the emissive "
        "meshes, picked by emitted power, and to the world where it lights the scene, "
        "drawn by its radiance (one after a glossy bounce)",
        **setting("emitter_samples", default=NEW.emitter_samples),
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
        default=NEW.light_samples,
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
        **setting("fresnel", default=NEW.fresnel),
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
    volume_step_rate: FloatProperty(
        name="Volume Step Rate",
        description="Heterogeneous media (a volume shader whose inputs nodes drive) are "
        "marched in steps of a tenth of their object's mean size times the material's Step "
        "Rate times this, as Cycles' Volumes > Step Rate: lower is finer and slower",
        **setting("volume_step_rate", default=1.0),
    )
    volume_max_steps: IntProperty(
        name="Volume Max Steps",
        description="The most steps a ray's segment through a heterogeneous medium takes, as "
        "Cycles' Volumes > Max Steps (longer steps beyond)",
        **setting("volume_max_steps", default=1024),
    )
    pixel_filter_type: EnumProperty(
        name="Pixel Filter",
        description="Where a pixel's samples land about its centre, as Cycles' Film > Pixel "
        "Filter (Whitted's adaptive anti-aliasing samples each pixel's square)",
        items=(
            ("BOX", "Box", "Each pixel's samples in its own square: no filtering"),
            ("GAUSSIAN", "Gaussian", "A smooth filter: soft edges"),
            (
                "BLACKMAN_HARRIS",
                "Blackman-Harris",
                "Cycles' default: a balance between smoothness and detail",
            ),
        ),
        default="BLACKMAN_HARRIS",
    )
    filter_width: FloatProperty(
        name="Width",
        description="The pixel filter's width: lower is crisper, higher softer and less aliased",
        subtype="PIXEL",
        precision=2,
        **setting("filter_width", default=1.5),
    )
    cutoff: FloatProperty(
        name="Cutoff",
        description="Adaptive depth control: a reflected or refracted ray whose weight on "
        "the pixel is below this is not traced; 0 traces every ray up to the max depth",
        **setting("cutoff", default=NEW.cutoff),
        precision=4,
    )
    texture_filter: EnumProperty(
        name="Texture Filter",
        description="How image textures are sampled",
        items=(
            ("AUTHORED", "As Authored", "Each Image Texture node's interpolation"),
            ("CLOSEST", "Closest", "The closest texel everywhere (cheaper, blocky)"),
        ),
        default=NEW.texture_filter,
    )
    ambient_strength: FloatProperty(
        name="Ambient Strength",
        description="Lecture local model: scale of the ambient light Ia that the world's "
        "colour gives every surface (the Phong ambient term); 0 disables it. The Blender "
        "model lights surfaces with the world itself, as Cycles (World > Ray Visibility)",
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
