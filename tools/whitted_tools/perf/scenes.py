"""Save a scene of the performance suite (bench-performance) as a .blend (in Blender).

    blender -b --factory-startup \\
        --python tools/whitted_tools/__main__.py -- perf-scenes --scene NAME \\
        --resolution W H --save OUT.blend [--triangles N] [--depth D] [--instances N] \\
        [--ico-subdivisions N] [--parents N]
    .venv/bin/python -m whitted_tools perf-scenes --scene NAME ...            (bpy module)

The scenes (demo, million, instances, glass8, triangles, fur) and the settings they share
are whitted_tools.bench_scenes'. The scene's custom properties "perf_scene" and
"perf_mesh_triangles" (the triangles of the distinct meshes Whitted exports, each
instanced mesh once) are saved with it.
"""

import argparse
import os

import bpy

from whitted_tools import bench_scenes
from whitted_tools.blender import factory_scene
from whitted_tools.verbs import prog

BUILDERS = {
    "demo": bench_scenes.build_demo,
    "million": bench_scenes.build_million,
    "instances": bench_scenes.build_instances,
    "glass8": bench_scenes.build_glass8,
    "triangles": bench_scenes.build_triangles,
    "fur": bench_scenes.build_fur,
    # The cost report's scenes of distributed ray tracing, for the presets' glossy and
    # lens samples: rough metal, plastic and frosted glass; a lens at f/1.4 and a moving
    # ball.
    "distributed": lambda scene, _args: bench_scenes.build_distributed_scene(scene),
    "camera": lambda scene, _args: bench_scenes.build_camera_scene(scene),
}


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=sorted(BUILDERS), required=True)
    parser.add_argument("--resolution", nargs=2, type=int, required=True, metavar=("W", "H"))
    parser.add_argument("--save", required=True, help=".blend file to write")
    parser.add_argument("--triangles", type=int, help="million, triangles: triangle count")
    parser.add_argument("--instances", type=int, help="instances: instance count")
    parser.add_argument("--parents", type=int, help="fur: parent hairs (20 children each)")
    parser.add_argument(
        "--ico-subdivisions",
        type=int,
        help="instances: subdivisions of the instanced ico sphere (default "
        f"{bench_scenes.ICO_SUBDIVISIONS}: 20,480 triangles)",
    )
    parser.add_argument("--depth", type=int, help="Whitted's max depth (default 5; glass8: 8)")
    return parser.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    scene = BUILDERS[args.scene](factory_scene("whitted", "cycles"), args)
    default_depth = (
        bench_scenes.GLASS8_MAX_DEPTH if args.scene == "glass8" else bench_scenes.DEFAULT_MAX_DEPTH
    )
    bench_scenes.configure(
        scene, args.resolution, default_depth if args.depth is None else args.depth
    )
    scene["perf_scene"] = args.scene
    scene["perf_mesh_triangles"] = bench_scenes.mesh_triangles(scene)
    path = os.path.abspath(args.save)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    print(
        f"perf_scenes: saved {path} ({args.scene}, "
        f"{scene['perf_mesh_triangles']:,} mesh triangles)",
        flush=True,
    )
