"""Predict each preset's full render time and its error against Reference from a probe.

The scene is exported once; each preset then traces the probe: one tile in n^2 of
the frame at full resolution (estimate_model.py says why, and the formulas). From
the same probe renders come the time (rays scaled by the pixel count, at the
probe's ray rate) and the error (RMSE of each preset's probe pixels, as displayed,
against the Reference preset's). The first probe job of each preset warms the caches
(the first of all measures the scene compile) and gives the pixels of the error and
the rays per pixel; the rate comes from jobs in larger tiles
(estimate_model.TIMING_TILE_SIZE) of at least MIN_JOB_SECONDS (a cheap preset's
timing jobs take denser tiles), repeated until they have traced for
MIN_PROBE_SECONDS, the rate taken over all of them. The export, which a fast scene
repeats (FIXED_BUDGET_SECONDS), gives the fixed costs, less what a render's depsgraph
does before the engine starts (copy_seconds).
docs/notes/estimate_accuracy.md gives the measured accuracy of both predictions.
"""

import statistics
import time
from dataclasses import dataclass

from . import estimate_model as model
from .export.mesh import copied_for_normals, mesh_instances
from .export.motion import scene_frame_set
from .properties.presets import PRESETS
from .sync.frame import sync_frame

REFERENCE = "REFERENCE"  # the preset the errors are measured against
# How long one poll of a probe job waits.
POLL_SECONDS = 0.1
# Trace time a probe gathers (over repeats) before its ray rate is trusted ...
MIN_PROBE_SECONDS = 0.3
# ... in jobs of at least this long (else its tiles are made denser).
MIN_JOB_SECONDS = 0.1
# Repeats of one probe at most, however fast it is.
MAX_PROBE_REPEATS = 10
# The start-up job: this many one-pixel tiles (enough to start every worker thread) of
# camera rays only.
STARTUP_PIXELS = 64
STARTUP_REPEATS = 3
# One export of a scene can take 10-15% more or less than the next on a quiet machine
# (the Python export is bound by memory; whitted_tools estimate-accuracy shows the fixed
# costs of the renders after it). While the exports so far took less than this in
# all, the scene is exported again, FIXED_REPEATS times at most, and the median kept:
# a fast scene's fixed costs, often most of its Draft render, are not one draw.
FIXED_BUDGET_SECONDS = 1.5
FIXED_REPEATS = 3


@dataclass(frozen=True)
class Estimate:
    preset: str  # key in properties.presets.PRESETS
    seconds: float  # predicted full render time
    error: float  # predicted display RMSE against Reference, 8-bit levels; 0 for Reference
    rays_per_pixel: float  # on the probe (the full render's, per pixel)
    rays_per_second: float  # on the probe


@dataclass(frozen=True)
class Probe:
    pixels: int  # the errors' probe (a cheap preset's time comes from more)
    stride: int  # one tile in stride^2
    width: int  # the full render's region (the border, or the whole frame)
    height: int
    # The export (the median of its repeats, less the copies a render skips: copy_seconds)
    # and the scene compile.
    fixed_seconds: float
    startup_seconds: float  # starting the worker threads

    def describe(self):
        return (
            f"{self.pixels:,}-pixel probe (1 tile in {self.stride**2}) "
            f"of {self.width}x{self.height}"
        )


def estimate_presets(depsgraph, native):
    """(Probe, [Estimate per preset], the memory.MemoryEstimate of the full render) for
    the evaluated depsgraph's scene. Raises what sync.frame.sync_frame raises."""
    frame, export_seconds = _export(depsgraph, native)
    xmin, ymin, xmax, ymax = frame.film.region
    pixels = (xmax - xmin) * (ymax - ymin)
    stride = model.probe_stride(pixels)
    # The first job compiles the scene, as a full render's does; later ones reuse it.
    startup, compile_seconds = _startup_seconds(native, frame)
    probes = {}  # preset key -> (stats, rays per second, probe pixels' RGB)
    for key, _, _, quality in PRESETS:
        settings = frame.at_quality(depsgraph, native, quality)
        settings.tile_size = model.PROBE_TILE_SIZE
        settings.probe_stride = stride
        probes[key] = _probe(native, frame, settings, startup)
    fixed = max(0.0, export_seconds - copy_seconds(depsgraph)) + compile_seconds
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
        pixels=len(reference),
        stride=stride,
        width=xmax - xmin,
        height=ymax - ymin,
        fixed_seconds=fixed,
        startup_seconds=startup,
    )
    return probe, estimates, frame.memory


