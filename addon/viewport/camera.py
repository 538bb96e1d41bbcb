"""The 3D view as a camera: what a viewport render sees.

Everything is read from the view's own matrices, which Blender has already
built for every mode (perspective, orthographic, camera view with its zoom,
offset, lens shift and sensor fit), so the render sees exactly what the
viewport's overlays are drawn over. Pure functions of plain matrices (numpy),
so they are tested without Blender.

Axes: the view looks down its local -Z with +Y up, as the native camera does.
"""

from dataclasses import dataclass, replace

import numpy as np

from ..export.camera import PINHOLE, LensData, PanoramaData


@dataclass(frozen=True)
class ViewCamera:
    """The fields of whitted_native.Camera, as tuples so that two views compare."""

    to_world: tuple  # 4x4 row-major, view to world, orthonormal axes
    projection: str  # PERSPECTIVE | ORTHOGRAPHIC | PANORAMIC
    window: tuple[float, float, float, float]  # (xmin, xmax, ymin, ymax)
    clip_start: float
    clip_end: float
    # Looking through a camera (camera view): its depth of field and panorama, as
    # Cycles' viewport shows them; elsewhere a pinhole.
    lens: LensData = PINHOLE
    panorama: PanoramaData | None = None


def view_camera(view_matrix, window_matrix, is_perspective):
    """The ViewCamera of a 3D view: `view_matrix` (world to view) and
    `window_matrix` (view to clip space, OpenGL's convention) as 4x4 arrays.

    A perspective projection P maps the view-space point (x, y, z) to
    x_clip = P00 x + P02 z over w = -z; on the plane at distance 1 (z = -1) the
    window edges, where x_clip / w = -1 and +1, are x = (P02 -+ 1) / P00; the
    same for y with P11, P12. Near and far follow from P22 and P23.
    An orthographic one maps x to P00 x + P03: edges x = (-P03 -+ 1) / P00.
    """
    view = np.asarray(view_matrix, dtype=np.float64)
    p = np.asarray(window_matrix, dtype=np.float64)
    to_world = np.linalg.inv(view)
    # The view matrix can carry a scale (an ortho zoom does not, but be safe):
    # the native camera takes unit axes; the window holds the extent.
    to_world[:3, :3] /= np.linalg.norm(to_world[:3, :3], axis=0)
    if is_perspective:
        window = (
            (p[0, 2] - 1.0) / p[0, 0],
            (p[0, 2] + 1.0) / p[0, 0],
            (p[1, 2] - 1.0) / p[1, 1],
            (p[1, 2] + 1.0) / p[1, 1],
        )
        near = p[2, 3] / (p[2, 2] - 1.0)
        far = p[2, 3] / (p[2, 2] + 1.0)
        projection = "PERSPECTIVE"
    else:
        window = (
            (-p[0, 3] - 1.0) / p[0, 0],
            (-p[0, 3] + 1.0) / p[0, 0],
            (-p[1, 3] - 1.0) / p[1, 1],
            (-p[1, 3] + 1.0) / p[1, 1],
        )
        near = (p[2, 3] + 1.0) / p[2, 2]
        far = (p[2, 3] - 1.0) / p[2, 2]
        projection = "ORTHOGRAPHIC"
        if near < 0.0:
            # Blender's orthographic view clips on both sides of the view point;
            # the native camera starts its rays at clip_start >= 0, so the origin
            # moves back along the view's +Z (parallel rays: nothing else changes).
            to_world[:3, 3] += to_world[:3, 2] * -near
            near, far = 0.0, far - near
    return ViewCamera(
        to_world=tuple(map(tuple, to_world)),
        projection=projection,
        window=tuple(float(v) for v in window),
        clip_start=float(near),
        clip_end=float(far),
    )


def through_camera(view, lens, panorama=None, frame=None, size=None, shift=(0.0, 0.0)):
    """`view` (a ViewCamera of a camera view) with the camera's depth of field `lens`
    and, for a panoramic camera, its projection `panorama`: its [0, 1]^2, moved by the
    lens `shift` (as in a render), spans the camera frame `frame` (region pixels, as
    camera_frame gives) of an image of `size` (width, height) pixels."""
    if panorama is None:
        return replace(view, lens=lens)
    fx0, fy0, fx1, fy1 = frame
    width, height = size
    sx, sy = shift
    window = (
        -fx0 / (fx1 - fx0) + sx,
        (width - fx0) / (fx1 - fx0) + sx,
        -fy0 / (fy1 - fy0) + sy,
        (height - fy0) / (fy1 - fy0) + sy,
    )
    return replace(view, projection="PANORAMIC", window=window, lens=lens, panorama=panorama)


def camera_frame(perspective_matrix, corners_world, width, height):
    """The camera frame's rectangle in region pixels (xmin, ymin, xmax, ymax), from
    the view's `perspective_matrix` (world to clip) and the world positions of the
    camera frame's corners (Camera.view_frame placed by the camera's matrix)."""
    p = np.asarray(perspective_matrix, dtype=np.float64)
    points = np.c_[np.asarray(corners_world, dtype=np.float64), np.ones(len(corners_world))]
    clip = points @ p.T
    ndc = clip[:, :2] / clip[:, 3:4]
    xs = (ndc[:, 0] + 1.0) * 0.5 * width
    ys = (ndc[:, 1] + 1.0) * 0.5 * height
    return float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max())


def border_pixels(frame, border, width, height):
    """Region pixels (xmin, ymin, xmax, ymax), end exclusive, of the fractions
    `border` (min_x, min_y, max_x, max_y) of rectangle `frame` (region pixels, as
    camera_frame gives, or the whole region), clipped to a width x height image;
    None when nothing of it is inside."""
    fx0, fy0, fx1, fy1 = frame
    bx0, by0, bx1, by1 = border
    # Rounded: the projected frame's corners carry rounding error either way.
    xmin = max(0, round(fx0 + bx0 * (fx1 - fx0)))
    ymin = max(0, round(fy0 + by0 * (fy1 - fy0)))
    xmax = min(width, round(fx0 + bx1 * (fx1 - fx0)))
    ymax = min(height, round(fy0 + by1 * (fy1 - fy0)))
    if xmin >= xmax or ymin >= ymax:
        return None
    return xmin, ymin, xmax, ymax
