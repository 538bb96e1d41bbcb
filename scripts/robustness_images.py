"""Render the hard-case scenes of docs/ROBUSTNESS.md and print their measures.

    .venv/bin/python scripts/robustness_images.py [--size W H] [--output DIR]
    blender -b --factory-startup --python scripts/robustness_images.py -- [ARGS]

The scenes are tests/blender/hard_cases.py's. Each is rendered with Whitted
(anti-aliasing 2 x 2) to DIR/<case>.png (docs/images/robustness by default);
one line per image gives what the tests check: non-finite pixels and samples,
total internal reflections, sanitised triangles, trace time, and for the floor
scenes the acne share of the flat lit floor; then the relative RMSE of the scaled acne scenes.
"""

import argparse
import json
import os
import sys
import tempfile

import bpy

# isort: split
# Blender as a Python module makes addon_utils importable only after bpy.
import addon_utils
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "blender"))
import hard_cases  # noqa: E402  (a module of the test directory, found through sys.path)

CASES = {
    "acne_scale_1e-4": lambda scene: hard_cases.acne(scene, 1e-4),
    "acne_scale_1": lambda scene: hard_cases.acne(scene, 1.0),
    "acne_scale_1e5": lambda scene: hard_cases.acne(scene, 1e5),
    "grazing": hard_cases.grazing,
    "total_internal_reflection": hard_cases.total_internal_reflection,
    "water_in_glass": hard_cases.water_in_glass,
    "overlapping_spheres": hard_cases.overlapping_spheres,
    "overlapping_spheres_merged": lambda scene: hard_cases.overlapping_spheres(scene, True),
    "camera_inside_glass": lambda scene: hard_cases.camera_inside_glass(scene, offset=1.5),
    "degenerate_geometry": hard_cases.degenerate_geometry,
    "facing_mirrors": hard_cases.facing_mirrors,
    "coplanar_quads": hard_cases.coplanar_quads,
}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, nargs=2, default=(320, 240), metavar=("W", "H"))
    parser.add_argument("--output", default=os.path.join(REPO, "docs", "images", "robustness"))
    return parser.parse_args(argv)


def fresh_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if addon_utils.enable("whitted", default_set=True) is None:
        sys.exit("cannot enable the add-on 'whitted': run scripts/setup.sh")
    return bpy.context.scene


def render(scene, size, workdir, png_path):
    """Render to EXR (for the measures) and PNG; returns (linear pixels, stats)."""
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 2
    scene.view_settings.view_transform = "Standard"
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.color_mode = "OPEN_EXR", "32", "RGBA"
    scene.render.filepath = os.path.join(workdir, "render.exr")
    os.environ["WHITTED_STATS"] = os.path.join(workdir, "stats.json")
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(scene.render.filepath)
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        settings.file_format, settings.color_depth, settings.color_mode = "PNG", "8", "RGB"
        image.save_render(png_path, scene=scene)
    finally:
        bpy.data.images.remove(image)
    with open(os.environ["WHITTED_STATS"], encoding="utf-8") as stats:
        return pixels.reshape(height, width, 4), json.load(stats)


def main():
    args = parse_args()
    os.makedirs(args.output, exist_ok=True)
    images = {}
    print(f"Blender {bpy.app.version_string}, {args.size[0]}x{args.size[1]}, AA 2x2")
    with tempfile.TemporaryDirectory() as workdir:
        for name, build in CASES.items():
            path = os.path.join(args.output, f"{name}.png")
            pixels, stats = render(build(fresh_scene()), args.size, workdir, path)
            images[name] = pixels
            line = (
                f"{name:28s} non-finite pixels {int((~np.isfinite(pixels)).sum())}, "
                f"samples {stats['nonfinite_samples']}; TIR "
                f"{stats['total_internal_reflections']}; sanitised "
                f"{sum(stats['sanitised'].values())}; trace {stats['phases']['trace']:.3f} s"
            )
            if name.startswith(("acne", "grazing")):  # scenes with a flat lit floor
                acne, region = hard_cases.acne_share(pixels)
                line += f"; acne {acne:.4%} of {region} px"
            print(line)
    for scale in ("1e-4", "1e5"):
        error = hard_cases.relative_rmse(images[f"acne_scale_{scale}"], images["acne_scale_1"])
        print(f"acne scene at scale {scale} vs 1: relative RMSE {error:.2e}")
    merged = images["overlapping_spheres_merged"]
    error = hard_cases.relative_rmse(images["overlapping_spheres"], merged)
    print(f"overlapping spheres vs their union: relative RMSE {error:.4f}")
    print(f"images in {args.output}")


if __name__ == "__main__":
    main()
