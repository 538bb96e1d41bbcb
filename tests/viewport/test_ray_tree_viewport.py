"""The inspected ray tree is drawn in the 3D view where the tree says (Blender 3.4, a
real window under Xvfb): at points along each drawn ray the after-screenshot shows the
ray kind's colour, which the before-screenshot did not."""

import images
import numpy as np

# The colours of addon/ray_tree/draw.py as 8-bit screen values (drawn as given).
COLOURS = {
    "shadow": (89, 255, 89),
    "reflection": (77, 153, 255),
    "refraction": (255, 89, 230),
    "tir": (255, 128, 26),
    "transparent": (191, 191, 191),
}
NEAR = 3  # pixels around a projected point searched for the colour
TOLERANCE = 40  # per channel


def _has_colour(image, xy, colour):
    x, y = (round(c) for c in xy)
    h, w, _ = image.shape
    patch = image[max(0, y - NEAR) : min(h, y + NEAR + 1), max(0, x - NEAR) : min(w, x + NEAR + 1)]
    if patch.size == 0:
        return False
    close = np.all(np.abs(patch[..., :3].astype(int) - np.array(colour)) <= TOLERANCE, axis=-1)
    return bool(close.any())


def test_inspected_tree_is_drawn_where_its_rays_are(demo_blend, run_scenario):
    run = run_scenario("ray_tree.py", demo_blend)
    run.assert_clean()
    assert run.data["inspect"] == ["FINISHED"], run.describe()
    before = images.load(run.screenshot("before")["path"])
    after = images.load(run.screenshot("after")["path"])
    width, height = run.data["area"]
    points = [
        p
        for p in run.data["points"]
        if not p["blocked"] and 0 <= p["xy"][0] < width and 0 <= p["xy"][1] < height
    ]
    kinds = {p["kind"] for p in points}
    assert "reflection" in kinds and len(points) >= 6, run.data["points"]
    drawn = [p for p in points if _has_colour(after, p["xy"], COLOURS[p["kind"]])]
    new = [p for p in drawn if not _has_colour(before, p["xy"], COLOURS[p["kind"]])]
    print(f"ray tree points in view {len(points)}, drawn {len(drawn)}, new {len(new)}")
    assert len(new) >= 0.8 * len(points), (points, drawn)
