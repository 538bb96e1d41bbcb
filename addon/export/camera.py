"""The scene camera and the image size, as plain data.

Axes: Blender's camera looks down its local -Z with +Y up, which is also the
native camera's convention, so no axis change is needed.
"""

import math
from dataclasses import dataclass

import numpy as np

from . import ExportError


@dataclass(frozen=True)
class LensData:
    """A thin lens: Blender's Depth of Field as Cycles reads it (its blender/camera.cpp)."""

    aperture_radius: float = 0.0  # scene units (m at unit scale 1); 0: a pinhole
    focus_distance: float = 1.0  # of the plane in focus, along the view axis
    blades: int = 0  # a polygonal aperture of this many sides; below 3 a disc
    rotation: float = 0.0  # of the polygon, radians
    ratio: float = 1.0  # anamorphic bokeh: the aperture's width over this
    fstop: float = 0.0  # what the artist set, for the report; 0 without depth of field


PINHOLE = LensData()


@dataclass(frozen=True)
class PanoramaData:
    """A panoramic camera's projection as Cycles reads it (its blender/camera.cpp)."""

    type: str  # Blender's panorama_type: EQUIRECTANGULAR, MIRRORBALL, FISHEYE_...
    longitude_latitude: tuple[float, float, float, float]  # radians: lon min, max, lat min, max
    fisheye_fov: float  # radians
    fisheye_lens: float  # mm
    sensor: tuple[float, float]  # mm, the sensor fitted to the image's aspect
    polynomial: tuple[float, float, float, float, float]  # k0..k4
    cylinder: tuple[float, float, float, float]  # radians, then heights over the radius


@dataclass(frozen=True)
class CameraData:
    width: int  # final image size in pixels (resolution times percentage)
    height: int
    to_world: np.ndarray  # float64[4,4] row-major camera to world, scale removed
    projection: str  # "PERSPECTIVE", "ORTHOGRAPHIC" or "PANORAMIC"
    # (xmin, xmax, ymin, ymax), shift included: on the plane at distance 1, in camera
    # units (orthographic), or of the panorama's [0, 1]^2 (panoramic).
    window: tuple[float, float, float, float]
    clip_start: float
    clip_end: float
    lens: LensData = PINHOLE
    panorama: PanoramaData | None = None  # a PANORAMIC camera's projection
    motion: tuple = ()  # its to_world over the shutter (export/motion.py), () when still
    # When in the shutter its samples are taken (export/motion.py Shutter): the Shutter
    # Curve's openness, () for a box; the rolling shutter's Duration, or None.
    shutter_curve: tuple = ()
    rolling_shutter: float | None = None


def convert_camera(camera_object, render, warnings):
    """Convert the scene's camera object (evaluated) and its RenderSettings.

    Raises ExportError when there is no camera or the scene camera is not a camera.
    """
    if camera_object is None:
        raise ExportError("Whitted: the scene has no camera")
    if camera_object.type != "CAMERA":
        raise ExportError(
            f"Whitted: the scene camera '{camera_object.name}' is not a camera object "
            f"(its type is {camera_object.type})"
        )
    camera = camera_object.data
    width, height = image_size(render)
    projection = projection_of(camera)
    if camera.type not in {"PERSP", "ORTHO", "PANO"}:  # 5.x's CUSTOM (an OSL camera)
        warnings.append(
            f"Whitted: camera '{camera_object.name}' is {camera.type}, which Whitted does "
            "not support; rendering it as a perspective camera"
        )
    if render.use_multiview:
        warnings.append(
            "Whitted: Stereoscopy (Output > Views) is on; Whitted renders one view, from "
            f"camera '{camera_object.name}' itself"
        )
    panorama = None
    if projection == "PANORAMIC":
        panorama = panorama_data(camera, width, height, render)
        # Cycles' panoramic viewplane: the projection's [0, 1]^2, moved by the shift.
        window = (camera.shift_x, 1.0 + camera.shift_x, camera.shift_y, 1.0 + camera.shift_y)
    else:
        if projection == "ORTHOGRAPHIC":
            # ortho_scale is the extent, in camera units, of the fitted image side.
            fitted_extent = camera.ortho_scale
        else:
            # The sensor side (mm) over the focal length (mm) is the fitted image side on
            # the plane at distance 1.
            fitted_extent = _sensor_size(camera) / camera.lens
        window = _window(camera, fitted_extent, width, height, render)

    return CameraData(
        width=width,
        height=height,
        to_world=without_scale(camera_object),
        projection=projection,
        window=window,
        clip_start=camera.clip_start,
        clip_end=camera.clip_end,
        lens=lens_data(camera_object, projection),
        panorama=panorama,
    )


def image_size(render):
    """Blender's final image size: resolution times percentage, rounded down as Blender
    rounds it."""
    return (
        render.resolution_x * render.resolution_percentage // 100,
        render.resolution_y * render.resolution_percentage // 100,
    )


def projection_of(camera):
    """The native projection of a camera's data: PERSPECTIVE, ORTHOGRAPHIC or PANORAMIC."""
    return {"ORTHO": "ORTHOGRAPHIC", "PANO": "PANORAMIC"}.get(camera.type, "PERSPECTIVE")


def panorama_settings(camera):
    """Where a camera's panorama settings live: on the camera from Blender 4.0, on its
    Cycles settings (camera.cycles) before."""
    return camera if hasattr(camera, "panorama_type") else camera.cycles


