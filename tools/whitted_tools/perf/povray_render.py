"""Render a saved scene with POV-Ray 3.7 as Whitted renders it, timed (in Blender 3.4).

Render a saved scene with POV-Ray 3.7 through Blender 3.4's render_povray add-on, set
up to render what Whitted renders (whitted_tools.povray explains the mapping), and time it.

    blender -b SCENE.blend \\
        --python tools/whitted_tools/__main__.py -- perf-povray --json OUT.json --image OUT.png
"""

import argparse
import json

import bpy

from whitted_tools import povray
from whitted_tools.verbs import prog


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog=prog(__name__),
        description=__doc__.splitlines()[0],
    )
    parser.add_argument("--json", help="write the times and settings here")
    parser.add_argument("--image", required=True, help="the rendered image (PNG)")
    parser.add_argument("--work-dir", help="keep the add-on's .pov, .ini and POV-Ray's output here")
    return parser.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    scene = bpy.context.scene
    povray.configure(scene)
    result = povray.render(scene, args.image, work_dir=args.work_dir)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as out:
            json.dump(result, out, indent=2)
    print(
        f"perf_povray: {result['resolution'][0]}x{result['resolution'][1]} "
        f"render {result['render_seconds']:.3f} s, POV-Ray trace {result['povray_seconds']:.3f} s "
        f"(parse {result['povray_parse_seconds']:.3f} s) on {result['threads']} threads; "
        f"wrote {result['image']}",
        flush=True,
    )