def render_differences(depsgraph):
    """How a render's geometry will differ from the evaluated (viewport) `depsgraph`'s,
    as short sentences. The Estimate measures the viewport's depsgraph (Python cannot
    make a render one), and F12 evaluates each modifier with its render settings: this
    lists, for the objects the viewport shows, the modifiers enabled in one of the two
    only and the Subdivision Surface and Multiresolution levels that differ. Geometry
    nodes that ask Is Viewport, and objects shown in one of the two only, are not
    seen."""
    differences = []
    for obj in depsgraph.scene.objects:
        if not obj.visible_get(view_layer=depsgraph.view_layer):
            continue
        for modifier in obj.modifiers:
            if modifier.show_viewport != modifier.show_render:
                where = "the viewport" if modifier.show_viewport else "renders"
                differences.append(
                    f"'{obj.name}': modifier '{modifier.name}' is on in {where} only"
                )
            elif (
                modifier.show_render
                and modifier.type in ("SUBSURF", "MULTIRES")
                and modifier.levels != modifier.render_levels
            ):
                differences.append(
                    f"'{obj.name}': '{modifier.name}' subdivides {modifier.levels} times in "
                    f"the viewport, {modifier.render_levels} in renders"
                )
    return differences


def copy_seconds(depsgraph):
    """Seconds the export of the viewport's `depsgraph` spends on meshes that a render
    reads in place (export.mesh.copied_for_normals: Blender < 4.1 meshes with auto
    smooth or custom normals, whose corner normals a render depsgraph computes before
    the engine starts): their copy and normals made again, once each, and timed. On a
    glTF model of 29 such meshes the Estimate's export was 40% above the render's
    without this (whitted_tools estimate-accuracy --third-party two_cylinder_engine shows
    both, in its fixed-cost column)."""
    seconds = 0.0
    seen = set()
    for object_instance, key in mesh_instances(depsgraph):
        obj = object_instance.object
        if key in seen or not copied_for_normals(obj):
            continue
        seen.add(key)
        started = time.perf_counter()
        try:
            copy = obj.to_mesh()
        except RuntimeError:  # the export could not make it a mesh either, and said so
            continue
        copy.calc_normals_split()
        obj.to_mesh_clear()
        seconds += time.perf_counter() - started
    return seconds


def _export(depsgraph, native):
    """(the Frame of the depsgraph, the median seconds its export took): the scene is
    exported again while that is cheap (FIXED_BUDGET_SECONDS), keeping the last
    export only, so that no more than one native scene is held at a time."""
    seconds = []
    frame = None
    while not seconds or (len(seconds) < FIXED_REPEATS and sum(seconds) < FIXED_BUDGET_SECONDS):
        frame = None  # the previous export's native scene goes before the next is made
        started = time.perf_counter()
        frame = sync_frame(depsgraph, native, frame_set=scene_frame_set(depsgraph.scene))
        seconds.append(time.perf_counter() - started)
    return frame, statistics.median(seconds)


def _startup_seconds(native, frame):
    """(seconds a job takes to start its worker threads: the fastest of a few jobs that
    trace STARTUP_PIXELS camera rays, one pixel a tile; seconds the first of them took
    to compile the scene)."""
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
    runs = [_render(frame.job(native, settings)) for _ in range(STARTUP_REPEATS)]
    return min(stats["trace_seconds"] for stats in runs), runs[0]["compile_seconds"]


def _probe(native, frame, settings, startup):
    """(statistics of the probe, its rays per second, float64[probe pixels, 3] linear
    RGB of the probe at `settings`).

    The first job, at `settings`, gives the pixels the errors are measured on and the
    rays per pixel, and warms the caches. When it traced for MIN_PROBE_SECONDS its rate
    is taken; otherwise the rate comes from timing jobs in tiles of TIMING_TILE_SIZE.
    A job of a few milliseconds times mostly the machine (a thread that waits for a
    core on a busy machine waits as long as the job): while a timing job traces for
    less than MIN_JOB_SECONDS, the next takes four times the tiles (half the stride);
    they repeat until they have traced for MIN_PROBE_SECONDS."""
    job = frame.job(native, settings)
    stats = _render(job)
    # Every traced pixel took at least its camera ray; the others were not traced.
    values = job.image()[job.cost_image() > 0.0][:, :3]
    if stats["trace_seconds"] >= MIN_PROBE_SECONDS:
        rate = model.rays_per_second([stats["rays"]["total"]], [stats["trace_seconds"]], startup)
        return stats, rate, values
    timing = settings  # the first job's pixels are taken; its settings are not needed again
    timing.tile_size = model.TIMING_TILE_SIZE
    rays, traced = [], []
    while len(traced) < MAX_PROBE_REPEATS and sum(traced) < MIN_PROBE_SECONDS:
        timed = _render(frame.job(native, timing))
        if timed["trace_seconds"] < MIN_JOB_SECONDS and timing.probe_stride > 1:
            timing.probe_stride //= 2
            rays, traced = [], []  # a denser probe: start the timing again
            continue
        rays.append(timed["rays"]["total"])
        traced.append(timed["trace_seconds"])
    return stats, model.rays_per_second(rays, traced, startup), values


def _render(job):
    job.start()
    while not job.wait(POLL_SECONDS):
        continue
    return job.stats()
