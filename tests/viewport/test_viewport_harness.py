"""The harness itself, proven with Blender's own engines in a real 3.4 window under Xvfb.

If these fail, the Whitted viewport tests cannot be trusted either: the window,
camera view, screenshots or the camera-frame alignment are broken, not Whitted.
"""

import images
import numpy as np
import pytest
from whitted_tools.metrics import ssim
from windowrun import run_in_window

# Linear sky colour of scripts/demo_scene.py (0.25, 0.45, 0.8), as the screen shows it
# with the Standard view transform (sRGB): measured (137, 176, 230) in EEVEE and Cycles.
SKY_ON_SCREEN = np.array([137.0, 180.0, 231.0])


@pytest.fixture(scope="module")
def harness_run(demo_blend, tmp_path_factory):
    # One Blender session for all the checks below (each launch costs ~5 s).
    return run_in_window(tmp_path_factory.mktemp("harness"), "harness.py", demo_blend)


def _sky(image, frame):
    # The top-centre of the camera frame: only sky there in the demo's camera view.
    left, top, right, _ = frame
    cx = int((left + right) / 2)
    return image[int(top) + 10 : int(top) + 40, cx - 20 : cx + 20].reshape(-1, 3).mean(axis=0)


def test_blender_runs_the_scenario_cleanly(harness_run):
    harness_run.assert_clean()
    print(f"Blender {harness_run.result['blender']} on {harness_run.result['gpu']}")


@pytest.mark.parametrize(
    "name", ["workbench_solid", "eevee_rendered_final", "cycles_rendered"], ids=str
)
def test_screenshot_is_the_maximised_area_and_not_black(harness_run, name):
    harness_run.assert_clean()
    shot = harness_run.screenshot(name)
    image = images.load(shot["path"])
    # The 3D view was maximised over the whole 1280x800 window, header hidden: the
    # area, its main region and the PNG are all that size.
    assert shot["area"] == [1280, 800] and shot["region"] == [1280, 800], shot
    assert image.shape == (800, 1280, 3), (image.shape, shot)
    assert image.mean() > 40.0, f"{name} is (nearly) black: mean {image.mean():.1f}"
    assert image.std() > 20.0, f"{name} is flat: std {image.std():.1f}"
    # The camera frame fills the height (view_center_camera) and keeps the render's 4:3.
    left, top, right, bottom = shot["camera_frame"]
    assert 0 <= left < right <= 1280 and 0 <= top < bottom <= 800, shot["camera_frame"]
    assert (right - left) / (bottom - top) == pytest.approx(4 / 3, rel=0.01)


@pytest.mark.parametrize("name", ["eevee_rendered_final", "cycles_rendered"], ids=str)
def test_rendered_mode_shows_the_world(harness_run, name):
    # In Rendered mode the sky is the demo's world colour, not the Solid theme's grey:
    # proves the shading type took effect in the window.
    harness_run.assert_clean()
    shot = harness_run.screenshot(name)
    sky = _sky(images.load(shot["path"]), shot["camera_frame"])
    assert np.abs(sky - SKY_ON_SCREEN).max() < 12.0, f"sky of {name} on screen: {sky}"


@pytest.mark.parametrize(
    ("shot_name", "render_name", "threshold"),
    [
        # Measured 0.988 (Workbench) and 0.979 (EEVEE, 16 samples both) on llvmpipe.
        ("workbench_solid_final", "workbench_f12", 0.95),
        ("eevee_rendered_final", "eevee_f12", 0.93),
    ],
    ids=["workbench", "eevee"],
)
def test_camera_frame_in_the_screenshot_matches_an_f12_render(
    harness_run, shot_name, render_name, threshold
):
    """The alignment the Whitted comparison relies on, proven with Blender's engines.

    The camera frame is found by projecting the camera's view frame into the region
    (driver.Harness.camera_frame); the F12 render was made at that frame's size.
    """
    harness_run.assert_clean()
    shot = harness_run.screenshot(shot_name)
    render = harness_run.result["renders"][render_name]
    frame = shot["camera_frame"]
    assert render["size"] == [round(frame[2] - frame[0]), round(frame[3] - frame[1])]
    view, still = images.camera_view(images.load(shot["path"]), frame, images.load(render["path"]))
    value = ssim(view, still)
    print(f"SSIM {shot_name} vs {render_name}: {value:.4f}")
    assert value > threshold, f"SSIM {value:.4f} <= {threshold}"
    # A frame off by a few pixels would still look much alike to SSIM: the same
    # crop shifted right by 6 px must match worse, or the alignment proves nothing.
    shifted = images.crop(
        images.load(shot["path"]),
        [frame[0] + 6, frame[1], frame[2] + 6, frame[3]],
        images.FRAME_INSET,
    )
    height, width = min(shifted.shape[0], view.shape[0]), min(shifted.shape[1], view.shape[1])
    worse = ssim(shifted[:height, :width], still[:height, :width])
    print(f"SSIM with the frame 6 px off: {worse:.4f}")
    assert worse < value - 0.02
