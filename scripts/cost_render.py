"""Render one .blend with several quality settings (run inside Blender, by
scripts/accuracy_cost.py; not meant to be run by hand).

    blender -b --factory-startup FILE.blend --python scripts/cost_render.py -- \\
        --runs RUNS.json --out DIR --resolution W H --repeats N

RUNS.json is a list of {"name": str, "quality": {field: value}} (the fields of
addon/properties/presets.py's Quality). For each run the scene is rendered
`--repeats` times with Whitted; DIR/NAME.exr holds the last render as a 32-bit
multilayer OpenEXR (Combined and the "Whitted Rays" cost pass) and DIR/NAME.json
the statistics of every repeat (scene.whitted.last_stats), in the order run.
"""

import argparse
import json
import os

import bpy
from whitted_tools.blender import enable_addon
from whitted_tools.cli import script_args
from whitted_tools.render import use_multilayer_exr


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--resolution", nargs=2, type=int, required=True, metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3)
    return parser.parse_args(script_args())


def configure_output(scene, width, height):
    render = scene.render
    render.engine = "WHITTED"
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.use_border = False
    use_multilayer_exr(render.image_settings)


def main():
    args = parse_args()
    enable_addon()
    from whitted.properties.presets import Quality, apply_quality

    scene = bpy.context.scene
    configure_output(scene, *args.resolution)
    with open(args.runs, encoding="utf-8") as runs_file:
        runs = json.load(runs_file)
    for run in runs:
        apply_quality(scene.whitted, Quality(**run["quality"]))
        scene.render.filepath = os.path.join(args.out, run["name"] + ".exr")
        repeats = []
        for _ in range(args.repeats):
            bpy.ops.render.render(write_still=True)
            repeats.append(json.loads(scene.whitted.last_stats))
        with open(os.path.join(args.out, run["name"] + ".json"), "w", encoding="utf-8") as out:
            json.dump(repeats, out)
        print(f"cost_render: {run['name']}: {repeats[-1]['phases']['total']:.3f} s", flush=True)


if __name__ == "__main__":
    main()
