"""whitted_tools.metrics without Blender: the image comparisons the pages and tests use."""

import numpy as np
import pytest
from whitted_tools.metrics import error_figures, mean_absolute_difference, relative_rmse, ssim


def noise_image(seed, shape=(32, 40, 3)):
    return np.random.default_rng(seed).uniform(0.0, 255.0, shape)


def test_ssim_of_an_image_with_itself_is_one():
    image = noise_image(1)
    assert ssim(image, image) == pytest.approx(1.0, abs=1e-12)


def test_ssim_is_symmetric_and_falls_with_the_noise_added():
    image = noise_image(2)
    rng = np.random.default_rng(3)
    slightly = image + rng.normal(0.0, 5.0, image.shape)
    badly = image + rng.normal(0.0, 60.0, image.shape)
    assert ssim(image, slightly) == pytest.approx(ssim(slightly, image), abs=1e-12)
    assert 0.0 < ssim(image, badly) < ssim(image, slightly) < 1.0


def test_ssim_of_two_flat_images_follows_the_luminance_term():
    # Flat windows: no variance, so SSIM is (2 mx my + c1) / (mx^2 + my^2 + c1).
    a, b = np.full((16, 16), 100.0), np.full((16, 16), 120.0)
    c1 = (0.01 * 255.0) ** 2
    expected = (2 * 100.0 * 120.0 + c1) / (100.0**2 + 120.0**2 + c1)
    assert ssim(a, b) == pytest.approx(expected, rel=1e-12)


def test_ssim_refuses_different_shapes():
    with pytest.raises(ValueError, match="different shapes"):
        ssim(np.zeros((8, 8, 3)), np.zeros((8, 9, 3)))


def test_relative_rmse_and_mean_absolute_difference():
    reference = np.ones((4, 4, 4))
    image = reference.copy()
    image[..., :3] *= 1.1  # alpha is not compared
    image[..., 3] = 7.0
    assert relative_rmse(image, reference) == pytest.approx(0.1)
    assert mean_absolute_difference(image, reference) == pytest.approx(0.1)
    assert mean_absolute_difference(image, np.ones((4, 5, 4))) is None


def test_error_figures():
    reference = np.full((2, 2), 0.5)
    figures = error_figures(reference + 0.1, reference)
    assert figures["rmse"] == pytest.approx(0.1)
    assert figures["psnr"] == pytest.approx(20.0)
    assert figures["relmse"] == pytest.approx(0.01 / (0.25 + 0.01))
    assert error_figures(reference, reference)["psnr"] == float("inf")
