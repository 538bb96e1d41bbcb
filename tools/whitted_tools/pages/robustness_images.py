"""Render the hard cases of docs/ROBUSTNESS.md and print their measures (in Blender).

    .venv/bin/python -m whitted_tools robustness-images [--size W H] [--output DIR]
    blender -b --factory-startup \\
        --python tools/whitted_tools/__main__.py -- robustness-images [ARGS]

The scenes are whitted_tools.hard_cases' (tools/whitted_tools/hard_cases.py). Each
is rendered with Whitted (anti-aliasing 2 x 2) to DIR/<case>.png (docs/images/robustness
by default); one line per image gives what the tests check: non-finite pixels and
samples, total internal reflections, sanitised triangles, trace time, and for the floor
scenes the acne share of the flat lit floor; then the relative RMSE of the scaled acne
scenes.
"""

import argparse
import json
import os
import tempfile

import bpy
import numpy as np

from whitted_tools import REPO, hard_cases
from whitted_tools.blender import factory_scene
from whitted_tools.metrics import relative_rmse
from whitted_tools.render import render_exr
from whitted_tools.verbs import prog

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


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, nargs=2, default=(320, 240), metavar=("W", "H"))
    parser.add_argument("--output", default=str(REPO / "docs" / "images" / "robustness"))
    return parser.parse_args(argv)


def render(scene, size, workdir, png_path):
    """Render to EXR (for the measures) and PNG; returns (linear pixels, stats)."""
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 2
    scene.view_settings.view_transform = "Standard"
    os.environ["WHITTED_STATS"] = os.path.join(workdir, "stats.json")
    pixels = render_exr(scene, os.path.join(workdir, "render.exr"), png=png_path)
    with open(os.environ["WHITTED_STATS"], encoding="utf-8") as stats:
        return pixels, json.load(stats)


def main(argv):
    args = parse_args(argv)
    os.makedirs(args.output, exist_ok=True)
    images = {}
    print(f"Blender {bpy.app.version_string}, {args.size[0]}x{args.size[1]}, AA 2x2")
    with tempfile.TemporaryDirectory() as workdir:
        for name, build in CASES.items():
            path = os.path.join(args.output, f"{name}.png")
            pixels, stats = render(build(factory_scene()), args.size, workdir, path)
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
        error = relative_rmse(images[f"acne_scale_{scale}"], images["acne_scale_1"])
        print(f"acne scene at scale {scale} vs 1: relative RMSE {error:.2e}")
    merged = images["overlapping_spheres_merged"]
    error = relative_rmse(images["overlapping_spheres"], merged)
    print(f"overlapping spheres vs their union: relative RMSE {error:.4f}")
    print(f"images in {args.output}")
