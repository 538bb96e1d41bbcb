"""Render the classic Whitted demo scene (whitted_tools.demo_scene) with the Whitted
engine, and print the absolute path of the image:

    blender -b --factory-startup --python scripts/demo_scene.py -- \\
        --output out/demo.png --resolution 640 480 [--preset PREVIEW] \\
        [--save out/demo.blend] [--no-render]
    .venv/bin/python scripts/demo_scene.py --output out/demo.png     (bpy module)

Without --preset the scene keeps the seed's quality (whitted_tools.blender.SEED_QUALITY:
2 x 2 regular samples, the scene the tests and benchmarks share); scripts/demo.sh and
docs/images/demo.png render it at the Preview preset (noise-driven sampling): the sky
lights the scene, and its feelers at 2 x 2 samples leave the shadows grainy.
"""

import argparse
import os

import bpy
from whitted_tools.blender import factory_scene
from whitted_tools.cli import script_args
from whitted_tools.demo_scene import build_demo_scene


def _parse_args():
    parser = argparse.ArgumentParser(description="Render the Whitted demo scene.")
    parser.add_argument("--output", default="out/demo.png", help="PNG to write")
    parser.add_argument("--resolution", nargs=2, type=int, default=(640, 480), metavar=("W", "H"))
    parser.add_argument(
        "--preset",
        choices=("DRAFT", "PREVIEW", "FINAL", "REFERENCE"),
        help="render at this quality preset (default: the seed's quality)",
    )
    parser.add_argument("--save", help="also save the scene as this .blend file")
    parser.add_argument(
        "--no-render", action="store_true", help="only build the scene (and --save it)"
    )
    return parser.parse_args(script_args())


def main():
    args = _parse_args()
    scene = build_demo_scene(factory_scene())
    scene.render.engine = "WHITTED"
    if args.preset:
        from whitted.properties.presets import apply_quality, preset

        apply_quality(scene.whitted, preset(args.preset))
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    # The classic look: linear radiance shown without a film curve.
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    output = os.path.abspath(args.output)
    os.makedirs(os.path.dirname(output), exist_ok=True)
    scene.render.filepath = output
    if args.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
        print(f"demo_scene: saved {os.path.abspath(args.save)}")
    if not args.no_render:
        bpy.ops.render.render(write_still=True)
        print(f"demo_scene: wrote {output}", flush=True)


if __name__ == "__main__":
    main()
