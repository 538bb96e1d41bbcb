"""Image comparisons, in numpy (no Blender): what the tests and the pages measure."""

import numpy as np


def _box_mean(image, size):
    # Mean over every size x size window ("valid" positions), via a summed-area table.
    table = np.pad(image, ((1, 0), (1, 0)), mode="constant").cumsum(0).cumsum(1)
    total = (
        table[size:, size:] - table[:-size, size:] - table[size:, :-size] + table[:-size, :-size]
    )
    return total / (size * size)


def ssim(a, b, window=7, data_range=255.0):
    """Mean structural similarity of two same-sized images, averaged over channels.

    The formulation of Wang et al. (2004) with a uniform 7x7 window and the sample
    covariance, as scikit-image's structural_similarity does by default, so its
    values are comparable with published numbers. data_range: 255 for 8-bit values,
    1 for display values in 0..1.
    """
    if a.shape != b.shape:
        raise ValueError(f"ssim of different shapes {a.shape} and {b.shape}")
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    c1, c2 = (0.01 * data_range) ** 2, (0.03 * data_range) ** 2
    n = window * window
    unbias = n / (n - 1.0)
    values = []
    channels = a.shape[2] if a.ndim == 3 else 1
    for channel in range(channels):
        x = a[..., channel] if a.ndim == 3 else a
        y = b[..., channel] if b.ndim == 3 else b
        mx, my = _box_mean(x, window), _box_mean(y, window)
        vx = (_box_mean(x * x, window) - mx * mx) * unbias
        vy = (_box_mean(y * y, window) - my * my) * unbias
        cxy = (_box_mean(x * y, window) - mx * my) * unbias
        s = ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2))
        values.append(s.mean())
    return float(np.mean(values))


def relative_rmse(image, reference):
    """RMS of the difference of the RGB channels over the RMS of the reference."""
    a, b = image[..., :3].astype(np.float64), reference[..., :3].astype(np.float64)
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b**2)))


def mean_absolute_difference(a, b):
    """Mean |a - b| over the RGB channels; None when the sizes differ."""
    if a.shape != b.shape:
        return None
    return float(np.abs(a[..., :3].astype(np.float64) - b[..., :3]).mean())


def error_figures(image, reference):
    """RMSE, PSNR (for values in 0..1) and relative MSE (each squared difference over
    the reference's square plus 0.01, so black pixels do not dominate)."""
    difference = np.asarray(image, dtype=np.float64) - reference
    mse = float(np.mean(difference**2))
    return {
        "rmse": float(np.sqrt(mse)),
        "psnr": 10.0 * float(np.log10(1.0 / mse)) if mse > 0.0 else float("inf"),
        "relmse": float(np.mean(difference**2 / (np.asarray(reference) ** 2 + 0.01))),
    }


def srgb_encode(linear):
    """Display values: linear RGB clipped to [0, 1] and sRGB-encoded (IEC 61966-2-1)."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1.0 / 2.4) - 0.055)


def luminance(rgb):
    """Rec. 709 luminance of linear RGB (the last axis)."""
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def subject_figures(image, reference, subject=None, dark=0.02):
    """(SSIM of the display images, median luminance ratio image / reference) of two
    linear RGBA renders; the ratio over the pixels both cover fully (alpha), that
    `subject` (a mask, or every pixel) keeps and the reference shows brighter than
    `dark`; nan when there are none."""
    value = ssim(srgb_encode(image[..., :3]), srgb_encode(reference[..., :3]), data_range=1.0)
    covered = (image[..., 3] > 0.99) & (reference[..., 3] > 0.99)
    if subject is not None:
        covered &= subject
    a, b = luminance(image[..., :3]), luminance(reference[..., :3])
    lit = covered & (b > dark)
    ratio = float(np.median(a[lit] / b[lit])) if lit.any() else float("nan")
    return value, ratio
