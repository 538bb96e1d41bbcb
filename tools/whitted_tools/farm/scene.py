"""The farm's demo animation as a .blend (in Blender): tests/farm's scenes, bench-farm's.

    blender -b --factory-startup --python-exit-code 1 \\
        --python tools/whitted_tools/__main__.py -- farm-scene OUT.blend [--fail] [--size W H]

The demo scene at 96 x 72 (or W x H) with its camera moving over frames 1-6 (so every frame
differs), Whitted as the engine. --fail gives the camera a zero scale, which
Whitted refuses (an engine error after which Blender itself would exit 0).
"""

import argparse
import os

import bpy

from whitted_tools.blender import factory_scene
from whitted_tools.demo_scene import build_demo_scene
from whitted_tools.verbs import prog


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--fail", action="store_true")
    parser.add_argument("--size", nargs=2, type=int, default=(96, 72), metavar=("W", "H"))
    args = parser.parse_args(argv)
    scene = build_demo_scene(factory_scene())
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    scene.frame_start, scene.frame_end = 1, 6
    camera = scene.camera
    for frame in (1, 6):
        camera.location.x = -1.5 if frame == 1 else 1.5
        camera.keyframe_insert("location", index=0, frame=frame)
    if args.fail:
        camera.scale = (0.0, 0.0, 0.0)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out))
