"""The Estimate button's arithmetic: how big its probe is, and how a probe's time and
image become a full render's predicted time and error. Plain Python and numpy (no
bpy), so it is tested without Blender (tests/python/test_estimate_model.py).

The probe traces one tile in n^2 of the frame at full resolution (native
Settings.probe_stride = n): a pixel's value and rays never depend on its neighbours,
so the probe's pixels are exactly the full render's, and need no model of how
rays per pixel or error change with resolution. Only the count is scaled:

    predicted seconds = fixed + start-up + probe rays * (pixels / probe pixels) / rate

fixed: the export (with the meshes' BVHs) and the scene compile (top-level BVH),
each measured once; start-up: starting the worker threads, measured on a job of a
few pixels; rate: the probe's rays per second of tracing, start-up excluded.

    predicted error = 255 sqrt(mean over the probe's pixels and R, G, B of
                            (display(preset) - display(Reference))^2)

display(c) = the sRGB encoding of linear c clamped to [0, 1]: the image as an 8-bit
PNG with the Standard view transform shows it, so the error is in grey levels of
255. Not the linear RMSE of docs/ACCURACY_COST.md: unclamped, a few specular
highlights (linear values of 5 to 8 that one preset's samples catch and another's
miss) carry most of its square (84% from 0.1% of the demo's pixels at 320x240), and
a sample of the pixels cannot predict it, nor does an artist see it.
"""

import math

import numpy as np

# The probe covers 1/PROBE_STRIDE^2 of the pixels at most (1/64: the cost of the former
# probe at 1/8 of each side) ...
PROBE_STRIDE = 8
# ... and at least this many pixels (80 x 60), or the whole frame when it is smaller.
MIN_PROBE_PIXELS = 4800
# The probe's tiles: 2x2 pixels, so that a probe is thousands of them spread over the
# frame. Its rays per pixel are a sample mean, and where a few pixels take most of the
# rays (glass, mirrors and soft shadows at a deep preset: a pixel's rays vary by 1.6 to
# 2.2 times their mean on the scenes of whitted_tools estimate-accuracy) a sample of 75
# tiles of 8x8 (4,800 pixels) missed the frame's mean by up to 13% (Final, 240x180);
# 1,200 tiles of 2x2 miss it by 2% at most there.
PROBE_TILE_SIZE = 2
# The probe's timing jobs (a probe's rate, not its pixels): tiles of 8x8. Each tile
# costs the job a fixed hand-over (the shared tile counter and the statistics' lock,
# whose cache lines the two cores pass back and forth); in a 2x2 tile of a Draft
# preset, about 9 rays, that hand-over was a quarter of the tile's time (the probe's
# rate came out 24% low on the demo scene), and a 32x32 tile of the render pays it 256
# times less often per pixel. At 8x8 it is 16 times rarer than at 2x2, and a probe of
# a 240x180 frame at stride 3 still holds 75 tiles for the two threads to share.
TIMING_TILE_SIZE = 8


def probe_stride(pixels):
    """The probe stride n (one tile in n^2 traced) for a frame of `pixels` pixels."""
    return max(1, min(PROBE_STRIDE, math.isqrt(pixels // MIN_PROBE_PIXELS)))


# The display's levels: the error is in steps of an 8-bit image.
LEVELS = 255.0


def display(rgb):
    """float64[..., 3]: linear RGB (float[..., >= 3], alpha ignored) clamped to [0, 1]
    and sRGB-encoded (IEC 61966-2-1)."""
    linear = np.clip(np.asarray(rgb, np.float64)[..., :3], 0.0, 1.0)
    return np.where(
        linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1.0 / 2.4) - 0.055
    )


def display_error(image, reference):
    """The RMSE of two linear images (float[..., >= 3]) as displayed, in 8-bit levels."""
    difference = display(image) - display(reference)
    return LEVELS * math.sqrt(float(np.mean(difference**2))) if difference.size else 0.0


def rays_per_second(rays, trace_seconds, startup_seconds):
    """Rays per second of tracing, summed over repeats of one probe: `rays` and
    `trace_seconds` are per repeat; each repeat's thread start-up is left out."""
    tracing = sum(max(t - startup_seconds, 0.0) for t in trace_seconds)
    return sum(rays) / tracing if tracing > 0.0 else 0.0


def predict_seconds(fixed_seconds, startup_seconds, probe_rays, probe_pixels, pixels, rate):
    """The full render's predicted seconds (module docstring)."""
    if probe_pixels <= 0 or rate <= 0.0:
        return fixed_seconds + startup_seconds
    return fixed_seconds + startup_seconds + probe_rays * pixels / probe_pixels / rate
