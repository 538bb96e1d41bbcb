"""The Whitted RenderEngine: F12 and material previews (render), the Rendered
viewport (view_update, view_draw). Every kind of render goes through the one
sync layer (addon/sync); this class only hands each call to its owner."""

import os
import sys
import time
import traceback
from dataclasses import asdict

import bpy

from . import memory
from . import result as render_result
from . import stats as render_stats
from .denoise import denoise, denoising_of, rect_of
from .export import ExportError
from .export.film import pixel_filter_decision
from .export.instance import cryptomatte_names, writes_cryptomatte
from .native import load_native
from .properties.presets import preset, quality_of
from .sync.frame import sync_frame
from .viewport.session import ViewportSession

# One poll of the render job waits this long. Esc (test_break) is checked after
# every poll, so the render stops within this time plus the job's cancel latency.
POLL_SECONDS = 0.05

# A failed frame's log line starts with this (farms grep for it), and the exit code
# of a background render with WHITTED_EXIT_ON_ERROR=1 (see WhittedRenderEngine._fail).
FAILURE_PREFIX = "Whitted: RENDER FAILED:"
FAILURE_EXIT_CODE = 3


class WhittedRenderEngine(bpy.types.RenderEngine):
    bl_idname = "WHITTED"
    bl_label = "Whitted"
    # Material Properties' preview and material icons render with Whitted too.
    bl_use_preview = True
    # Use the artists' Cycles/EEVEE shader nodes (Principled BSDF) rather than
    # hiding them behind nodes of our own.
    bl_use_shading_nodes_custom = False

    # Blender 4.4+ requires this signature and the super() call; 3.4 accepts it.
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._viewport = None

    def __del__(self):
        # Blender frees the engine when the viewport leaves Rendered mode, its area
        # closes or Blender quits: the session's job stops here. This may run on an
        # instance whose __init__ never ran, or one whose Blender data is already freed
        # (at quit, after an F12 render: no viewport session was ever made for it).
        try:
            viewport = self._viewport
        except (AttributeError, ReferenceError):
            return
        if viewport is not None:
            viewport.stop()

    def update_render_passes(self, scene=None, renderlayer=None):
        render_result.register_passes(self, scene, renderlayer)

    # --- F12 and material previews ---------------------------------------------

    def render(self, depsgraph):
        # The engine's boundary with Blender: an exception that escapes render() crashes
        # Blender 3.4 as it then writes the frame's image (seen: a segmentation fault
        # saving a 32-bit OpenEXR with write_still). So every error, an expected one or a
        # bug, ends here as a failed frame with its report, and Blender lives on.
        try:
            self._render(depsgraph)
        except Exception as error:  # noqa: BLE001 - the boundary above: nothing may escape
            traceback.print_exc()
            self._fail(depsgraph.scene, f"Whitted: internal error: {error!r}")

    def _render(self, depsgraph):
        phases = render_stats.PhaseTimes()
        started = time.perf_counter()
        scene = depsgraph.scene
        # Material previews and icons sample as the viewport does (as Cycles' previews
        # take its viewport samples): its preset and its Denoise switch.
        if self.is_preview:
            quality = preset(scene.whitted.viewport_preset)
        else:
            quality = quality_of(scene.whitted)
        passes = render_result.enabled_passes(depsgraph.view_layer)
        try:
            native = load_native()
            frame_set = None if self.is_preview else self.frame_set
            frame = sync_frame(depsgraph, native, quality, frame_set=frame_set)
            phases.mesh_bvh = frame.sync.scene.mesh_build_seconds
            phases.export = time.perf_counter() - started - phases.mesh_bvh
            denoising = denoising_of(scene, native, viewport=self.is_preview)
            # Sampling > Render > Time Limit: F12's alone (the viewport refines until done).
            frame.settings.time_limit = scene.whitted.time_limit
            render_result.configure(
                frame.settings, scene, depsgraph.view_layer, passes, guides=denoising.on
            )
            job = frame.job(native)
        except (ImportError, ExportError) as error:
            self._fail(scene, str(error))
            return
        except (ValueError, RuntimeError) as error:
            # The native module refused the data (bad arrays, a missing name, ...).
            self._fail(scene, f"Whitted: the renderer refused the scene: {error}")
            return
        if not self.is_preview:
            for warning in frame.warnings:
                self.report({"WARNING"}, warning)
        render_result.add_passes(self, passes)
        try:
            self._run(job, frame.film.region, phases, passes)
        except (MemoryError, RuntimeError) as error:
            # A worker failed (out of memory, say): the job stopped all of them.
            self._fail(scene, f"Whitted: the render failed: {error}")
            return
        if denoising.on and not job.stats()["cancelled"]:
            self._denoise(native, job, frame, phases, passes, denoising)
        if self.is_preview:
            return  # Blender's preview scene: no statistics, nothing to keep
        if writes_cryptomatte(depsgraph.view_layer):
            names = cryptomatte_names(depsgraph)
            render_result.add_cryptomatte_metadata(self, depsgraph.view_layer, names)
        phases.total = time.perf_counter() - started
        stats = render_stats.render_stats(
            bpy.app.version_string,
            quality,
            frame.settings,
            job.stats(),
            phases,
            asdict(frame.sync.sanitised),
            [spec.name for spec in passes],
        )
        stats["effects"] += [
            pixel_filter_decision(frame.film, quality.aa_mode),
            render_stats.sampling_decision(stats),
            denoising.decision(),
        ]
        displaced = frame.sync.displacement_effect()
        if displaced is not None:
            stats["effects"].append(displaced)
        stats["sync"] = frame.report.as_dict()
        # What the memory guard expected this render to need (docs/MEMORY.md).
        stats["memory_estimate_mib"] = frame.memory.bytes / memory.MIB
        stats["status"] = "ok"  # a failed frame's WHITTED_STATS says "failed" (_fail)
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

    def _fail(self, scene, message):
        """A failed frame, made visible to farms: Blender itself writes the (empty)
        image and exits 0 after an engine error, so Whitted says so three ways:
        the error report, one log line that starts with FAILURE_PREFIX, and, when
        WHITTED_STATS is set, a JSON {"status": "failed", "error": ...} in place of
        the statistics. With WHITTED_EXIT_ON_ERROR=1 a background render
        (`blender -b ... -f N`) then ends the process at once with exit code
        FAILURE_EXIT_CODE, before Blender saves an image for the frame."""
        self.report({"ERROR"}, message)
        if self.is_preview:
            return
        frame = scene.frame_current
        line = f"{FAILURE_PREFIX} frame {frame}: {message.removeprefix('Whitted: ')}"
        print(line, file=sys.stderr, flush=True)
        path = os.environ.get("WHITTED_STATS")
        if path:
            failure = {
                "status": "failed",
                "error": message,
                "frame": frame,
                "blender": bpy.app.version_string,
            }
            render_stats.write_json(path, failure)
        if bpy.app.background and os.environ.get("WHITTED_EXIT_ON_ERROR") == "1":
            sys.stdout.flush()
            os._exit(FAILURE_EXIT_CODE)

    def _run(self, job, region, phases, passes):
        started = time.perf_counter()
        job.start()
        # Nobody watches a background (farm) render: its tiles are written once, at
        # the end, which costs far less than many small writes (docs/PERFORMANCE.md).
        progressive = not bpy.app.background
        pending = []
        try:
            while True:
                # Raises what a worker raised, once all workers have stopped.
                finished = job.wait(POLL_SECONDS)
                pending += job.take_finished_tiles()
                if progressive:
                    self._write(job, pending, region, phases, passes)
                    pending = []
                self.update_progress(job.progress)
                seconds = time.perf_counter() - started
                self.update_stats("", render_stats.progress_line(job.stats(), seconds))
                if finished:
                    break
                if self.test_break():
                    # Workers stop after their current pixel row; wait for that so
                    # the statistics below are complete.
                    job.cancel()
                    job.wait(1.0)
                    break
        finally:
            # What was finished is kept, even when the render failed.
            self._write(job, pending + job.take_finished_tiles(), region, phases, passes)
        native_stats = job.stats()
        phases.world_light = native_stats["world_light_seconds"]
        phases.scene_bvh = native_stats["compile_seconds"] - phases.world_light
        phases.trace = native_stats["trace_seconds"]

    def _denoise(self, native, job, frame, phases, passes, denoising):
        """Replace the finished render's Combined, and its Shadow Catcher pass when it has
        one, by their denoised images (the other passes, Noisy Image and Noisy Shadow
        Catcher among them, keep the job's)."""
        self.update_stats("", "Whitted | denoising")
        started = time.perf_counter()
        region = frame.film.region
        rect = rect_of(region)
        sources = {s.name: s.source for s in passes if s in render_result.DENOISED_PASSES}
        try:
            clean = {
                name: denoise(native, job, rect, denoising, frame.settings.threads, source=source)
                for name, source in sources.items()
            }
        except RuntimeError as error:
            # The library failed on this image (out of memory, say): keep the noisy one.
            self.report({"WARNING"}, f"Whitted: denoising failed, image left noisy: {error}")
            return
        phases.denoise = time.perf_counter() - started
        write_started = time.perf_counter()
        render_result.write_tile(self, job, rect, region, passes, replaced=clean)
        phases.writeback += time.perf_counter() - write_started

    def _write(self, job, tiles, region, phases, passes):
        write_started = time.perf_counter()
        for tile in _clip_tiles(_merge_tiles(tiles), region):
            render_result.write_tile(self, job, tile, region, passes)
        phases.writeback += time.perf_counter() - write_started

    # --- the Rendered viewport --------------------------------------------------

    def view_update(self, context, depsgraph):
        if self._viewport is None:
            try:
                self._viewport = ViewportSession(self, load_native())
            except ImportError as error:
                self.update_stats("", str(error))
                return
        self._viewport.update(context, depsgraph)

    def view_draw(self, context, depsgraph):
        if self._viewport is not None:
            self._viewport.draw(context, depsgraph)


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
