"""A final frame (F12, a material preview, a probe) set up from empty: the scene
synced, the scene camera, the film and the native settings."""

from dataclasses import dataclass

from .. import memory
from ..export.camera import convert_camera
from ..export.film import FilmData, convert_film
from ..properties.presets import quality_of
from ..settings import native_settings
from .native_data import native_camera
from .scene import SceneSync, SyncParams, SyncReport


@dataclass
class Frame:
    sync: SceneSync  # .scene is the native scene
    report: SyncReport
    camera: object  # whitted_native.Camera of the scene camera
    width: int  # the whole frame, pixels
    height: int
    film: FilmData
    settings: object  # whitted_native.Settings
    warnings: list  # what could not be exported as authored
    memory: memory.MemoryEstimate  # what the render was estimated to need

    def job(self, native, settings=None, **kwargs):
        """A native RenderJob of this frame (with other `settings` if given)."""
        return native.RenderJob(
            self.sync.scene, settings or self.settings, camera=self.camera, **kwargs
        )


def sync_frame(depsgraph, native, quality=None):
    """The Frame of the evaluated depsgraph at properties.presets.Quality `quality`
    (by default scene.whitted's). Raises export.ExportError when the scene cannot be
    rendered (a render that would not fit in memory among them: memory.py), and the
    native module's ValueError when it refuses data."""
    scene = depsgraph.scene
    quality = quality or quality_of(scene.whitted)
    camera_warnings = []
    camera = convert_camera(scene.camera, scene.render, camera_warnings)
    # Before anything large is allocated.
    needed = memory.check(depsgraph, camera.width * camera.height)
    sync = SceneSync(native)
    report = sync.sync(depsgraph, SyncParams.of(scene, quality))
    warnings = list(sync.warnings) + camera_warnings
    if sync.light_count == 0:
        warnings.append("Whitted: the scene has no lights; only ambient light and emission show")
    film = convert_film(scene.render, camera.width, camera.height)
    return Frame(
        sync=sync,
        report=report,
        camera=native_camera(native, camera),
        width=camera.width,
        height=camera.height,
        film=film,
        settings=native_settings(native, scene, camera.width, camera.height, film, quality),
        warnings=warnings,
        memory=needed,
    )
