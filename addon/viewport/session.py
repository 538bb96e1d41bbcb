"""One Rendered viewport: sync on view_update, restart and draw on view_draw.

Blender calls both on the main thread. `view_update` follows every change of
the scene: the running job is cancelled and the sync (addon/sync) brings the
native scene up to date. A change of view (orbit, pan, zoom, resize, camera
view) reaches only `view_draw`, which compares the view with the one the job
renders and restarts it without a sync. The job refines progressively (coarse
blocks, then full resolution, then anti-aliasing samples up to the viewport's
quality preset); a main-thread timer polls its frame counter and asks for a
redraw only when a new pass exists or the job has ended, and stops once the last
pass is shown and the job has ended, so a converged viewport costs no CPU. No bpy
data is read off the main thread.
"""

import math
import time
import weakref
from dataclasses import dataclass

import bpy
import numpy as np

from .. import memory
from ..denoise import GUIDE_SOURCES, BackgroundDenoise, denoising_of, rect_of
from ..export import ExportError
from ..export.camera import image_size, lens_data, panorama_data, projection_of
from ..export.film import convert_film
from ..properties.presets import preset
from ..result import MAX_CONTRIBUTION_DEPTH, mist_of, viewport_display
from ..settings import native_settings
from ..sync import SceneSync, SyncParams
from ..sync.native_data import native_camera
from .camera import ViewCamera, border_pixels, camera_frame, through_camera, view_camera
from .display import Display
from .log import ViewportLog

# How often the timer polls the job for a new pass.
POLL_SECONDS = 0.01
# The first image of a new state should appear within one frame of a 30 Hz display.
FIRST_PASS_SECONDS = 0.03
# How long a redraw right after a restart waits for that first pass.
FIRST_PASS_WAIT = 0.05
# The first pass used before any speed was measured, in pixels a side (a power of two;
# the coarsest is native Settings.start_pixel_size's maximum).
DEFAULT_START_PIXEL_SIZE = 8
# The viewport's workers' niceness (0 normal .. 19 lowest, native LIMITS).
WORKER_NICE = 10


@dataclass(frozen=True)
class ViewSetup:
    """What a viewport job renders: a change of any field restarts it."""

    camera: ViewCamera
    width: int  # render pixels: the region's size over the preview pixel size
    height: int
    region_width: int  # the region it is drawn over
    region_height: int
    border: tuple | None  # (xmin, ymin, xmax, ymax) render pixels, or None: all
    # Settings that change the image besides the scene: the viewport's quality
    # preset, transparent film, render threads, the display's passes, denoising.
    settings: tuple


