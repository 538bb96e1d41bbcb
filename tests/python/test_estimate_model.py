"""The Estimate button's arithmetic (addon/estimate_model.py), without Blender: the
probe's size, the display error and the time prediction."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

PATH = Path(__file__).parents[2] / "addon" / "estimate_model.py"
SPEC = importlib.util.spec_from_file_location("whitted_estimate_model", PATH)
model = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(model)


@pytest.mark.parametrize(
    ("width", "height", "stride"),
    [(48, 36, 1), (160, 120, 2), (320, 240, 4), (640, 480, 8), (1920, 1080, 8)],
)
def test_probe_stride_keeps_at_least_the_minimum_and_at_most_one_64th(width, height, stride):
    assert model.probe_stride(width * height) == stride
    # A probe of one tile in stride^2 has at least MIN_PROBE_PIXELS, or is the frame.
    assert width * height / stride**2 >= min(model.MIN_PROBE_PIXELS, width * height)


def test_display_is_srgb_of_the_clamped_linear_value():
    linear = np.array([[-1.0, 0.0, 0.0031308], [0.5, 1.0, 7.0]])
    shown = model.display(linear)
    np.testing.assert_allclose(shown[0], [0.0, 0.0, 0.0031308 * 12.92])
    np.testing.assert_allclose(shown[1], [0.735357, 1.0, 1.0], atol=1e-6)


def test_display_error_is_in_levels_and_ignores_alpha_and_what_clamps():
    reference = np.full((10, 10, 4), 0.5)
    assert model.display_error(reference, reference) == 0.0
    one_level = reference.copy()
    shown = model.display(reference)[0, 0, 0] + 1.0 / 255.0
    one_level[..., :3] = ((shown + 0.055) / 1.055) ** 2.4  # the linear value shown 1 up
    one_level[..., 3] = 0.0  # alpha is not compared
    assert model.display_error(one_level, reference) == pytest.approx(1.0)
    # Highlights that both show as white differ by nothing on the display.
    assert model.display_error(np.full((2, 3), 5.0), np.full((2, 3), 8.0)) == 0.0
    # One pixel in 100 black instead of mid grey: sqrt(1/100) of its levels.
    wrong = reference.copy()
    wrong[0, 0] = 0.0
    expected = 255.0 * model.display(np.full(3, 0.5))[0] * 0.1
    assert model.display_error(wrong, reference) == pytest.approx(expected)


def test_rate_leaves_out_each_repeats_start_up():
    # Two repeats of 1000 rays, 0.011 s and 0.013 s with 0.001 s of start-up each.
    rate = model.rays_per_second([1000, 1000], [0.011, 0.013], 0.001)
    assert rate == pytest.approx(2000 / 0.022)
    assert model.rays_per_second([10], [0.0005], 0.001) == 0.0  # nothing but start-up


def test_predicted_time_scales_the_probes_rays_to_every_pixel():
    seconds = model.predict_seconds(
        fixed_seconds=0.5,
        startup_seconds=0.01,
        probe_rays=1e6,
        probe_pixels=4800,
        pixels=76800,
        rate=2e6,
    )
    assert seconds == pytest.approx(0.5 + 0.01 + 16e6 / 2e6)
    assert model.predict_seconds(0.5, 0.01, 0, 0, 76800, 0.0) == pytest.approx(0.51)
