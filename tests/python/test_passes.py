"""Film passes through the bindings: Settings.passes by name, pass_tile / pass_image
and the viewport's display of a pass."""

import numpy as np
import pytest
import whitted_native as wn
from test_scene import finish, lit_floor_scene


def test_settings_take_passes_by_name_and_refuse_unknown_ones():
    settings = wn.Settings(width=8, height=8, passes=["depth", "diffuse_color"])
    assert settings.passes == ["diffuse_color", "depth"]  # in FILM_PASSES order
    assert "contributions" in wn.FILM_PASSES and "cut_weight" in wn.FILM_PASSES
    with pytest.raises(ValueError, match="no film pass 'shadow'"):
        wn.Settings(passes=["shadow"])
    with pytest.raises(ValueError, match="contribution_depth"):
        wn.Settings(passes=["contributions"], contribution_depth=9)
    with pytest.raises(ValueError, match="mist"):
        wn.Settings(mist=(0.0, -1.0, 2.0))


def test_pass_tiles_and_images_of_a_lit_floor():
    settings = wn.Settings(
        width=16,
        height=12,
        passes=["depth", "normal", "diffuse_direct", "diffuse_color", "contributions"],
        contribution_depth=2,
    )
    job = wn.RenderJob(lit_floor_scene(), settings)
    image = finish(job)
    depth = job.pass_image("depth")
    assert depth.shape == (12, 16, 1)
    assert depth.min() > 4.9 and depth.max() < 5.1  # the camera is 5 above the floor
    np.testing.assert_allclose(job.pass_image("normal")[..., 2], 1.0, atol=1e-6)
    # Diffuse only, no ambient: Color * Direct is the image.
    rebuilt = job.pass_image("diffuse_color") * job.pass_image("diffuse_direct")
    np.testing.assert_allclose(rebuilt, image[..., :3], atol=1e-5)
    # Contributions: RGB of depth 0, depth 1, and depth 2 and beyond.
    contributions = job.pass_tile("contributions", 0, 0, 16, 12)
    assert contributions.shape == (16 * 12, 9)
    assert not contributions.flags.writeable  # whole rows: a view of the film
    np.testing.assert_allclose(contributions[:, :3], image[..., :3].reshape(-1, 3), atol=1e-6)
    assert job.pass_tile("depth", 2, 3, 4, 5).shape == (20, 1)
    with pytest.raises(ValueError, match="keeps no 'mist' pass"):
        job.pass_tile("mist", 0, 0, 1, 1)


def test_display_shows_a_pass_as_rgba():
    job = wn.RenderJob(
        lit_floor_scene(), wn.Settings(width=8, height=8, passes=["depth", "normal"])
    )
    finish(job)
    depth = job.display("depth")
    assert depth.shape == (8, 8, 4)
    # Divided by the farthest surface shown: the floor's corners reach 1.
    assert depth[..., 0].max() == pytest.approx(1.0)
    np.testing.assert_array_equal(depth[..., 0], depth[..., 1])
    normal = job.display("normal")
    np.testing.assert_allclose(normal[..., 2], 1.0, atol=1e-6)
    np.testing.assert_array_equal(normal[..., 3], 1.0)
    with pytest.raises(ValueError, match="first channel"):
        job.display("normal", first=1)
