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
import math
import os
import resource
import subprocess
import sys
import tempfile

SCRIPT = os.path.abspath(__file__)
RESULT_PREFIX = "bench_instances:"
ICO_SUBDIVISIONS = 6  # 20 * 4^(6 - 1) = 20,480 triangles (subdivision 1 is the icosahedron)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--instances", type=int, default=10_000)
    parser.add_argument("--resolution", type=int, default=128, help="image width and height")
    parser.add_argument("--blender", default="blender", help="the Blender program to run")
    parser.add_argument(
        "--bpy", action="store_true", help="use the bpy module in this Python instead"
    )
    parser.add_argument("--child", type=int, metavar="N", help=argparse.SUPPRESS)
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    args = parser.parse_args(argv)
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
    options = ["--child", str(count), "--resolution", str(args.resolution)]
    if args.bpy:
        return [sys.executable, SCRIPT, *options]
    return [
        *(args.blender, "-b", "--factory-startup", "--addons", "whitted"),
        *("--python-exit-code", "1", "--python", SCRIPT, "--", *options),
    ]


def child(count, resolution):
    """Inside Blender: build the scene, render it, print the peak memory."""
    import bpy

    # isort: split
    # Blender as a Python module makes addon_utils importable only after bpy.
    import addon_utils

    addon_utils.enable("whitted", default_set=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("whitted", default_set=True)
    scene = bpy.context.scene
    build_scene(scene, count, resolution)
    with tempfile.TemporaryDirectory() as directory:
        stats_path = os.path.join(directory, "stats.json")
        os.environ["WHITTED_STATS"] = stats_path
        bpy.ops.render.render()
        with open(stats_path) as file:
            stats = json.load(file)
    # ru_maxrss is in KiB on Linux.
    peak_mib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    from whitted.export.mesh import convert_meshes

    exported = convert_meshes(bpy.context.evaluated_depsgraph_get(), [])
    print(
        f"{RESULT_PREFIX} Blender {bpy.app.version_string}, instances={stats['instances']} "
        f"exported_meshes={len(exported.meshes)} "
        f"exported_triangles={sum(len(m.triangles) for m in exported.meshes)} "
        f"instanced_triangles={stats['triangles']} "
        f"render={stats['phases']['total']:.2f}s peak_rss={peak_mib:.0f} MiB",
        flush=True,
    )


def build_scene(scene, count, resolution):
    import bpy
    import numpy as np

    # The geometry-nodes tree the tests use too (as scripts/gallery.py shares scenes).
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(__file__)), "tests", "blender"))
    import node_trees

    side = math.ceil(math.sqrt(count))
    spacing = 1.0
    u = (np.arange(side) - (side - 1) / 2.0) * spacing
    x, y = np.meshgrid(u, u)
    points = np.stack([x.ravel(), y.ravel(), np.zeros(side * side)], axis=-1)[:count]

    mesh = bpy.data.meshes.new("Points")
    mesh.vertices.add(count)
    mesh.vertices.foreach_set("co", points.astype(np.float32).reshape(-1))
    scatter = bpy.data.objects.new("Scatter", mesh)
    scene.collection.objects.link(scatter)
    tree = node_trees.ico_sphere_on_points("Scatter", radius=0.4, subdivisions=ICO_SUBDIVISIONS)
    scatter.modifiers.new("Scatter", "NODES").node_group = tree

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = side * spacing + 1.0
    camera.location = (0.0, 0.0, 10.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.rotation_euler = (0.5, 0.3, 0.0)
    scene.collection.objects.link(sun)

    scene.render.engine = "WHITTED"
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 1


if __name__ == "__main__":
    main()
