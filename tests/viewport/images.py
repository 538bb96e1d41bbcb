"""Image helpers for the pytest side of tests/viewport (numpy and Pillow, outside Blender);
the SSIM they compare with is whitted_tools.metrics.ssim."""

import numpy as np
from PIL import Image

# Pixels cut off each side of the camera frame before comparing: the viewport draws a
# 1 px frame line there even with overlays off, and the projected frame is sub-pixel.
FRAME_INSET = 3


def load(path):
    """An RGB PNG as float64[height, width, 3] in 0..255, rows top to bottom."""
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"), dtype=np.float64)


def crop(image, rect, inset=0):
    """image[top:bottom, left:right] of rect [left, top, right, bottom], rounded inwards."""
    left, top, right, bottom = rect
    left, top = int(np.ceil(left)) + inset, int(np.ceil(top)) + inset
    right, bottom = int(np.floor(right)) - inset, int(np.floor(bottom)) - inset
    height, width = image.shape[:2]
    left, top = max(left, 0), max(top, 0)
    right, bottom = min(right, width), min(bottom, height)
    if right <= left or bottom <= top:
        raise ValueError(f"rect {rect} is outside the {width}x{height} image")
    return image[top:bottom, left:right]


def resize(image, width, height):
    """Resample float RGB to width x height (bilinear; both images get the same filter)."""
    pil = Image.fromarray(np.clip(image, 0, 255).astype(np.uint8))
    return np.asarray(pil.resize((width, height), Image.BILINEAR), dtype=np.float64)


def camera_view(screenshot, frame, render):
    """The screenshot's camera frame and the F12 render, cut and scaled to the same size.

    The render was made at the frame's size (rounded), so the scale is within a pixel
    of 1; the render loses the same FRAME_INSET border so both show the same scene rect.
    """
    inner = crop(screenshot, frame, FRAME_INSET)
    render_h, render_w = render.shape[:2]
    frame_w, frame_h = frame[2] - frame[0], frame[3] - frame[1]
    # The inset in render pixels (the render spans the whole frame).
    sx, sy = render_w / frame_w, render_h / frame_h
    left = round((np.ceil(frame[0]) + FRAME_INSET - frame[0]) * sx)
    top = round((np.ceil(frame[1]) + FRAME_INSET - frame[1]) * sy)
    right = left + round(inner.shape[1] * sx)
    bottom = top + round(inner.shape[0] * sy)
    cut = render[top:bottom, left:right]
    return inner, resize(cut, inner.shape[1], inner.shape[0])


def region(image, rect, pad=0):
    """Pixels of rect [l, t, r, b] grown by pad, clipped to the image."""
    left, top, right, bottom = rect
    return crop(image, [left - pad, top - pad, right + pad, bottom + pad])


def union(a, b):
    return [min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])]


def shrink(rect, fraction):
    """The central part of rect: each side moved in by fraction of its size."""
    left, top, right, bottom = rect
    dx, dy = (right - left) * fraction, (bottom - top) * fraction
    return [left + dx, top + dy, right - dx, bottom - dy]
