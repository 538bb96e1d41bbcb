"""How good is the Estimate button? Predicted against actual render time, per preset.

Run inside Blender (3.4 binary or the bpy 5.0 module); for each .blend it runs the
Estimate operator (a low-resolution probe per preset), then renders every preset
at full resolution and compares the engine's total time with the prediction:

    blender -b --factory-startup --python scripts/estimate_accuracy.py -- \\
        FILE.blend [FILE.blend ...] [--resolution 320 240] [--out docs/notes/estimate.md]

Writes a Markdown fragment (a table and the mean and worst error) for
scripts/accuracy_cost.py --notes, and prints it.
"""

import argparse
import json
import os
import shlex
import statistics
import sys

import addon_utils
import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("blend", nargs="+")
    parser.add_argument("--resolution", nargs=2, type=int, default=(320, 240), metavar=("W", "H"))
    parser.add_argument("--out", help="Markdown file to write")
    return parser.parse_args(argv), argv


def measure(path, resolution):
    """[(preset label, predicted seconds, actual seconds)] for one .blend."""
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    if addon_utils.enable("whitted", default_set=True) is None:
        sys.exit("estimate_accuracy: the add-on 'whitted' is not installed; run scripts/setup.sh")
    from whitted.properties.presets import PRESETS, apply_quality

    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    bpy.ops.whitted.estimate()
    predicted = {e.preset: e.seconds for e in scene.whitted.estimates}
    rows = []
    for key, label, _, values in PRESETS:
        apply_quality(scene.whitted, values)
        bpy.ops.render.render()
        actual = json.loads(scene.whitted.last_stats)["phases"]["total"]
        rows.append((label, predicted[key], actual))
    return scene.whitted.estimate_probe, rows


def main():
    args, argv = parse_args()
    lines = [
        "## How accurate is the Estimate button",
        "",
        "Predicted (Estimate operator, a probe at 1/8 of the resolution per preset) "
        "against actual render time (the engine's total) at "
        f"{args.resolution[0]}x{args.resolution[1]}, Blender {bpy.app.version_string}. "
        "Command:",
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
        "| scene | preset | predicted (s) | actual (s) | error |",
        "|---|---|---:|---:|---:|",
    ]
    errors = []
    for path in args.blend:
        probe, rows = measure(path, args.resolution)
        for label, predicted, actual in rows:
            error = (predicted - actual) / actual
            errors.append(abs(error))
            lines.append(
                f"| {os.path.basename(path)} | {label} | {predicted:.3f} | {actual:.3f} | "
                f"{100 * error:+.0f}% |"
            )
    lines += [
        "",
        f"Over {len(errors)} renders ({probe.split(',')[0]}): mean absolute error "
        f"{100 * statistics.fmean(errors):.0f}%, worst {100 * max(errors):.0f}%.",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as out:
            out.write(text)


if __name__ == "__main__":
    main()
