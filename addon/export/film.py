"""What part of the frame is rendered (render border) and whether the sky is transparent."""

from dataclasses import dataclass

import numpy as np

Region = tuple[int, int, int, int]


@dataclass(frozen=True)
class FilmData:
    # (xmin, ymin, xmax, ymax) in pixels of the full frame, end exclusive, rows
    # from the bottom: the border, or the whole frame without one.
    region: Region
    transparent_background: bool  # camera rays that miss everything give alpha 0


def convert_film(render, width, height):
    """The film of RenderSettings `render` for a frame of `width` x `height` pixels."""
    full_frame = (0, 0, width, height)
    return FilmData(
        region=_border_region(render, width, height) if render.use_border else full_frame,
        transparent_background=render.film_transparent,
    )


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