class ViewportSession:
    def __init__(self, engine, native):
        self._engine = weakref.ref(engine)
        self._native = native
        self._sync = SceneSync(native)
        self._log = ViewportLog.from_environment()
        self._display = Display()
        self._job = None
        self._setup = None  # ViewSetup of the job
        self._scene_version = 0  # counts syncs
        self._job_version = -1  # the sync the job renders
        self._shown = 0  # the job's frame in the texture
        self._converged = False
        # What the texture shows: RenderJob.display's (kind, first channel): the image,
        # the ray cost heat map or a film pass (result.VIEWPORT_DISPLAYS).
        self._kind = ("image", 0)
        self._samples_per_second = None  # measured camera samples a second
        self._last_sync = None
        self._error = ""
        self._poll = None  # the registered timer function
        self._started = 0.0  # time.perf_counter() when the job started
        # Sampling > Viewport > Denoise: whether the job's last pass is denoised, and
        # the denoise running on its own thread (denoise.BackgroundDenoise).
        self._denoising = None
        self._denoise = None
        self._denoised = False  # the texture shows the denoised last pass

    # --- view_update -------------------------------------------------------------

    def update(self, context, depsgraph):
        # The job renders its own snapshot of the native scene, so it may run on while
        # the sync edits the scene: many updates (selection, a panel's setting that
        # does not change the image) change nothing, and then the job goes on.
        scene = depsgraph.scene
        if self._scene_version == 0:
            # The first sync exports everything: refuse a scene that would not fit.
            region = context.region
            pixels = region.width * region.height if region is not None else 0
            try:
                memory.check(depsgraph, pixels)
            except ExportError as error:
                self._error = str(error)
                self._status()
                return
        try:
            report = self._sync.sync(depsgraph, SyncParams.of(scene, _quality(scene)))
        except ValueError as error:
            # The native module refused data; keep the last image, say why, and export
            # everything again at the next update (this sync may be half done).
            self._stop_job()
            self._sync = SceneSync(self._native)
            self._error = f"Whitted: the renderer refused the scene: {error}"
            self._status()
            return
        self._error = ""
        if report.changed or self._scene_version == 0:
            self._scene_version += 1
            if self._setup is not None:
                # The view is the one of the last draw until view_draw says otherwise:
                # start now rather than a redraw later.
                self._start(self._setup, scene)
            else:
                self._stop_job()
        self._last_sync = report
        self._log.write("sync", **report.as_dict())
        engine = self._engine()
        if engine is not None:
            engine.tag_redraw()

    # --- view_draw ---------------------------------------------------------------

    def draw(self, context, depsgraph):
        scene = depsgraph.scene
        engine = self._engine()
        if engine is None:
            return
        setup = _view_setup(context, scene, engine.get_preview_pixel_size(scene))
        if self._scene_version == 0:
            return  # not synced yet (view_update comes first)
        if self._job is None or setup != self._setup or self._job_version != self._scene_version:
            self._start(setup, scene)
        shown = viewport_display(scene.whitted.viewport_display)
        kind = (shown.kind, shown.first)
        if kind != self._kind:
            self._kind = kind
            self._shown = 0  # show the current pass again, as the other kind
        if self._job is not None:
            self._wait_for_first_pass()
            self._show_new_pass()
            self._show_denoised()
        if self._display.draw(0, 0, setup.region_width, setup.region_height):
            self._log.write("draw", frame=self._shown)
        self._status()

    def _start(self, setup, scene):
        self._stop_job()
        self._setup = setup
        self._job_version = self._scene_version
        if self._error:
            return
        settings = native_settings(
            self._native,
            scene,
            setup.width,
            setup.height,
            convert_film(
                scene,
                setup.width,
                setup.height,
                region=setup.border or (0, 0, setup.width, setup.height),
            ),
            _quality(scene),
        )
        # The film passes the display shows, if any: asked for only then, so the image
        # and the cost cost what they did without passes.
        shown = viewport_display(scene.whitted.viewport_display)
        if shown.passes:
            settings.passes = list(shown.passes)
            settings.contribution_depth = MAX_CONTRIBUTION_DEPTH
            settings.pass_alpha_threshold = bpy.context.view_layer.pass_alpha_threshold
            settings.mist = mist_of(scene.world)
        self._denoising = denoising_of(scene, self._native, viewport=True)
        if self._denoising.on:
            # The denoiser's guides (denoise.py), kept only when it runs.
            settings.passes = sorted(set(settings.passes) | set(GUIDE_SOURCES))
        settings.progressive = True
        settings.start_pixel_size = self._start_pixel_size(setup)
        # Below the interface's priority: Blender's own thread, which polls the job
        # and uploads each pass, must not wait for a core behind the workers.
        settings.worker_nice = WORKER_NICE
        self._job = self._native.RenderJob(
            self._sync.scene, settings, camera=native_camera(self._native, setup.camera)
        )
        self._job.start()
        self._started = time.perf_counter()
        self._shown = 0
        self._converged = False
        self._denoised = False
        self._start_polling()

    def _wait_for_first_pass(self):
        """Right after a restart, wait (at most FIRST_PASS_WAIT) for the first pass,
        which is sized to take FIRST_PASS_SECONDS: this redraw then shows the new
        state, rather than the old image and another redraw later (on a busy machine
        a redraw of the window can take longer than the pass)."""
        deadline = self._started + FIRST_PASS_WAIT
        while self._job.frame == 0 and time.perf_counter() < deadline:
            if self._job.wait(0.002):
                break

    def _start_pixel_size(self, setup):
        """The finest power-of-two block size whose pass takes at most
        FIRST_PASS_SECONDS at the speed measured on earlier passes."""
        if not self._samples_per_second:
            return DEFAULT_START_PIXEL_SIZE
        pixels = setup.width * setup.height
        blocks_allowed = max(1.0, FIRST_PASS_SECONDS * self._samples_per_second)
        size = 2 ** math.ceil(math.log2(max(1.0, math.sqrt(pixels / blocks_allowed))))
        return min(int(self._native.LIMITS["start_pixel_size"][1]), size)

    def _show_new_pass(self):
        job = self._job
        try:
            finished = job.wait(0.0)  # raises what a worker raised
        except (MemoryError, RuntimeError) as error:
            self._error = f"Whitted: the viewport render failed: {error}"
            self._stop_job()
            return
        frame = job.frame
        if frame != self._shown:
            self._display.upload(job.display(*self._kind))
            self._shown = frame
            self._log.write("frame", frame=frame, **job.pass_info())
        # The last pass is published before the workers end: the job may finish after
        # its last frame was shown, at a later draw (the timer asks for one).
        if not finished or self._converged:
            return
        info = job.pass_info()
        stats = job.stats()
        if stats["trace_seconds"] > 0.0 and stats["samples"] > 0:
            self._samples_per_second = stats["samples"] / stats["trace_seconds"]
        if info["pass"] == info["passes"]:
            self._converged = True
            self._log.write("converged", waves=stats["waves"])
            if self._denoising.on and self._kind == ("image", 0):
                setup = self._setup
                region = setup.border or (0, 0, setup.width, setup.height)
                self._denoise = BackgroundDenoise(
                    self._native, job, rect_of(region), self._denoising, stats["threads"]
                )

    def _show_denoised(self):
        """Once the background denoise is done: its image in the texture (the border's
        rectangle of the film's), or why it failed in the status line."""
        result = self._denoise
        if result is None or not result.done or self._kind != ("image", 0):
            return
        self._denoise = None
        if result.result is None:
            self._error = f"Whitted: viewport denoising failed: {result.error}"
            return
        image = self._job.display("image")
        x, y, width, height = result.rect
        clean = result.result.reshape(height, width, 4)
        # As the film's display: finite, below the half-float maximum.
        image[y : y + height, x : x + width] = np.clip(np.nan_to_num(clean), 0.0, 65000.0)
        self._display.upload(image)
        self._denoised = True
        self._log.write("denoised")

    def _status(self):
        engine = self._engine()
        if engine is None:
            return
        if self._error:
            engine.update_stats("", self._error)
            return
        parts = ["Whitted"]
        if self._job is not None and self._shown:
            info = self._job.pass_info()
            stats = self._job.stats()
            rate = stats["rays"]["total"] / stats["trace_seconds"] if stats["trace_seconds"] else 0
            if info["pixel_size"] > 1:
                parts.append(f"pass {info['pass']}/{info['passes']} ({info['pixel_size']} px)")
            else:
                parts.append(f"pass {info['pass']}/{info['passes']}, {info['samples']} spp")
            parts.append(f"{rate / 1e6:.1f} M rays/s")
            if self._converged:
                parts.append("denoised" if self._denoised else "done")
        if self._last_sync is not None:
            parts.append(self._last_sync.describe())
        engine.update_stats("", " | ".join(parts))

    # --- polling and stopping ----------------------------------------------------

    def _start_polling(self):
        if self._poll is not None:
            return
        session = weakref.ref(self)

        def poll():
            # A timer holds only a weak reference: a freed session stops polling.
            alive = session()
            return None if alive is None else alive._on_timer()

        self._poll = poll
        bpy.app.timers.register(poll, first_interval=POLL_SECONDS)

    def _on_timer(self):
        """Ask for a redraw when the job has a new pass, or its denoise is done; stop once
        converged (and denoised)."""
        if self._job is None or (self._converged and self._denoise is None):
            self._poll = None
            return None
        engine = self._engine()
        if engine is None:
            self._poll = None
            return None
        if (
            self._job.frame != self._shown
            or self._ended_unseen()
            or (self._denoise is not None and self._denoise.done)
        ):
            try:
                engine.tag_redraw()
            except ReferenceError:
                # Blender freed the engine's data before its Python object.
                self._poll = None
                return None
        return POLL_SECONDS

    def _ended_unseen(self):
        """The job has ended since the last draw took in its state: its last pass may have
        been shown while the workers were still finishing, or a worker failed."""
        if self._converged:
            return False
        try:
            return self._job.wait(0.0)
        except (MemoryError, RuntimeError):
            return True  # the draw reports it

    def _stop_job(self):
        if self._denoise is not None:
            self._denoise.stop()
            self._denoise = None
        if self._job is None:
            return
        self._job.cancel()
        # Dropping the job joins its workers, which stop after their current row.
        self._job = None
        self._log.write("stop")

    def stop(self):
        """End the session: the job stops, the timer with it."""
        self._stop_job()
        if self._poll is not None and bpy.app.timers.is_registered(self._poll):
            bpy.app.timers.unregister(self._poll)
        self._poll = None


