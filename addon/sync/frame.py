"""A final frame (F12, a material preview, a probe) set up from empty: the scene
synced, the scene camera, the film and the native settings."""

from dataclasses import dataclass, replace

from .. import memory
from ..export.camera import convert_camera
from ..export.film import FilmData, convert_film
from ..export.motion import sample_motion, shutter_of
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
    motion: object = None  # export.motion.MotionData of a motion-blurred frame, else None

    def at_quality(self, depsgraph, native, quality):
        """Native Settings of this frame at another Quality, the scene synced again for
        it (soft-shadow samples and the texture filter are part of the scene), what it
        sampled of the shutter kept."""
        scene = depsgraph.scene
        self.sync.sync(depsgraph, replace(SyncParams.of(scene, quality), motion=self.motion))
        return native_settings(
            native,
            scene,
            self.width,
            self.height,
            self.film,
            quality,
            shutter=self.settings.shutter,
        )

    def job(self, native, settings=None, **kwargs):
        """A native RenderJob of this frame (with other `settings` if given)."""
        return native.RenderJob(
            self.sync.scene, settings or self.settings, camera=self.camera, **kwargs
        )


def sync_frame(depsgraph, native, quality=None, frame_set=None):
    """The Frame of the evaluated depsgraph at properties.presets.Quality `quality`
    (by default scene.whitted's). Given `frame_set(frame, subframe)`, which evaluates
    the depsgraph at another time (the render's RenderEngine.frame_set for F12 and a
    farm frame; export.motion.scene_frame_set for the operators that stand for F12),
    and with Render > Motion Blur on, what moves within the shutter is sampled first
    (export/motion.py), the scene evaluated at sub-frames and put back.
    Raises export.ExportError when the scene cannot be rendered (a render that would
    not fit in memory among them: memory.py), and the native module's ValueError when
    it refuses data."""
    scene = depsgraph.scene
    quality = quality or quality_of(scene.whitted)
    shutter = shutter_of(scene) if frame_set is not None else None
    # Before anything is read: frame_set evaluates the depsgraph again.
    motion = sample_motion(frame_set, depsgraph, shutter) if shutter is not None else None
    scene = depsgraph.scene
    camera_warnings = []
    # The camera as this depsgraph evaluated it: the scene's pointer is the original
    # object, which a background render (`blender -b FILE -f N`) never moves to frame N.
    camera_object = scene.camera.evaluated_get(depsgraph) if scene.camera is not None else None
    camera = convert_camera(camera_object, scene.render, camera_warnings)
    if motion is not None:
        camera = replace(
            camera,
            motion=motion.camera,
            shutter_curve=shutter.curve,
            rolling_shutter=shutter.rolling,
        )
    # Before anything large is allocated.
    needed = memory.check(depsgraph, camera.width * camera.height)
    sync = SceneSync(native)
    report = sync.sync(depsgraph, replace(SyncParams.of(scene, quality), motion=motion))
    needed = memory.check_volumes(needed, sync.volume_bytes)
    warnings = list(sync.warnings) + camera_warnings
    if motion is not None and motion.unmatched:
        names = _first_names(motion.unmatched)
        warnings.append(
            f"Whitted: {len(motion.unmatched)} object(s) are not there for the whole shutter "
            f"({names}); they render where the frame puts them, without motion blur"
        )
    if motion is not None and motion.deforming:
        names = _first_names(motion.deforming)
        warnings.append(
            f"Whitted: {len(motion.deforming)} object(s) change their vertex count within the "
            f"shutter ({names}); their movement blurs, their deformation cannot (as in Cycles)"
        )
    if sync.light_count == 0 and not sync.world_lights:
        warnings.append(
            "Whitted: the scene has no lamps and no world light; only what emits (surfaces, "
            "glowing media) and the ambient light light it"
        )
    film = convert_film(scene, camera.width, camera.height)
    return Frame(
        sync=sync,
        report=report,
        camera=native_camera(native, camera),
        width=camera.width,
        height=camera.height,
        film=film,
        settings=native_settings(
            native,
            scene,
            camera.width,
            camera.height,
            film,
            quality,
            shutter=0.0 if shutter is None else shutter.close - shutter.open,
        ),
        warnings=warnings,
        memory=needed,
        motion=motion,
    )


def _first_names(names):
    # A warning's list of objects: the first three, then "..." if there are more.
    return ", ".join(names[:3]) + ("..." if len(names) > 3 else "")
