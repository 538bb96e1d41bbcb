"""Predict each preset's full-resolution render time from a low-resolution probe.

The scene is exported once; each preset then renders the whole frame at
1/PROBE_DIVISOR of the resolution (in this process, with the native module).
The probe gives rays per pixel and rays per second; the prediction is
    export + BVH time (as measured) + rays per pixel * pixels / rays per second
with the probe's rays per pixel carried to full resolution: unchanged for grid
anti-aliasing, and for adaptive anti-aliasing the splits along edges scaled by
the probe's side over the full side (edges are curves: a probe pixel meets more
of them). A probe lasts milliseconds, so thread start-up and a cold cache would
dominate its time: one warm-up render runs first, and each probe repeats until
it has traced for MIN_PROBE_SECONDS, keeping its fastest rate.
docs/ACCURACY_COST.md gives the measured error of the prediction.
"""

import time
from dataclasses import dataclass, replace

from .properties.presets import PRESETS
from .settings import native_settings
from .sync import SyncParams
from .sync.frame import sync_frame

PROBE_DIVISOR = 8
# A probe narrower than this is not one (the whole frame when it is smaller).
MIN_PROBE_WIDTH = 80
# Small tiles keep every thread busy on the small probe: with few large tiles one
# expensive tile (glass) leaves the other threads idle and the rate looks halved.
PROBE_TILE_SIZE = 4
# How long one poll of a probe job waits.
POLL_SECONDS = 0.1
# Trace time a probe gathers (over repeats) before its ray rate is trusted.
MIN_PROBE_SECONDS = 0.1
# Repeats of one probe at most, however fast it is.
MAX_PROBE_REPEATS = 20


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
    """((probe width, height), (full width, height), [Estimate per preset], the
    memory.MemoryEstimate of the full render) for the evaluated depsgraph's scene.
    Raises what sync.frame.sync_frame raises."""
    scene = depsgraph.scene
    started = time.perf_counter()
    frame = sync_frame(depsgraph, native)
    export_seconds = time.perf_counter() - started
    film = frame.film
    xmin, ymin, xmax, ymax = film.region
    pixels = (xmax - xmin) * (ymax - ymin)
    width, height = probe_size(frame.width, frame.height)
    # The probe covers the whole (smaller) frame: no border.
    probe_film = replace(film, region=(0, 0, width, height))
    estimates = []
    for key, _, _, quality in PRESETS:
        # Soft-shadow samples and the texture filter are part of the scene: sync
        # them for this preset.
        frame.sync.sync(depsgraph, SyncParams.of(scene, quality))
        settings = native_settings(native, scene, width, height, probe_film, quality)
        settings.tile_size = PROBE_TILE_SIZE
        stats, rays_per_second = _probe(native, frame, settings)
        rays_per_pixel = _full_resolution_rays_per_pixel(
            native, settings, stats, width * height, width / frame.width
        )
        compile_seconds = stats["compile_seconds"]
        trace = rays_per_pixel * pixels / rays_per_second if rays_per_second > 0 else 0.0
        estimates.append(
            Estimate(
                preset=key,
                seconds=export_seconds + compile_seconds + trace,
                rays_per_pixel=rays_per_pixel,
                rays_per_second=rays_per_second,
            )
        )
    return (width, height), (xmax - xmin, ymax - ymin), estimates, frame.memory


def _probe(native, frame, settings):
    """(statistics, fastest rays per second) of the probe render, after a warm-up and
    over enough repeats to have traced for MIN_PROBE_SECONDS."""
    _render(frame.job(native, settings))  # warm-up: threads, caches
    traced = 0.0
    rates = []
    for _ in range(MAX_PROBE_REPEATS):
        stats = _render(frame.job(native, settings))
        rays = stats["rays"]["total"]
        if stats["trace_seconds"] > 0.0:
            rates.append(rays / stats["trace_seconds"])
        traced += stats["trace_seconds"]
        if traced >= MIN_PROBE_SECONDS:
            break
    return stats, max(rates, default=0.0)


def _full_resolution_rays_per_pixel(native, settings, stats, probe_pixels, scale):
    """Rays per pixel the full-resolution render will trace, from the probe's.

    Grid anti-aliasing takes the same samples per pixel at any resolution. Adaptive
    anti-aliasing takes 4 corner samples per pixel plus splits along edges; edges are
    curves, so the share of pixels they cross shrinks with the resolution's side (a
    probe pixel, 1/scale full pixels wide, meets 1/scale times as many edges).
    """
    rays_per_sample = stats["rays"]["total"] / stats["samples"] if stats["samples"] else 0.0
    samples_per_pixel = stats["samples"] / probe_pixels
    if settings.aa_mode == native.AntiAliasing.ADAPTIVE:
        samples_per_pixel = 4.0 + max(0.0, samples_per_pixel - 4.0) * scale
    return samples_per_pixel * rays_per_sample


def _render(job):
    job.start()
    while not job.wait(POLL_SECONDS):
        continue
    return job.stats()
