"""bench-viewport-clean's figures from its captures (outside Blender): the error over the
camera frame without the corner icon, the time to clean, the last change."""

import numpy as np
from PIL import Image
from whitted_tools.bench.viewport_clean import (
    FRAME_INSET,
    ICON_BOX,
    clean_times,
    half_way,
    last_change,
    load_frame,
    rmse,
)


def test_the_error_leaves_out_the_frame_edge_and_the_corner_icon(tmp_path):
    # A 100x80 capture whose camera frame is the whole area: grey, with a white frame
    # line and a white icon in the top-right corner, as the maximised 3D view draws them.
    pixels = np.full((80, 100, 3), 100, np.uint8)
    pixels[0, :] = pixels[:, 0] = 255
    pixels[6:20, 100 - 21 : 100 - 6] = 255
    path = tmp_path / "capture.png"
    Image.fromarray(pixels).save(path)
    image = load_frame(path, [0.0, 0.0, 100.0, 80.0])
    assert image.shape == (80 - 2 * FRAME_INSET, 100 - 2 * FRAME_INSET, 3)
    grey = np.full_like(image, 100.0)
    assert rmse(image, grey) == 0.0  # neither the line nor the icon counts
    assert np.isnan(image[0, -1]).all() and np.isnan(image[ICON_BOX - FRAME_INSET - 1, -1]).all()
    assert rmse(image, grey + 3.0) == 3.0


def test_time_to_clean_is_the_first_capture_below_each_target():
    errors = [(0.1, 9.0), (0.5, 3.5), (1.0, 1.5), (2.0, 2.5), (4.0, 0.9)]
    assert clean_times(errors, (4.0, 2.0, 1.0, 0.5)) == {4.0: 0.5, 2.0: 1.0, 1.0: 4.0, 0.5: None}


def test_the_last_change_is_the_last_capture_unlike_the_one_before():
    captures = [{"t": t, "hash": h} for t, h in ((0.1, "a"), (0.2, "b"), (0.4, "b"), (0.8, "b"))]
    assert last_change(captures) == 0.2
    assert last_change(captures[:1]) == 0.0


def test_a_references_noise_is_measured_against_its_capture_at_half_its_time():
    run = {"captures": [{"t": t, "path": f"{t}.png"} for t in (0.1, 1.0, 2.1, 3.0, 4.0)]}
    assert half_way(run) == "2.1.png"