def _quality(scene):
    # The viewport has its own preset, apart from F12's controls (as Cycles keeps
    # viewport samples apart).
    return preset(scene.whitted.viewport_preset)


def region_camera(scene, space, view, width, height):
    """The ViewCamera a 3D view (`space`, its region data `view`) renders through at
    width x height pixels: its own matrices; in camera view also the camera's depth of
    field and, for a panoramic camera, its projection over the camera frame (as Cycles'
    viewport shows them)."""
    camera = view_camera(view.view_matrix, view.window_matrix, view.is_perspective)
    if view.view_perspective != "CAMERA":
        return camera
    camera_object = space.camera if space.use_local_camera else scene.camera
    if camera_object is None or camera_object.type != "CAMERA":
        return camera
    data = camera_object.data
    projection = projection_of(data)
    lens = lens_data(camera_object, projection)
    if projection != "PANORAMIC":
        return through_camera(camera, lens)
    corners = [camera_object.matrix_world @ corner for corner in data.view_frame(scene=scene)]
    frame = camera_frame(view.perspective_matrix, corners, width, height)
    panorama = panorama_data(data, *image_size(scene.render), scene.render)
    return through_camera(
        camera, lens, panorama, frame, (width, height), (data.shift_x, data.shift_y)
    )


def _view_setup(context, scene, pixel_size):
    region = context.region
    view = context.region_data
    space = context.space_data
    # render.preview_pixel_size (1-8, or automatic by the display's DPI) divides the
    # resolution; the texture is stretched back over the region.
    width = max(1, region.width // pixel_size)
    height = max(1, region.height // pixel_size)
    camera = region_camera(scene, space, view, width, height)
    border = None
    render = scene.render
    fractions = None
    frame = (0.0, 0.0, float(width), float(height))
    if view.view_perspective == "CAMERA":
        if render.use_border and scene.camera is not None:
            corners = [
                scene.camera.matrix_world @ corner
                for corner in scene.camera.data.view_frame(scene=scene)
            ]
            frame = camera_frame(view.perspective_matrix, corners, width, height)
            fractions = (
                render.border_min_x,
                render.border_min_y,
                render.border_max_x,
                render.border_max_y,
            )
    elif space.use_render_border:
        fractions = (
            space.render_border_min_x,
            space.render_border_min_y,
            space.render_border_max_x,
            space.render_border_max_y,
        )
    if fractions is not None:
        # Nothing of the border in view renders nothing: a one-pixel border.
        border = border_pixels(frame, fractions, width, height) or (0, 0, 1, 1)
    return ViewSetup(
        camera=camera,
        width=width,
        height=height,
        region_width=region.width,
        region_height=region.height,
        border=border,
        # The passes a display needs: another display may need another job.
        settings=(
            _quality(scene),
            render.film_transparent,
            render.threads,
            viewport_display(scene.whitted.viewport_display).passes,
            scene.whitted.use_viewport_denoising,
        ),
    )
