"""The Whitted RenderEngine: export, start the native render, poll it, write tiles."""

import os
import time

import bpy

from . import result as render_result
from . import stats as render_stats
from .export import ExportError
from .export.film import convert_film
from .export.scene import convert_scene
from .native import load_native
from .properties.presets import quality_of
from .settings import native_settings

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

    def update_render_passes(self, scene=None, renderlayer=None):
        render_result.register_passes(self, scene, renderlayer)

    def render(self, depsgraph):
        phases = render_stats.PhaseTimes()
        started = time.perf_counter()
        scene = depsgraph.scene
        quality = quality_of(scene.whitted)
        try:
            native = load_native()
            exported = convert_scene(depsgraph, native)
            phases.mesh_bvh = exported.scene.mesh_build_seconds
            phases.export = time.perf_counter() - started - phases.mesh_bvh
            film = convert_film(scene.render, exported.width, exported.height)
            settings = native_settings(native, scene, exported.width, exported.height, film)
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
        render_result.add_passes(self)
        self._run(job, film.region, phases)
        phases.total = time.perf_counter() - started
        stats = render_stats.render_stats(
            bpy.app.version_string,
            quality,
            settings,
            job.stats(),
            phases,
            exported.sanitised,
            render_result.PASSES,
        )
        line = render_stats.summary_line(stats)
        effects = render_stats.effects_line(stats)
        self.update_stats("", line)
        self.report({"INFO"}, effects)
        print(line)  # for the logs of headless and farm renders
        print(effects)
        # The evaluated scene is a copy; Python reads the original.
        scene.original.whitted.last_stats = render_stats.to_json(stats)
        path = os.environ.get("WHITTED_STATS")
        if path:
            render_stats.write_json(path, stats)

    def _run(self, job, region, phases):
        started = time.perf_counter()
        job.start()
        # Nobody watches a background (farm) render: its tiles are written once, at
        # the end, which costs far less than many small writes (docs/PERFORMANCE.md).
        progressive = not bpy.app.background
        pending = []
        while True:
            finished = job.wait(POLL_SECONDS)
            pending += job.take_finished_tiles()
            if progressive:
                self._write(job, pending, region, phases)
                pending = []
            self.update_progress(job.progress)
            seconds = time.perf_counter() - started
            self.update_stats("", render_stats.progress_line(job.stats(), seconds))
            if finished:
                break
            if self.test_break():
                # Workers stop after their current pixel row; wait for that so the
                # statistics below are complete.
                job.cancel()
                job.wait(1.0)
                break
        self._write(job, pending + job.take_finished_tiles(), region, phases)
        native_stats = job.stats()
        phases.scene_bvh = native_stats["compile_seconds"]
        phases.trace = native_stats["trace_seconds"]

    def _write(self, job, tiles, region, phases):
        write_started = time.perf_counter()
        for tile in _clip_tiles(_merge_tiles(tiles), region):
            render_result.write_tile(self, job, tile, region)
        phases.writeback += time.perf_counter() - write_started


def _merge_tiles(tiles):
    """Finished tiles (x, y, w, h) merged into fewer rectangles: tiles side by side
    in a row into one, then rows of the same span on top of each other into one
    (a whole image becomes one rectangle).

    Each write into Blender's render result has a fixed cost (begin_result and
    end_result): at 1920x1080 one write per 32-pixel tile took about 100 ms in
    all. Only tiles that touch are merged, so no pixel still being traced is read.
    """
    rows = []
    for x, y, width, height in sorted(tiles, key=lambda t: (t[1], t[3], t[0])):
        if rows and rows[-1][1::2] == (y, height) and rows[-1][0] + rows[-1][2] == x:
            rows[-1] = (rows[-1][0], y, rows[-1][2] + width, height)
        else:
            rows.append((x, y, width, height))
    merged = []
    for x, y, width, height in rows:
        if merged and merged[-1][0::2] == (x, width) and merged[-1][1] + merged[-1][3] == y:
            merged[-1] = (x, merged[-1][1], width, merged[-1][3] + height)
        else:
            merged.append((x, y, width, height))
    return merged


def _clip_tiles(tiles, region):
    """The parts of tiles (x, y, w, h) inside region (xmin, ymin, xmax, ymax)."""
    xmin, ymin, xmax, ymax = region
    for x, y, width, height in tiles:
        left, bottom = max(x, xmin), max(y, ymin)
        right, top = min(x + width, xmax), min(y + height, ymax)
        if left < right and bottom < top:
            yield left, bottom, right - left, top - bottom
