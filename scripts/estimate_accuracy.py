"""How good is the Estimate button? Predicted against actual time and error, per preset.

Run inside Blender (3.4 binary or the bpy 5.0 module); for each .blend it runs the
Estimate operator (a probe of each preset: addon/estimate.py), then renders every
preset at the full resolution and compares the engine's total time (the median of
up to --repeats renders, fewer once MAX_RENDER_SECONDS have been spent on a preset)
and the display error against the Reference render (addon/estimate_model.py's
display_error, on the whole frame) with the predictions:

    blender -b --factory-startup --python scripts/estimate_accuracy.py -- \\
        FILE.blend [FILE.blend ...] [--resolution 320 240] [--repeats 3] \\
        [--out docs/notes/estimate_accuracy.md]

Writes a Markdown page (a table, the time, rays and error figures; docs/ACCURACY_COST.md
links to it) and prints it. docs/notes/estimate_accuracy.md was made at 240x180 from
six scenes built by the scene builders (S=/tmp/crypto-scenes):

    blender -b --factory-startup --python scripts/perf_scenes.py -- --scene demo \
        --resolution 320 240 --save $S/demo.blend
    blender -b --factory-startup --python scripts/cost_scenes.py -- --scene glass \
        --save $S/glass.blend                      (and --scene diffuse)
    blender -b --factory-startup --python scripts/perf_scenes.py -- --scene glass8 \
        --resolution 320 240 --save $S/glass8.blend
    ... --scene instances --instances 1000 --ico-subdivisions 3 (instances.blend)
    ... --scene triangles --triangles 300000 (triangles.blend)
"""

import argparse
import json
import os
import shlex
import statistics
import sys
import tempfile
import time

import addon_utils
import bpy
import numpy as np

# Renders of one preset stop repeating once they have taken this long in all.
MAX_RENDER_SECONDS = 20.0


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("blend", nargs="+")
    parser.add_argument("--resolution", nargs=2, type=int, default=(320, 240), metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3, help="renders of each preset at most")
    parser.add_argument("--out", help="Markdown file to write")
    return parser.parse_args(argv), argv


def render_image(scene, path):
    """Render the scene to an EXR at `path`; (engine's total seconds, rays per pixel,
    float[H, W, 4])."""
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    stats = json.loads(scene.whitted.last_stats)
    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(height, width, 4)
    bpy.data.images.remove(image)
    return stats["phases"]["total"], stats["rays"]["total"] / stats["pixels"], pixels


def measure(path, resolution, repeats, workdir):
    """(probe description, Estimate seconds, [(preset label, predicted s, actual s,
    predicted error, actual error, predicted rays per pixel, actual)]) for one .blend."""
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    if addon_utils.enable("whitted", default_set=True) is None:
        sys.exit("estimate_accuracy: the add-on 'whitted' is not installed; run scripts/setup.sh")
    from whitted.estimate import REFERENCE
    from whitted.estimate_model import display_error
    from whitted.properties.presets import PRESETS, apply_quality

    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    started = time.perf_counter()
    bpy.ops.whitted.estimate()
    estimate_seconds = time.perf_counter() - started
    predicted = {e.preset: (e.seconds, e.error, e.rays_per_pixel) for e in scene.whitted.estimates}
    actual = {}
    for key, _, _, values in PRESETS:
        apply_quality(scene.whitted, values)
        times = []
        for _ in range(repeats):
            seconds, rays, image = render_image(scene, os.path.join(workdir, f"{key}.exr"))
            times.append(seconds)
            if sum(times) >= MAX_RENDER_SECONDS:
                break
        actual[key] = (statistics.median(times), image, rays)
    reference = actual[REFERENCE][1]
    rows = [
        (
            label,
            predicted[key][0],
            actual[key][0],
            predicted[key][1],
            display_error(actual[key][1], reference),
            predicted[key][2],
            actual[key][2],
        )
        for key, label, _, _ in PRESETS
    ]
    return scene.whitted.estimate_probe, estimate_seconds, rows


def rank(values):
    """The order of `values` (indices, largest first)."""
    return sorted(range(len(values)), key=lambda i: -values[i])


def main():
    args, argv = parse_args()
    load = os.getloadavg()[0]
    lines = [
        "## How accurate is the Estimate button",
        "",
        "Predicted (Estimate operator: each preset traces one tile in n^2 of the frame "
        "at full resolution, addon/estimate.py) against actual render time (the engine's "
        f"total, median of up to {args.repeats} renders) and error against the Reference "
        "render (RMSE as an 8-bit sRGB display shows the image, in levels of 255: "
        f"addon/estimate_model.py), at {args.resolution[0]}x{args.resolution[1]}, "
        f"Blender {bpy.app.version_string}, {os.cpu_count()} cores. Command:",
        "",
        "    "
        + shlex.join(
            [
                "blender",
                "-b",
                "--factory-startup",
                "--python",
                "scripts/estimate_accuracy.py",
                "--",
                *argv,
            ]
        ),
        "",
        "| scene | preset | predicted (s) | actual (s) | time error | predicted rays/px "
        "| actual rays/px | predicted error | actual error |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    time_errors, error_ratios, ranks_right, probes, estimate_seconds = [], [], 0, set(), []
    ray_errors = []
    with tempfile.TemporaryDirectory() as workdir:
        for path in args.blend:
            probe, seconds, rows = measure(path, args.resolution, args.repeats, workdir)
            probes.add(probe)
            estimate_seconds.append(seconds)
            for label, predicted, actual, predicted_error, actual_error, *rays in rows:
                error = (predicted - actual) / actual
                time_errors.append(abs(error))
                ray_errors.append(abs(rays[0] / rays[1] - 1.0))
                if actual_error > 0.0:
                    error_ratios.append(predicted_error / actual_error)
                lines.append(
                    f"| {os.path.basename(path)} | {label} | {predicted:.3f} | {actual:.3f} | "
                    f"{100 * error:+.0f}% | {rays[0]:.1f} | {rays[1]:.1f} | "
                    f"{predicted_error:.2f} | {actual_error:.2f} |"
                )
            ranks_right += rank([r[3] for r in rows]) == rank([r[4] for r in rows])
    scenes = len(args.blend)
    lines += [
        "",
        f"Time, over {len(time_errors)} renders: mean absolute error "
        f"{100 * statistics.fmean(time_errors):.1f}%, worst {100 * max(time_errors):.0f}%. "
        f"Rays: mean absolute error {100 * statistics.fmean(ray_errors):.1f}%, worst "
        f"{100 * max(ray_errors):.1f}% (the rest of the time error is the ray rate and the "
        "fixed costs: export, BVH, write-back, as the load of the machine moves them).",
        "",
        f"Error: the predicted order of the presets is right on {ranks_right} of {scenes} "
        f"scenes; predicted / actual error over the {len(error_ratios)} presets below "
        f"Reference: median {statistics.median(error_ratios):.2f}, from "
        f"{min(error_ratios):.2f} to {max(error_ratios):.2f}.",
        "",
        f"Probe: {'; '.join(sorted(probes))}. The Estimate button took "
        f"{statistics.fmean(estimate_seconds):.1f} s a scene on average (at most "
        f"{max(estimate_seconds):.1f} s). Load average over 1 minute when the run began: "
        f"{load:.1f} (other work shared the cores; times vary with it).",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as out:
            out.write(text)


if __name__ == "__main__":
    main()
