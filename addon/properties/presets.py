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
    light_samples: int  # shadow feelers per axis of a sized light whose own setting is 0
    glossy_samples: int  # rays per axis drawn from a rough reflection lobe
    emitter_samples: int  # feelers per axis to the emissive meshes from a shading point
    fresnel: str  # OFF | SCHLICK | EXACT
    cutoff: float  # a secondary ray whose weight is below this is not traced
    texture_filter: str  # AUTHORED (each Image Texture node's) | CLOSEST


# (key, label, description, values), cheapest first.
PRESETS = (
    (
        "DRAFT",
        "Draft",
        "One sample per pixel, two bounces, hard-edged soft shadows, closest texels",
        Quality(
            max_depth=2,
            aa_mode="REGULAR",
            aa_samples=1,
            aa_threshold=0.3,
            aa_depth=1,
            light_samples=1,
            glossy_samples=1,
            emitter_samples=1,
            fresnel="SCHLICK",
            cutoff=0.05,
            texture_filter="CLOSEST",
        ),
    ),
    (
        "PREVIEW",
        "Preview",
        "Adaptive anti-aliasing (one split), four bounces, 2x2 shadow and emitter feelers",
        Quality(
            max_depth=4,
            aa_mode="ADAPTIVE",
            aa_samples=2,
            aa_threshold=0.3,
            aa_depth=1,
            light_samples=2,
            glossy_samples=2,
            emitter_samples=2,
            fresnel="SCHLICK",
            cutoff=0.01,
            texture_filter="AUTHORED",
        ),
    ),
    (
        "FINAL",
        "Final",
        "Adaptive anti-aliasing (two splits, threshold 0.1), eight bounces, 4x4 shadow "
        "and emitter feelers, exact Fresnel",
        Quality(
            max_depth=8,
            aa_mode="ADAPTIVE",
            aa_samples=3,
            aa_threshold=0.1,
            aa_depth=2,
            light_samples=4,
            glossy_samples=3,
            emitter_samples=4,
            fresnel="EXACT",
            cutoff=1.0 / 255.0,
            texture_filter="AUTHORED",
        ),
    ),
    (
        "REFERENCE",
        "Reference",
        "6x6 jittered samples per pixel, 16 bounces, 6x6 shadow and emitter feelers, cutoff 0.001",
        Quality(
            max_depth=16,
            aa_mode="JITTERED",
            aa_samples=6,
            aa_threshold=0.0,
            aa_depth=3,
            light_samples=6,
            glossy_samples=6,
            emitter_samples=6,
            fresnel="EXACT",
            # Not 0: without a cutoff a ray tree in glass doubles at every bounce
            # (2^16 rays per camera sample); a weight of 1/1000 is below 8-bit output.
            cutoff=0.001,
            texture_filter="AUTHORED",
        ),
    ),
)


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
