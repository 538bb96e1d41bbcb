"""Motion blur as plain data: the shutter Render > Motion Blur sets, and the transforms
of the objects and the camera that move within it, read as Cycles reads them (its
blender/sync.cpp sync_motion): the scene evaluated at sub-frames through
RenderEngine.frame_set, then put back at the frame.

Times: Blender frames (fractional). The native side takes each transform list as
evenly spaced samples from the shutter's opening (time 0) to its closing (time 1)."""

import math
from dataclasses import dataclass, field

import numpy as np

from .camera import without_scale
from .curves import STRAND_TYPES
from .instance import instance_name
from .mesh import is_renderable_mesh

# The Shutter Curve is read at this many evenly spaced times (Cycles' table size).
SHUTTER_CURVE_SAMPLES = 256

# Cycles' object Motion Steps s give 2^s + 1 samples (2 << (s - 1), plus the frame
# itself); the samples of fewer steps are a subset of those of more. Capped at s = 5
# (33 sub-frame evaluations of the whole scene).
MAX_MOTION_STEPS = 5


@dataclass(frozen=True)
class Shutter:
    """When the shutter is open, in frames: Render > Motion Blur's Shutter (in frames)
    placed by its Position (Start: from the frame on, Center: around it, End: up to it)."""

    open: float
    close: float
    samples: int  # evaluations over it, evenly spaced, both ends included (odd)
    # How open it is at SHUTTER_CURVE_SAMPLES evenly spaced times (Render > Motion Blur >
    # Shutter Curve); () for a box, the curve's default.
    curve: tuple = ()
    # Cycles' Rolling Shutter (Render > Motion Blur, scene.cycles): its Duration in [0, 1]
    # when the rows are read from the top, None for a global shutter.
    rolling: float | None = None

    def times(self):
        step = (self.close - self.open) / (self.samples - 1)
        return [self.open + i * step for i in range(self.samples)]


@dataclass(frozen=True)
class MotionData:
    """What moves within the shutter: each moving mesh instance's transforms and the
    camera's, as nested tuples (row-major 4x4) at Shutter.times()."""

    shutter: Shutter
    objects: dict = field(default_factory=dict)  # instance name -> transforms
    camera: tuple = ()  # the scene camera's to_world (scale removed), or () if still
    # Objects that showed up at some sub-frames and not others (hidden or shown by
    # keys, instanced by an animated count): each is rendered where the frame puts it.
    unmatched: tuple = ()
    # Deforming objects (armature, shape keys, modifiers; Object > Motion Blur >
    # Deformation on): by object name, float32[N,3] object-space positions at each time.
    deformations: dict = field(default_factory=dict)
    # Deforming objects whose vertex count changes within the shutter: their transforms
    # blur, their deformation cannot (as in Cycles).
    deforming: tuple = ()


def motion_position(scene):
    """START, CENTER or END: Render > Motion Blur > Position (scene.cycles' in 3.x)."""
    position = getattr(scene.render, "motion_blur_position", None)
    if position is None:
        position = scene.cycles.motion_blur_position
    return position


def shutter_of(scene):
    """The Shutter of Blender `scene` at its current frame, or None when motion blur is
    off or the shutter does not open (a zero shutter: the static frame)."""
    render = scene.render
    length = render.motion_blur_shutter
    if not render.use_motion_blur or not length > 0.0:
        return None
    frame = scene.frame_current + scene.frame_subframe
    start = {"START": frame, "END": frame - length}.get(motion_position(scene), frame - length / 2)
    steps = 1
    for obj in scene.objects:
        settings = getattr(obj, "cycles", None)
        if settings is not None and settings.use_motion_blur and obj.type in {"MESH", "CAMERA"}:
            steps = max(steps, min(settings.motion_steps, MAX_MOTION_STEPS))
    return Shutter(
        open=start,
        close=start + length,
        samples=(2 << (steps - 1)) + 1,
        curve=shutter_curve(render.motion_blur_shutter_curve),
        rolling=_rolling_shutter(scene),
    )


def shutter_curve(mapping):
    """Render > Motion Blur > Shutter Curve (a CurveMapping over the shutter's time, both
    in [0, 1]) at SHUTTER_CURVE_SAMPLES evenly spaced times; () when it is flat (a box:
    the default)."""
    mapping.initialize()  # its evaluation table, which a file just read may lack
    curve = mapping.curves[0]
    last = SHUTTER_CURVE_SAMPLES - 1
    values = tuple(mapping.evaluate(curve, i / last) for i in range(SHUTTER_CURVE_SAMPLES))
    return () if max(values) == min(values) else values


