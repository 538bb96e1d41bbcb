"""The Whitted RenderEngine: export, start the native render, poll it, write tiles."""

import os
import time

import bpy

from . import stats as render_stats
from .export import ExportError
from .export.film import convert_film
from .export.scene import convert_scene
from .native import load_native

# One poll of the render job waits this long. Esc (test_break) is checked after
# every poll, so the render stops within this time plus the job's cancel latency.
POLL_SECONDS = 0.05


class WhittedRenderEngine(bpy.types.RenderEngine):
    bl_idname = "WHITTED"
    bl_label = "Whitted"
    bl_use_preview = False
    # Use the artists' Cycles/EEVEE shader nodes (Principled BSDF) rather than
    # hiding them behind nodes of our own.
    bl_use_shading_nodes_custom = False

    def render(self, depsgraph):
        phases = render_stats.PhaseTimes()
        started = time.perf_counter()
        try:
            native = load_native()
            exported = convert_scene(depsgraph, native)
            phases.mesh_bvh = exported.scene.mesh_build_seconds
            phases.export = time.perf_counter() - started - phases.mesh_bvh
            film = convert_film(depsgraph.scene.render, exported.width, exported.height)
            settings = _settings(native, depsgraph.scene, exported, film)
            job = native.RenderJob(exported.scene, settings)
        except (ImportError, ExportError) as error:
            self.report({"ERROR"}, str(error))
            return
        except (ValueError, RuntimeError) as error:
            # The native module refused the data (bad arrays, a missing name, ...).
            self.report({"ERROR"}, f"Whitted: the renderer refused the scene: {error}")
            return
        for warning in exported.warnings:
            self.report({"WARNING"}, warning)
        self._run(job, film.region, phases)
        phases.total = time.perf_counter() - started
        stats = render_stats.render_stats(
            bpy.app.version_string, settings, job.stats(), phases, exported.sanitised
        )
        line = render_stats.summary_line(stats)
        self.update_stats("", line)
        print(line)  # for the logs of headless and farm renders
        path = os.environ.get("WHITTED_STATS")
        if path:
            render_stats.write_json(path, stats)

    def _run(self, job, region, phases):
        started = time.perf_counter()
        job.start()
        while True:
            finished = job.wait(POLL_SECONDS)
            write_started = time.perf_counter()
            self._write_finished_tiles(job, region)
            phases.writeback += time.perf_counter() - write_started
            self.update_progress(job.progress)
            self.update_stats("", _progress_line(job.stats(), time.perf_counter() - started))
            if finished:
                break
            if self.test_break():
                # Workers stop after their current pixel row; wait for that so the
                # statistics below are complete.
                job.cancel()
                job.wait(1.0)
                break
        native_stats = job.stats()
        phases.scene_bvh = native_stats["compile_seconds"]
        phases.trace = native_stats["trace_seconds"]

    def _write_finished_tiles(self, job, region):
        # Tile rows run bottom to top, as in Blender's render result. The fast path
        # is foreach_set of C-contiguous float32 pixels, but `rect.foreach_set`
        # wants shape (w*h, 4) in Blender 3.4 and a flat (w*h*4,) array in 5.0.
        # `passes.foreach_set("rect", flat)` takes the flat array in both; it fills
        # every pass in turn, and Whitted adds none, so the layer holds only Combined.
        for x, y, width, height in _clip_tiles(job.take_finished_tiles(), region):
            # The render result covers only the region (the render border), so
            # its pixel (0, 0) is the region's corner.
            result = self.begin_result(x - region[0], y - region[1], width, height)
            pixels = job.tile(x, y, width, height).reshape(-1)  # a view, no copy
            result.layers[0].passes.foreach_set("rect", pixels)
            self.end_result(result)


def _clip_tiles(tiles, region):
    """The parts of tiles (x, y, w, h) inside region (xmin, ymin, xmax, ymax)."""
    xmin, ymin, xmax, ymax = region
    for x, y, width, height in tiles:
        left, bottom = max(x, xmin), max(y, ymin)
        right, top = min(x + width, xmax), min(y + height, ymax)
        if left < right and bottom < top:
            yield left, bottom, right - left, top - bottom


def _settings(native, scene, exported, film):
    whitted = scene.whitted
    return native.Settings(
        width=exported.width,
        height=exported.height,
        border=film.region,
        transparent_background=film.transparent_background,
        max_depth=whitted.max_depth,
        aa_samples=whitted.aa_samples,
        # Blender's thread setting (Auto = all cores, or the -t command-line value).
        threads=scene.render.threads,
        tile_size=whitted.tile_size,
        fresnel=getattr(native.Fresnel, whitted.fresnel),
    )


def _progress_line(stats, seconds):
    rays = stats["rays"]["total"]
    rate = rays / seconds / 1e6 if seconds > 0.0 else 0.0
    return (
        f"Whitted | {stats['threads']} threads | {rays / 1e6:.1f} M rays "
        f"| {rate:.1f} M rays/s | {seconds:.1f} s"
    )
