"""Hash every pass of the standard scenes, to show a change alters no pixel.

Image hashes: every pass of every standard scene rendered small, hashed, to show a
change (a refactor) leaves every pixel, pass and ray count as it was.

    .venv/bin/python -m whitted_tools image-hashes --out /tmp/before.json [--blender blender]
    .venv/bin/python -m whitted_tools image-hashes --out /tmp/after.json --compare /tmp/before.json

Blender renders each scene (the demo, the cost report's, the hard cases, hair, curves and
points, an emissive panel, a moving cube) at 64x48 with every pass of the add-on's table
on, to a multilayer OpenEXR; this Python reads each channel with the OpenEXR bindings and
hashes its float32 pixels (SHA-256); the ray counts come from the render's statistics.
--compare lists what differs from an earlier run and exits 1 if anything does.

Inside Blender (`blender -b --factory-startup --python tools/whitted_tools/__main__.py --
image-hashes --render DIR`) it only renders, into DIR.
"""

import argparse
import hashlib
import json
import os
import sys
import tempfile
from pathlib import Path

from whitted_tools.verbs import prog

WIDTH, HEIGHT = 64, 48
STAT_KEYS = ("rays", "total_internal_reflections", "depth_limited", "cutoff_skipped")


def scenes():
    """name -> builder(scene) of every scene hashed (imported inside Blender)."""
    from whitted_tools import bench_scenes, camera_scenes, demo_scene, hair_scenes, hard_cases
    from whitted_tools.material_scenes import lambert_material, panel_room

    return {
        "demo": demo_scene.build_demo_scene,
        "cost glass": bench_scenes.build_glass_scene,
        "cost diffuse": bench_scenes.build_diffuse_scene,
        "cost distributed": bench_scenes.build_distributed_scene,
        "cost camera": bench_scenes.build_camera_scene,
        **hard_cases.SCENES,
        "particle hair": hair_scenes.particle_hair,
        "ribbons": hair_scenes.ribbon_hair,
        "curves": hair_scenes.curves_object,
        "points": hair_scenes.point_cloud,
        "panel": lambda scene: panel_room(scene, lambert_material("Grey", 0.8)),
        "moving cube": camera_scenes.cube_crossing,
    }


def render_all(directory):
    """Inside Blender: render every scene into `directory` (EXR and statistics)."""
    import bpy
    import whitted.result

    from whitted_tools.blender import factory_scene
    from whitted_tools.render import enable_every_pass, use_multilayer_exr

    for index, (name, build) in enumerate(scenes().items()):
        scene = factory_scene()
        build(scene)
        scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
        scene.render.resolution_percentage = 100
        scene.render.engine = "WHITTED"
        enable_every_pass(bpy.context.view_layer, whitted.result, contribution_depth=2)
        use_multilayer_exr(scene.render.image_settings)
        stem = os.path.join(directory, f"{index:02d}")
        os.environ["WHITTED_STATS"] = stem + ".json"
        scene.render.filepath = stem + ".exr"
        bpy.ops.render.render(write_still=True)
        with open(stem + ".name", "w", encoding="utf-8") as out:
            out.write(name)


def hashes(directory):
    """{scene: {"channels": {channel: sha256}, "stats": {...}}} of a rendered directory."""
    import numpy as np
    import OpenEXR

    out = {}
    for name_file in sorted(Path(directory).glob("*.name")):
        stem = name_file.with_suffix("")
        channels = {}
        with OpenEXR.File(str(stem) + ".exr", separate_channels=True) as exr:
            for part in exr.parts:
                for channel, data in part.channels.items():
                    pixels = np.ascontiguousarray(data.pixels, dtype=np.float32)
                    channels[channel] = hashlib.sha256(pixels.tobytes()).hexdigest()
        stats = json.loads(Path(str(stem) + ".json").read_text(encoding="utf-8"))
        out[name_file.read_text(encoding="utf-8")] = {
            "channels": dict(sorted(channels.items())),
            "stats": {key: stats[key] for key in STAT_KEYS},
        }
    return out


def differences(now, before):
    """Lines naming every scene, channel or count that differs."""
    lines = []
    for scene in sorted(now.keys() | before.keys()):
        if scene not in now or scene not in before:
            lines.append(f"{scene}: only in {'this run' if scene in now else 'the other'}")
            continue
        a, b = now[scene], before[scene]
        for channel in sorted(a["channels"].keys() | b["channels"].keys()):
            if a["channels"].get(channel) != b["channels"].get(channel):
                lines.append(f"{scene}: channel {channel} differs")
        if a["stats"] != b["stats"]:
            lines.append(f"{scene}: statistics differ: {a['stats']} against {b['stats']}")
    return lines


def main(argv):
    if "--render" in argv:  # inside Blender
        parser = argparse.ArgumentParser(prog=prog(__name__))
        parser.add_argument("--render", required=True)
        render_all(parser.parse_args(argv).render)
        return
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--compare", type=Path, help="an earlier run's --out")
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args(argv)
    from whitted_tools.blender import run_process, verb_in_blender

    with tempfile.TemporaryDirectory(prefix="whitted-hashes-") as directory:
        command = verb_in_blender(
            "image-hashes", "--render", directory, blender=args.blender, addons=("whitted",)
        )
        _, problem = run_process(command, 1800)
        if problem:
            sys.exit(f"rendering: {problem}")
        now = hashes(directory)
    args.out.write_text(json.dumps(now, indent=1, sort_keys=True), encoding="utf-8")
    channels = sum(len(s["channels"]) for s in now.values())
    print(f"image_hashes: {len(now)} scenes, {channels} channels -> {args.out}")
    if args.compare is not None:
        lines = differences(now, json.loads(args.compare.read_text(encoding="utf-8")))
        print("\n".join(lines) if lines else f"identical to {args.compare}")
        if lines:
            sys.exit(1)