def panorama_data(camera, width, height, render):
    """The panoramic projection of `camera` (a PANO camera's data). Angles are radians
    as Blender stores them; the fisheyes' sensor is fitted to the image's aspect as
    Cycles fits it (the sensor width, or height with Vertical fit, spans that side)."""
    settings = panorama_settings(camera)
    x_ratio, y_ratio = _aspect_ratios(width, height, render)
    if _horizontal_fit(camera, width, height, render):
        sensor = (_sensor_size(camera), _sensor_size(camera) * y_ratio / x_ratio)
    else:
        sensor = (_sensor_size(camera) * x_ratio / y_ratio, _sensor_size(camera))
    # Blender 5.0 added the central cylindrical projection; before, its defaults.
    radius = max(getattr(settings, "central_cylindrical_radius", 1.0), 1e-6)
    cylinder = (
        getattr(settings, "central_cylindrical_range_u_min", -math.pi),
        getattr(settings, "central_cylindrical_range_u_max", math.pi),
        getattr(settings, "central_cylindrical_range_v_min", -1.0) / radius,
        getattr(settings, "central_cylindrical_range_v_max", 1.0) / radius,
    )
    return PanoramaData(
        type=settings.panorama_type,
        longitude_latitude=(
            settings.longitude_min,
            settings.longitude_max,
            settings.latitude_min,
            settings.latitude_max,
        ),
        fisheye_fov=settings.fisheye_fov,
        fisheye_lens=settings.fisheye_lens,
        sensor=sensor,
        polynomial=tuple(getattr(settings, f"fisheye_polynomial_k{i}") for i in range(5)),
        cylinder=cylinder,
    )


def lens_data(camera_object, projection):
    """The camera's Depth of Field as a thin lens, as Cycles sets it up: the aperture's
    radius is the focal length (mm, to m) over twice the f-number (an orthographic
    camera's 1 / (2 f), in scene units); the focus distance is the depth of
    focus_point's point along the view axis when there is a focus object, else Focus
    Distance."""
    camera = camera_object.data
    dof = camera.dof
    if not dof.use_dof:
        return PINHOLE
    fstop = max(dof.aperture_fstop, 1e-5)
    if projection == "ORTHOGRAPHIC":
        radius = 1.0 / (2.0 * fstop)
    else:
        radius = camera.lens * 1e-3 / (2.0 * fstop)
    focus = dof.focus_distance
    if dof.focus_object is not None:
        view = np.array(camera_object.matrix_world)[:3, 2]
        view = view / np.linalg.norm(view)
        offset = focus_point(dof) - np.array(camera_object.matrix_world.translation)
        focus = abs(float(view @ offset))
    return LensData(
        aperture_radius=radius,
        focus_distance=max(focus, 1e-5),
        blades=dof.aperture_blades,
        rotation=dof.aperture_rotation,
        ratio=dof.aperture_ratio,
        fstop=dof.aperture_fstop,
    )


def focus_point(dof):
    """Where a camera's Depth of Field (`dof`, with a focus object) focuses, in world
    space, as Cycles reads it: the focus object's origin, or with Focus on Bone (an
    armature's focus_subtarget) that bone's head as the armature is posed. Of an
    evaluated camera the focus object is the depsgraph's evaluated copy (Blender points
    evaluated data at evaluated objects), so its place is the frame's even where the
    original object was left elsewhere (a script's scene not yet updated, a farm's
    `blender -b FILE -f N`)."""
    target = dof.focus_object
    bone = target.pose.bones.get(dof.focus_subtarget) if target.pose is not None else None
    if bone is None:
        return np.array(target.matrix_world.translation)
    return np.array(target.matrix_world @ bone.head)


def _aspect_ratios(width, height, render):
    # The image's shape in pixel units times the pixel aspect, as Cycles' viewplane.
    return width * render.pixel_aspect_x, height * render.pixel_aspect_y


def _horizontal_fit(camera, width, height, render):
    # AUTO fits the sensor to the longer side of the image.
    if camera.sensor_fit == "AUTO":
        x_ratio, y_ratio = _aspect_ratios(width, height, render)
        return x_ratio > y_ratio
    return camera.sensor_fit == "HORIZONTAL"


def _sensor_size(camera):
    # AUTO and HORIZONTAL use sensor_width, VERTICAL uses sensor_height (Cycles does
    # the same: with AUTO, sensor_width goes to whichever side is longer).
    if camera.sensor_fit == "VERTICAL":
        return camera.sensor_height
    return camera.sensor_width


def _window(camera, fitted_extent, width, height, render):
    """Cycles' viewplane (blender/camera.cpp) scaled to the plane at distance 1.

    The fitted side spans `fitted_extent`; the other side follows the image
    aspect. Shift is in units of the fitted extent on both axes.
    """
    x_ratio, y_ratio = _aspect_ratios(width, height, render)
    if _horizontal_fit(camera, width, height, render):
        half_x = fitted_extent / 2
        half_y = half_x * y_ratio / x_ratio
    else:
        half_y = fitted_extent / 2
        half_x = half_y * x_ratio / y_ratio
    dx = camera.shift_x * fitted_extent
    dy = camera.shift_y * fitted_extent
    return (-half_x + dx, half_x + dx, -half_y + dy, half_y + dy)


def without_scale(camera_object, matrix_world=None):
    """The camera's matrix_world (or `matrix_world`, the camera's at another time)
    without its scale: scale would stretch the rays; Cycles clears it too."""
    source = camera_object.matrix_world if matrix_world is None else matrix_world
    matrix = np.array(source, dtype=np.float64)
    scale = np.linalg.norm(matrix[:3, :3], axis=0)
    if not np.all(scale > 0.0):
        raise ExportError(f"Whitted: camera '{camera_object.name}' has a zero scale")
    matrix[:3, :3] /= scale
    return matrix