def _rolling_shutter(scene):
    # Cycles' setting (scene.cycles in 3.x and 5.x): "TOP" reads the rows from the top.
    settings = getattr(scene, "cycles", None)
    if settings is None or getattr(settings, "rolling_shutter_type", "NONE") != "TOP":
        return None
    return float(settings.rolling_shutter_duration)


def _blurs(obj):
    # Object Properties > Motion Blur, per object (Cycles' setting; on by default), as
    # the artist set it on the original.
    settings = getattr(obj.original, "cycles", None)
    return settings is None or settings.use_motion_blur


def _matrix(m):
    return tuple(tuple(float(x) for x in row) for row in m)


def scene_frame_set(scene):
    """frame_set(frame, subframe) for the operators that show what F12 would (the
    Estimate, the ray-tree inspector), which own no render's depsgraph: Blender `scene`
    (an original) set to the time, which evaluates the view layer's depsgraph there
    (context.evaluated_depsgraph_get()'s). sample_motion sets it back to its frame."""

    def frame_set(frame, subframe):
        scene.frame_set(frame, subframe=subframe)

    return frame_set


def sample_motion(frame_set, depsgraph, shutter):
    """MotionData of `depsgraph` over `shutter`: the scene evaluated at each of its times
    by `frame_set(frame, subframe)` (a render's RenderEngine.frame_set, or
    scene_frame_set's), then set back to the frame it was at. Objects whose Motion Blur
    is off, and objects that do not move, are left out. Every moving object is sampled
    at all the shutter's times (the most Motion Steps of any object's), where Cycles
    samples each at its own steps' subset. A deforming object's vertex positions are
    read at each time too."""
    scene = depsgraph.scene
    frame, subframe = scene.frame_current, scene.frame_subframe
    times = shutter.times()
    seen = {}
    cameras = []
    camera = scene.camera
    # The camera as the depsgraph evaluates it at each time (the scene's camera pointer
    # may be the original object, which sub-frames do not move).
    camera_name = camera.original.name_full if camera is not None and _blurs(camera) else None
    deforming = {
        obj.original.name_full
        for obj in scene.objects
        if obj.type == "MESH"
        and _blurs(obj)
        and getattr(obj.original.cycles, "use_deform_motion", False)
        and obj.original.is_deform_modified(scene.original, "RENDER")
    }
    shapes = {name: [None] * len(times) for name in deforming}
    try:
        for index, time in enumerate(times):
            whole = math.floor(time)
            frame_set(int(whole), time - whole)
            for object_instance in depsgraph.object_instances:
                obj = object_instance.object
                # Meshes, strands, and Volume objects (their grids move with them).
                moving_kind = is_renderable_mesh(object_instance) or (
                    obj.type in (*STRAND_TYPES, "VOLUME") and not obj.original.hide_render
                )
                if moving_kind and _blurs(obj):
                    name = instance_name(object_instance)
                    samples = seen.setdefault(name, [None] * len(times))
                    samples[index] = np.array(object_instance.matrix_world, dtype=np.float64)
                    if name in shapes and not object_instance.is_instance:
                        shapes[name][index] = _positions(obj)
                elif (
                    obj.type == "CAMERA"
                    and not object_instance.is_instance
                    and obj.original.name_full == camera_name
                ):
                    cameras.append(without_scale(obj, object_instance.matrix_world))
    finally:
        frame_set(frame, subframe)
    objects = {}
    unmatched = []
    for name, samples in seen.items():
        if any(m is None for m in samples):
            unmatched.append(name)
            continue
        if any(not np.array_equal(m, samples[0]) for m in samples):
            objects[name] = tuple(_matrix(m) for m in samples)
    still = len(cameras) < len(times) or all(np.array_equal(m, cameras[0]) for m in cameras)
    camera_motion = () if still else tuple(_matrix(m) for m in cameras)
    deformations = {}
    changing = []
    for name, steps in shapes.items():
        if any(p is None for p in steps):
            continue  # not there for the whole shutter: unmatched says so
        if any(len(p) != len(steps[0]) for p in steps):
            changing.append(name)
        elif any(not np.array_equal(p, steps[0]) for p in steps):
            deformations[name] = tuple(steps)
    return MotionData(
        shutter,
        objects,
        camera_motion,
        tuple(sorted(unmatched)),
        deformations,
        tuple(sorted(changing)),
    )


def _positions(obj):
    # The evaluated mesh's vertex positions, object space, float32[N,3].
    mesh = obj.to_mesh()
    try:
        positions = np.empty((len(mesh.vertices), 3), dtype=np.float32)
        mesh.vertices.foreach_get("co", positions.reshape(-1))
    finally:
        obj.to_mesh_clear()
    return positions
