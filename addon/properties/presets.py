"""Quality presets: each one a stated set of values of scene.whitted's quality controls.

The table below is the one place the presets are defined; the panel's buttons,
the Estimate operator, the cost report and docs/ACCURACY_COST.md read it. They are
the add-on's, not the renderer's: each names values of controls the native library
has no notion of presets for, some of them the exporter's alone (light_samples,
texture_filter); each value lies in the native range of its setting
(tests/blender/test_tables.py).
"""

import math
from dataclasses import asdict, dataclass, fields


@dataclass(frozen=True)
class Quality:
    """The quality controls of one render (the fields of scene.whitted they name)."""

    max_depth: int  # reflection/refraction bounces after the camera ray
    aa_mode: str  # REGULAR | JITTERED | ADAPTIVE
    aa_samples: int  # per axis, regular and jittered: n x n camera samples per pixel
    aa_threshold: float  # adaptive: split a square whose corners differ by more
    aa_depth: int  # adaptive: how many times a square may be split
    # Noise-driven sampling (native film.h, Cycles' adaptive sampling): each pixel stops
    # taking camera samples once its noise estimate is below the threshold, after at
    # least the minimum (0: Cycles' automatic minimum) and at most the n x n grid.
    adaptive_sampling: bool
    noise_threshold: float
    adaptive_min_samples: int
    light_samples: int  # shadow feelers per axis of a sized light whose own setting is 0
    glossy_samples: int  # rays per axis drawn from a rough reflection lobe
    emitter_samples: int  # feelers per axis to the emissive meshes and the world light
    fresnel: str  # OFF | SCHLICK | EXACT
    cutoff: float  # a secondary ray whose weight is below this is not traced
    texture_filter: str  # AUTHORED (each Image Texture node's) | CLOSEST
    # Heterogeneous media's march step, times the object's own (Cycles' Volumes > Step
    # Rate; native integrator/march.h): smaller is finer and slower.
    volume_step_rate: float


# (key, label, description, values), cheapest first. Each preset is a noise target:
# its threshold decides how many camera samples a pixel takes, up to its grid (the
# fewest is the first check's: the minimum rounded up past the next multiple of 16,
# native schedule.h); each camera sample sends one feeler per lamp, one to the emitters
# and one glossy ray (docs/notes/adaptive_sampling.md says what was measured to choose
# this).
PRESETS = (
    (
        "DRAFT",
        "Draft",
        "Noise threshold 0.1 (16 to 36 samples per pixel), two bounces, closest texels",
        Quality(
            max_depth=2,
            aa_mode="JITTERED",
            aa_samples=6,
            aa_threshold=0.3,
            aa_depth=1,
            adaptive_sampling=True,
            noise_threshold=0.1,
            adaptive_min_samples=4,
            light_samples=1,
            glossy_samples=1,
            emitter_samples=1,
            fresnel="SCHLICK",
            cutoff=0.05,
            texture_filter="CLOSEST",
            volume_step_rate=1.0,
        ),
    ),
    (
        "PREVIEW",
        "Preview",
        "Noise threshold 0.05 (16 to 64 samples per pixel), four bounces",
        Quality(
            max_depth=4,
            aa_mode="JITTERED",
            aa_samples=8,
            aa_threshold=0.3,
            aa_depth=1,
            adaptive_sampling=True,
            noise_threshold=0.05,
            adaptive_min_samples=8,
            light_samples=1,
            glossy_samples=1,
            emitter_samples=1,
            fresnel="SCHLICK",
            cutoff=0.01,
            texture_filter="AUTHORED",
            volume_step_rate=1.0,
        ),
    ),
    (
        "FINAL",
        "Final",
        "Noise threshold 0.01 (32 to 1024 samples per pixel), eight bounces, exact Fresnel",
        Quality(
            max_depth=8,
            aa_mode="JITTERED",
            # Up to 32 x 32: with 16 x 16 a bright emitter's edges and a wide lens's blur
            # stopped noisy at the most (docs/notes/adaptive_sampling.md, session 27).
            aa_samples=32,
            aa_threshold=0.1,
            aa_depth=2,
            adaptive_sampling=True,
            noise_threshold=0.01,
            adaptive_min_samples=16,
            light_samples=1,
            glossy_samples=1,
            emitter_samples=1,
            fresnel="EXACT",
            cutoff=1.0 / 255.0,
            texture_filter="AUTHORED",
            volume_step_rate=1.0,
        ),
    ),
    (
        "REFERENCE",
        "Reference",
        "Noise threshold 0.002 (80 to 1024 samples per pixel), 16 bounces, cutoff 0.001",
        Quality(
            max_depth=16,
            aa_mode="JITTERED",
            aa_samples=32,
            aa_threshold=0.0,
            aa_depth=3,
            adaptive_sampling=True,
            noise_threshold=0.002,
            adaptive_min_samples=64,
            light_samples=1,
            glossy_samples=1,
            emitter_samples=1,
            fresnel="EXACT",
            # Not 0: without a cutoff a ray tree in glass doubles at every bounce
            # (2^16 rays per camera sample); a weight of 1/1000 is below 8-bit output.
            cutoff=0.001,
            texture_filter="AUTHORED",
            # A quarter of the step: a procedural cloud against Cycles 5.0's unbiased
            # tracking, SSIM 0.9859 at 1, 0.9996 at 0.25 (docs/SUPPORT.md).
            volume_step_rate=0.25,
        ),
    ),
)

# A new scene's settings (scene.whitted's defaults), as Cycles' new scene renders
# with its production threshold.
NEW_SCENE = "FINAL"


def preset(key):
    """The Quality of the preset named `key` (DRAFT, PREVIEW, FINAL, REFERENCE)."""
    return next(values for k, _, _, values in PRESETS if k == key)


def preset_label(key):
    return next(label for k, label, _, _ in PRESETS if k == key)


def quality_of(settings):
    """The Quality that scene.whitted `settings` holds."""
    return Quality(**{field.name: getattr(settings, field.name) for field in fields(Quality)})


def apply_quality(settings, quality):
    """Set scene.whitted `settings` to `quality`."""
    for name, value in asdict(quality).items():
        setattr(settings, name, value)


def matching_preset(settings):
    """The key of the preset that `settings` holds, or None when they match none.

    Floats compare with a tolerance: Blender stores them in single precision.
    """
    current = asdict(quality_of(settings))
    for key, _, _, values in PRESETS:
        if all(_same(current[name], value) for name, value in asdict(values).items()):
            return key
    return None


def _same(a, b):
    if isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-6, abs_tol=1e-9)
    return a == b
