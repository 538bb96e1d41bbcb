"""The two kernels (waves, recursion) on any .blend, timed and compared (in Blender).

The two kernels on any .blend: traced in waves (Trace in Waves, the default) against
the recursion (the reference), as F12 syncs the scene.

    blender -b FILE.blend --addons whitted \\
        --python tools/whitted_tools/__main__.py -- compare-kernels \\
        [--resolution 160 120] [--threads 1] [--repeats 3] [--preset KEY] [--passes] \\
        [--json OUT]

Prints one line: the rays of each (they must be equal, by type), the most memory a
worker's wave queues held, the largest difference
of any channel relative to max(1, |recursion|) (the wave only reorders sums), the
pixels that differ by more than 1e-4 of that, and the median of the rounds' paired time
ratios (recursion / waves: above 1 the waves are faster). --preset renders at a quality
preset (DRAFT, PREVIEW, FINAL, REFERENCE) instead of the file's own controls; --passes
keeps the view layer's passes as F12 does (Depth is on in every new view layer). For files
we did not make: the wave must be tried on them before it is trusted (docs/notes/waves.md).
"""

import argparse
import json
import os

import bpy

# isort: split
import numpy as np

from whitted_tools.native_job import run_job
from whitted_tools.timing import paired_median
from whitted_tools.verbs import prog


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", nargs=2, type=int, default=(160, 120), metavar=("W", "H"))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--preset", help="a quality preset's key, instead of the file's controls")
    parser.add_argument("--passes", action="store_true", help="the view layer's passes, as F12")
    parser.add_argument("--json", help="also write the figures here")
    return parser.parse_args(argv)


def render(native, frame, waves):
    settings = frame.settings
    settings.waves = waves
    job = run_job(frame.job(native, settings))
    stats = job.stats()
    return job.image().copy(), stats


def main(argv):
    args = parse_args(argv)
    # The add-on's modules: importable once Blender enabled it (--addons whitted).
    from whitted.native import load_native
    from whitted.properties.presets import apply_quality, preset
    from whitted.result import configure, enabled_passes
    from whitted.sync.frame import sync_frame

    scene = bpy.context.scene
    if scene.camera is None:
        print(f"{os.path.basename(bpy.data.filepath)}: no camera, nothing to render")
        return
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    if args.preset:
        apply_quality(scene.whitted, preset(args.preset))
    native = load_native()
    frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
    if args.passes:  # as F12 asks for them (engine.py)
        view_layer = bpy.context.view_layer
        configure(frame.settings, scene, view_layer, enabled_passes(view_layer))
    render(native, frame, False)  # warm-up: page in the BVHs, start the threads once
    seconds = {"recursion": [], "waves": []}
    for _ in range(args.repeats):
        reference, recursion = render(native, frame, False)
        image, waves = render(native, frame, True)
        seconds["recursion"].append(recursion["trace_seconds"])
        seconds["waves"].append(waves["trace_seconds"])
    relative = np.abs(image - reference) / np.maximum(1.0, np.abs(reference))
    result = {
        "file": os.path.basename(bpy.data.filepath),
        "preset": args.preset,
        "passes": list(frame.settings.passes) if args.passes else [],
        "rays_equal": dict(waves["rays"]) == dict(recursion["rays"]),
        "rays": waves["rays"]["total"],
        "waves_on": waves["waves"],
        # The most memory one worker's wave queues held (bytes).
        "queue_bytes": waves["wave_bytes"],
        "max_relative": float(relative.max()),
        "pixels_over_1e-4": int((relative.max(axis=-1) > 1e-4).sum()),
        "speed_ratio": paired_median(seconds["recursion"], seconds["waves"]),
    }
    print(
        f"{result['file']} {result['preset'] or ''} {result['passes']}: rays "
        f"{result['rays']:,} equal {result['rays_equal']}, waves "
        f"{result['waves_on']} (queues {result['queue_bytes']:,} bytes), max relative "
        f"{result['max_relative']:.2g}, pixels over 1e-4 "
        f"{result['pixels_over_1e-4']}, recursion / waves time {result['speed_ratio']:.3f}"
    )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as out:
            json.dump(result, out, indent=1)
