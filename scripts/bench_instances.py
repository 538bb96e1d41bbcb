"""Peak memory of a Whitted render of many instances of one mesh, against one instance.

    .venv/bin/python scripts/bench_instances.py [--instances 10000] [--bpy]

Each case runs in a fresh headless Blender (Debian's `blender`, or with --bpy the
bpy module in this Python) that builds the scene, renders it with Whitted and
prints its own peak resident set size (getrusage ru_maxrss). The scene is a
geometry-nodes scatter: an ico sphere of 20,480 triangles on each point of a
grid. Shared meshes keep the difference between the cases small: copying the
mesh per instance would cost about 1 MB per instance.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

from whitted_tools.blender import blender_command, bpy_command
from whitted_tools.cli import script_args
from whitted_tools.timing import peak_rss_mib

SCRIPT = os.path.abspath(__file__)
RESULT_PREFIX = "bench_instances:"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--instances", type=int, default=10_000)
    parser.add_argument("--resolution", type=int, default=128, help="image width and height")
    parser.add_argument("--blender", default="blender", help="the Blender program to run")
    parser.add_argument(
        "--bpy", action="store_true", help="use the bpy module in this Python instead"
    )
    parser.add_argument("--child", type=int, metavar="N", help=argparse.SUPPRESS)
    args = parser.parse_args(script_args())
    if args.child is not None:
        child(args.child, args.resolution)
        return
    for count in (1, args.instances):
        command = child_command(args, count)
        print(f"$ {' '.join(command)}", flush=True)
        # The child's stderr passes through, so a failure shows its traceback.
        output = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout
        (line,) = [line for line in output.splitlines() if line.startswith(RESULT_PREFIX)]
        print(line, flush=True)


def child_command(args, count):
    options = ["--child", count, "--resolution", args.resolution]
    if args.bpy:
        return bpy_command(SCRIPT, *options, python=sys.executable)
    return blender_command(SCRIPT, *options, addons=("whitted",), blender=args.blender)


def child(count, resolution):
    """Inside Blender: build the scene, render it, print the peak memory."""
    import bpy
    from whitted_tools.bench_scenes import build_instance_grid
    from whitted_tools.blender import factory_scene

    scene = factory_scene()
    build_instance_grid(scene, count, resolution)
    with tempfile.TemporaryDirectory() as directory:
        stats_path = os.path.join(directory, "stats.json")
        os.environ["WHITTED_STATS"] = stats_path
        bpy.ops.render.render()
        with open(stats_path) as file:
            stats = json.load(file)
    peak_mib = peak_rss_mib()
    from whitted.export.mesh import mesh_instances
    from whitted_tools.bench_scenes import mesh_triangles

    geometries = {key for _, key in mesh_instances(bpy.context.evaluated_depsgraph_get())}
    print(
        f"{RESULT_PREFIX} Blender {bpy.app.version_string}, instances={stats['instances']} "
        f"geometries={len(geometries)} "
        f"exported_triangles={mesh_triangles(scene)} "
        f"instanced_triangles={stats['triangles']} "
        f"render={stats['phases']['total']:.2f}s peak_rss={peak_mib:.0f} MiB",
        flush=True,
    )


if __name__ == "__main__":
    main()
