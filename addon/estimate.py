"""Predict each preset's full render time and its error against Reference from a probe.

The scene is exported once; each preset then traces the probe: one tile in n^2 of
the frame at full resolution (estimate_model.py says why, and the formulas). From
the same probe renders come the time (rays scaled by the pixel count, at the
probe's ray rate) and the error (RMSE of each preset's probe pixels, as displayed,
against the Reference preset's). A probe lasts milliseconds: one warm-up render runs
first (caches, and the scene compile, which is measured there), then the probe repeats
until it has traced for MIN_PROBE_SECONDS, its rate taken over all repeats.
docs/notes/estimate_accuracy.md gives the measured accuracy of both predictions.
"""

import time
from dataclasses import dataclass

from . import estimate_model as model
from .properties.presets import PRESETS
from .settings import native_settings
from .sync import SyncParams
from .sync.frame import sync_frame

REFERENCE = "REFERENCE"  # the preset the errors are measured against
# How long one poll of a probe job waits.
POLL_SECONDS = 0.1
# Trace time a probe gathers (over repeats) before its ray rate is trusted.
MIN_PROBE_SECONDS = 0.2
# Repeats of one probe at most, however fast it is.
MAX_PROBE_REPEATS = 10
# The start-up job: this many one-pixel tiles (enough to start every worker thread) of
# camera rays only.
STARTUP_PIXELS = 64
STARTUP_REPEATS = 3


@dataclass(frozen=True)
class Estimate:
    preset: str  # key in properties.presets.PRESETS
    seconds: float  # predicted full render time
    error: float  # predicted display RMSE against Reference, 8-bit levels; 0 for Reference
    rays_per_pixel: float  # on the probe (the full render's, per pixel)
    rays_per_second: float  # on the probe


@dataclass(frozen=True)
class Probe:
    pixels: int  # traced by the probe
    stride: int  # one tile in stride^2
    width: int  # the full render's region (the border, or the whole frame)
    height: int
    fixed_seconds: float  # export and scene compile, measured once
    startup_seconds: float  # starting the worker threads

    def describe(self):
        return (
            f"{self.pixels:,}-pixel probe (1 tile in {self.stride**2}) "
            f"of {self.width}x{self.height}"
        )


def estimate_presets(depsgraph, native):
    """(Probe, [Estimate per preset], the memory.MemoryEstimate of the full render) for
    the evaluated depsgraph's scene. Raises what sync.frame.sync_frame raises."""
    scene = depsgraph.scene
    started = time.perf_counter()
    frame = sync_frame(depsgraph, native)
    export_seconds = time.perf_counter() - started
    xmin, ymin, xmax, ymax = frame.film.region
    pixels = (xmax - xmin) * (ymax - ymin)
    stride = model.probe_stride(pixels)
    startup = _startup_seconds(native, frame)
    compile_seconds = None
    probes = {}  # preset key -> (stats, rays per second, probe pixels' RGB)
    for key, _, _, quality in PRESETS:
        # Soft-shadow samples and the texture filter are part of the scene: sync
        # them for this preset.
        frame.sync.sync(depsgraph, SyncParams.of(scene, quality))
        settings = native_settings(native, scene, frame.width, frame.height, frame.film, quality)
        settings.tile_size = model.PROBE_TILE_SIZE
        settings.probe_stride = stride
        warm_up = _render(frame.job(native, settings))
        if compile_seconds is None:
            # The first job compiles the scene as a full render's does; later ones reuse it.
            compile_seconds = warm_up["compile_seconds"]
        probes[key] = _probe(native, frame, settings, startup)
    fixed = export_seconds + compile_seconds
    reference = probes[REFERENCE][2]
    estimates = []
    for key, _, _, _ in PRESETS:
        stats, rate, values = probes[key]
        rays, probe_pixels = stats["rays"]["total"], stats["pixels"]
        estimates.append(
            Estimate(
                preset=key,
                seconds=model.predict_seconds(fixed, startup, rays, probe_pixels, pixels, rate),
                error=model.display_error(values, reference),
                rays_per_pixel=rays / probe_pixels if probe_pixels else 0.0,
                rays_per_second=rate,
            )
        )
    probe = Probe(
        pixels=probes[REFERENCE][0]["pixels"],
        stride=stride,
        width=xmax - xmin,
        height=ymax - ymin,
        fixed_seconds=fixed,
        startup_seconds=startup,
    )
    return probe, estimates, frame.memory


def _startup_seconds(native, frame):
    """Seconds a job takes to start its worker threads: the fastest of a few jobs that
    trace STARTUP_PIXELS camera rays, one pixel a tile."""
    xmin, ymin, xmax, _ = frame.film.region
    width = min(STARTUP_PIXELS, xmax - xmin)
    settings = native.Settings(
        width=frame.width,
        height=frame.height,
        border=(xmin, ymin, xmin + width, ymin + 1),
        max_depth=0,
        tile_size=1,
        threads=frame.settings.threads,
    )
    runs = (_render(frame.job(native, settings)) for _ in range(STARTUP_REPEATS))
    return min(stats["trace_seconds"] for stats in runs)


def _probe(native, frame, settings, startup):
    """(statistics, rays per second, float64[probe pixels, 3] linear RGB) of the probe
    render, over enough repeats to have traced for MIN_PROBE_SECONDS."""
    rays, traced = [], []
    for _ in range(MAX_PROBE_REPEATS):
        job = frame.job(native, settings)
        stats = _render(job)
        rays.append(stats["rays"]["total"])
        traced.append(stats["trace_seconds"])
        if sum(traced) >= MIN_PROBE_SECONDS:
            break
    # Every traced pixel took at least its camera ray; the others were not traced.
    values = job.image()[job.cost_image() > 0.0][:, :3]
    return stats, model.rays_per_second(rays, traced, startup), values


def _render(job):
    job.start()
    while not job.wait(POLL_SECONDS):
        continue
    return job.stats()
