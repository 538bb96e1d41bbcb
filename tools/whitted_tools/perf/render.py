"""Render one saved scene once; what it cost as JSON (in Blender; bench-performance's).

Render one saved scene once and write what it cost as JSON (run inside Blender, by
whitted_tools bench-performance).

    blender -b --factory-startup --addons whitted FILE.blend \\
        --python tools/whitted_tools/__main__.py -- perf-render \\
        --engine WHITTED|CYCLES|POVRAY|NULL \\
        --json OUT.json [--threads N] [--depth D] [--resolution W H] [--image OUT.png]
    .venv/bin/python -m whitted_tools perf-render --blend FILE.blend --engine ...  (bpy module)

The JSON holds the wall seconds of the render call (bpy.ops.render.render; for POVRAY
the render_seconds whitted_tools.povray.render reports, the same call: end to end inside
Blender, without Blender's start-up, the file's load and writing the image), this
process's peak resident set size (getrusage ru_maxrss, read after the render), the
Blender version, the image size and threads, the scene's "perf_scene" and
"perf_mesh_triangles" properties (whitted_tools perf-scenes) and:

    WHITTED  "whitted": the engine's statistics (scene.whitted.last_stats: phases,
             rays by type, rays_per_second, peak_memory_mib, ...)
    POVRAY   "povray": what whitted_tools.povray.render returned (render_seconds,
             povray_seconds, ...)
    CYCLES   nothing more: the scene's own Cycles settings (64 samples, CPU)
    NULL     a do-nothing engine registered here: Blender evaluates the scene and
             allocates the render result as for any engine, the engine touches every
             object instance and writes an empty image. Its peak RSS is Blender's own
             memory for the same file at the same size, the baseline that Whitted's
             peak is compared against.

--threads N fixes Blender's render threads (Whitted and Cycles use them; default:
Blender's, all cores); --depth D sets scene.whitted.max_depth before the engine is
configured (POV-Ray's configure may read it); --resolution overrides the saved size.
"""

import argparse
import json
import os
import sys
import tempfile
import time

import bpy

from whitted_tools.blender import enable_addon
from whitted_tools.timing import peak_rss_mib
from whitted_tools.verbs import prog

ENGINES = ("WHITTED", "CYCLES", "POVRAY", "NULL")
NULL_ENGINE = "PERF_NULL"


class NullEngine(bpy.types.RenderEngine):
    """Renders nothing: the baseline of Blender's own memory for a scene."""

    bl_idname = NULL_ENGINE
    bl_label = "Null (performance baseline)"

    def render(self, depsgraph):
        # Walk the evaluated scene as an exporter would, copying nothing.
        instances = sum(1 for _ in depsgraph.object_instances)
        render = depsgraph.scene.render
        scale = render.resolution_percentage / 100.0
        width = int(render.resolution_x * scale)
        height = int(render.resolution_y * scale)
        result = self.begin_result(0, 0, width, height)
        self.end_result(result)
        self.update_stats("", f"null engine: {instances} object instances")


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--engine", choices=ENGINES, required=True)
    parser.add_argument("--json", required=True, help="the JSON file to write")
    parser.add_argument("--threads", type=int, help="render threads (default: Blender's)")
    parser.add_argument("--depth", type=int, help="scene.whitted.max_depth")
    parser.add_argument("--resolution", nargs=2, type=int, metavar=("W", "H"))
    parser.add_argument("--image", help="also write the image here (PNG)")
    parser.add_argument("--blend", help="open this .blend first (the bpy module)")
    return parser.parse_args(argv)


def apply_overrides(scene, args):
    render = scene.render
    if args.resolution:
        render.resolution_x, render.resolution_y = args.resolution
        render.resolution_percentage = 100
    if args.threads:
        render.threads_mode = "FIXED"
        render.threads = args.threads
    if args.depth is not None:
        scene.whitted.max_depth = args.depth


def render(scene, args, image_path):
    """Render one frame with args.engine; (wall seconds, extra JSON fields)."""
    render_settings = scene.render
    render_settings.filepath = image_path
    render_settings.image_settings.file_format = "PNG"
    if args.engine == "POVRAY":
        from whitted_tools import povray  # Blender 3.4's POV-Ray add-on only

        povray.configure(scene)
        started = time.perf_counter()
        figures = povray.render(scene, image_path)
        wall = time.perf_counter() - started
        # Its render_seconds time the render call alone, as below for the other engines.
        seconds = figures.get("render_seconds", wall)
        return seconds, {"povray": {"wall_seconds": wall, **figures}}
    if args.engine == "WHITTED":
        render_settings.engine = "WHITTED"
        scene.whitted.last_stats = ""
    elif args.engine == "CYCLES":
        render_settings.engine = "CYCLES"
        scene.cycles.device = "CPU"
    else:
        render_settings.engine = NULL_ENGINE
    started = time.perf_counter()
    bpy.ops.render.render()
    seconds = time.perf_counter() - started
    if args.image:  # after the clock: writing the file is not the render
        bpy.data.images["Render Result"].save_render(image_path, scene=scene)
    if args.engine == "WHITTED":
        if not scene.whitted.last_stats:
            sys.exit("perf_render: the Whitted render wrote no statistics (see its log)")
        return seconds, {"whitted": json.loads(scene.whitted.last_stats)}
    return seconds, {}


def main(argv):
    args = parse_args(argv)
    if args.blend:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
    # Every engine runs with the add-on's settings registered (its native module loads
    # only when a Whitted render starts), so the NULL baseline holds its Python too.
    enable_addon()
    if args.engine == "CYCLES":
        enable_addon("cycles")
    elif args.engine == "NULL":
        bpy.utils.register_class(NullEngine)
    scene = bpy.context.scene
    apply_overrides(scene, args)
    with tempfile.TemporaryDirectory(prefix="whitted-perf-") as tmp:
        image = os.path.abspath(args.image) if args.image else os.path.join(tmp, "image.png")
        seconds, extra = render(scene, args, image)
    render_settings = scene.render
    scale = render_settings.resolution_percentage / 100.0
    out = {
        "engine": args.engine,
        "blend": bpy.data.filepath,
        "blender": bpy.app.version_string,
        "scene": scene.get("perf_scene", scene.name),
        "mesh_triangles": scene.get("perf_mesh_triangles"),
        "width": int(render_settings.resolution_x * scale),
        "height": int(render_settings.resolution_y * scale),
        "threads": render_settings.threads,
        "max_depth": scene.whitted.max_depth,
        "seconds": seconds,
        "peak_rss_mib": peak_rss_mib(),
        **extra,
    }
    with open(args.json, "w", encoding="utf-8") as file:
        json.dump(out, file, indent=2)
    print(f"perf_render: {args.engine} {out['width']}x{out['height']}: {seconds} s", flush=True)
