"""Render one .blend at several quality settings (in Blender; accuracy-cost's).

Render one .blend with several quality settings (run inside Blender, by
whitted_tools accuracy-cost; not meant to be run by hand).

    blender -b --factory-startup FILE.blend \\
        --python tools/whitted_tools/__main__.py -- cost-render \\
        --runs RUNS.json --out DIR --resolution W H --repeats N

RUNS.json is a list of {"name": str, "quality": {field: value}, "use_denoising": bool}
(the fields of addon/properties/presets.py's Quality, and the scene's Denoise switch).
For each run the scene is rendered `--repeats` times with Whitted; DIR/NAME.exr
holds the last render as a 32-bit multilayer OpenEXR (Combined and the "Whitted
Rays" cost pass) and DIR/NAME.json the statistics of every repeat
(scene.whitted.last_stats), in the order run.
"""

import argparse
import json
import os

import bpy

from whitted_tools.blender import enable_addon
from whitted_tools.render import use_multilayer_exr
from whitted_tools.verbs import prog


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--runs", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--resolution", nargs=2, type=int, required=True, metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3)
    return parser.parse_args(argv)


def configure_output(scene, width, height):
    render = scene.render
    render.engine = "WHITTED"
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.use_border = False
    use_multilayer_exr(render.image_settings)


def main(argv):
    args = parse_args(argv)
    enable_addon()
    from whitted.properties.presets import Quality, apply_quality

    scene = bpy.context.scene
    configure_output(scene, *args.resolution)
    with open(args.runs, encoding="utf-8") as runs_file:
        runs = json.load(runs_file)
    for run in runs:
        apply_quality(scene.whitted, Quality(**run["quality"]))
        scene.whitted.use_denoising = run["use_denoising"]
        scene.render.filepath = os.path.join(args.out, run["name"] + ".exr")
        repeats = []
        for _ in range(args.repeats):
            bpy.ops.render.render(write_still=True)
            repeats.append(json.loads(scene.whitted.last_stats))
        with open(os.path.join(args.out, run["name"] + ".json"), "w", encoding="utf-8") as out:
            json.dump(repeats, out)
        print(f"cost_render: {run['name']}: {repeats[-1]['phases']['total']:.3f} s", flush=True)
