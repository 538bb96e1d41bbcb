"""What part of the frame is rendered (render border), whether the sky is transparent, and
the pixel filter (Render > Film, as Cycles')."""

from dataclasses import dataclass

import numpy as np

Region = tuple[int, int, int, int]


# The pixel filters' names in the report.
FILTER_NAMES = {"BOX": "Box", "GAUSSIAN": "Gaussian", "BLACKMAN_HARRIS": "Blackman-Harris"}


@dataclass(frozen=True)
class PixelFilter:
    # A native PixelFilterType item's name: BOX, GAUSSIAN or BLACKMAN_HARRIS.
    type: str
    # In pixels, Cycles' Width: 4 standard deviations of the Gaussian, half of
    # Blackman-Harris' support; the Box is the pixel's square whatever it is (native
    # integrator/pixel_filter.h).
    width: float


@dataclass(frozen=True)
class FilmData:
    # (xmin, ymin, xmax, ymax) in pixels of the full frame, end exclusive, rows
    # from the bottom: the border, or the whole frame without one.
    region: Region
    transparent_background: bool  # camera rays that miss everything give alpha 0
    pixel_filter: PixelFilter


def convert_film(scene, width, height, region=None):
    """The film of `scene` for a frame of `width` x `height` pixels: `region` (the
    viewport's border, or its whole view) or else the render border of
    scene.render."""
    render = scene.render
    if region is None:
        full_frame = (0, 0, width, height)
        region = _border_region(render, width, height) if render.use_border else full_frame
    return FilmData(
        region=region,
        transparent_background=render.film_transparent,
        pixel_filter=PixelFilter(scene.whitted.pixel_filter_type, scene.whitted.filter_width),
    )


def pixel_filter_decision(film, aa_mode):
    """The effects report's entry for the pixel filter ({name, on, why})."""
    kind = film.pixel_filter.type
    shown = FILTER_NAMES[kind] + ("" if kind == "BOX" else f" {film.pixel_filter.width:.2f} px")
    if aa_mode == "ADAPTIVE":
        why = f"off: Whitted's adaptive anti-aliasing samples each pixel's square, not {shown}"
        return {"name": "pixel filter", "on": False, "why": why}
    if kind == "BOX":
        return {"name": "pixel filter", "on": False, "why": "off: each pixel's own square (Box)"}
    return {"name": "pixel filter", "on": True, "why": shown}


def _border_region(render, width, height):
    # As Blender's render pipeline does (and Cycles after it): each edge is the
    # float32 product of the border fraction and the frame size, truncated. The
    # render result then has the border's size, and Blender itself either pastes
    # it into the full frame or, with "Crop to Render Region", keeps it alone, so
    # the engine's job is the same in both cases.
    def edge(fraction, size):
        return int(np.float32(fraction) * np.float32(size))

    xmin, xmax = edge(render.border_min_x, width), edge(render.border_max_x, width)
    ymin, ymax = edge(render.border_min_y, height), edge(render.border_max_y, height)
    # At least one pixel each way, as Cycles keeps.
    return xmin, ymin, max(xmax, xmin + 1), max(ymax, ymin + 1)
