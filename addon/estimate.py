"""Predict each preset's full-resolution render time from a low-resolution probe.

The scene is exported once; each preset then renders the whole frame at
1/PROBE_DIVISOR of the resolution (in this process, with the native module).
The probe gives rays per pixel and rays per second; the prediction is

    export + BVH time (as measured) + rays per pixel * pixels / rays per second

so it assumes rays per pixel and the ray rate do not change with resolution.
Adaptive anti-aliasing breaks the first assumption a little: a low-resolution
pixel covers more edges, so it splits more often (docs/ACCURACY_COST.md gives
the measured error).
"""

import time
from dataclasses import dataclass, replace

from .export.film import convert_film
from .export.light import convert_lights
from .export.scene import convert_scene, set_lights
from .properties.presets import PRESETS
from .settings import native_settings

PROBE_DIVISOR = 8
# A probe narrower than this is not one (the whole frame when it is smaller).
MIN_PROBE_WIDTH = 80
# Small tiles keep every thread busy on the small probe.
PROBE_TILE_SIZE = 16
# How long one poll of a probe job waits.
POLL_SECONDS = 0.1


@dataclass(frozen=True)
class Estimate:
    preset: str  # key in properties.presets.PRESETS
    seconds: float  # predicted full-resolution render time
    rays_per_pixel: float  # on the probe
    rays_per_second: float  # on the probe


def probe_size(width, height):
    """The probe's (width, height): 1/PROBE_DIVISOR of each side, the aspect kept."""
    probe_width = min(width, max(MIN_PROBE_WIDTH, width // PROBE_DIVISOR))
    return probe_width, max(1, round(height * probe_width / width))


def estimate_presets(depsgraph, native):
    """((probe width, height), (full width, height), [Estimate per preset]) for the
    evaluated depsgraph's scene. Raises what export.scene.convert_scene raises."""
    scene = depsgraph.scene
    started = time.perf_counter()
    exported = convert_scene(depsgraph, native)
    export_seconds = time.perf_counter() - started
    film = convert_film(scene.render, exported.width, exported.height)
    xmin, ymin, xmax, ymax = film.region
    pixels = (xmax - xmin) * (ymax - ymin)
    width, height = probe_size(exported.width, exported.height)
    # The probe covers the whole (smaller) frame: no border.
    probe_film = replace(film, region=(0, 0, width, height))
    estimates = []
    for key, _, _, quality in PRESETS:
        # Soft-shadow samples are part of the lights: re-set them for this preset.
        set_lights(exported.scene, convert_lights(depsgraph, [], quality.light_samples), native)
        settings = native_settings(native, scene, width, height, probe_film, quality)
        settings.tile_size = PROBE_TILE_SIZE
        stats = _render(native.RenderJob(exported.scene, settings))
        rays = stats["rays"]["total"]
        rays_per_pixel = rays / (width * height)
        rays_per_second = rays / stats["trace_seconds"] if stats["trace_seconds"] > 0 else 0.0
        trace = rays_per_pixel * pixels / rays_per_second if rays_per_second > 0 else 0.0
        estimates.append(
            Estimate(
                preset=key,
                seconds=export_seconds + stats["compile_seconds"] + trace,
                rays_per_pixel=rays_per_pixel,
                rays_per_second=rays_per_second,
            )
        )
    return (width, height), (xmax - xmin, ymax - ymin), estimates


def _render(job):
    job.start()
    while not job.wait(POLL_SECONDS):
        continue
    return job.stats()
