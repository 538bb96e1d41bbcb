"""The live sync and the Rendered viewport, measured: writes docs/VIEWPORT.md.

    .venv/bin/python -m whitted_tools bench-viewport [--out docs/VIEWPORT.md] [--repeats 9]
        [--quick] [--blender blender]

1. Sync (`blender -b`, Blender 3.4): on the demo, the million-triangle scene and the
   10,000-instance scene (whitted_tools perf-scenes), each edit is made the way the
   viewport receives it (a depsgraph update reaching SceneSync), --repeats times;
   the page gives the median time of the sync itself, of the native compile the next
   job does (the top-level BVH over all instances), and of Blender's own depsgraph
   evaluation of the edit; beside it, measured in the same process, a full export of
   the same scene (a sync from empty, mesh BVHs included, and its compile).
2. Latency (a real Blender 3.4 window under Xvfb, tests/viewport's harness): the demo
   in a 1000x700 Rendered viewport; after each edit, the time from the sync (the
   viewport's view_update) to the first view_draw that shows a pass of the new
   state, and to the full-resolution pass at one sample per pixel.

--quick: tiny scenes, few repeats, an --out outside docs/ (a smoke test).
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from whitted_tools import REPO
from whitted_tools.blender import enable_addon, run_for_json, verb_in_blender
from whitted_tools.pages import machine_lines, write_page
from whitted_tools.perf.measure import build_scene
from whitted_tools.verbs import prog, python_line

SCENES = ("demo", "million", "instances")
# The object each edit touches, by scene: a plain mesh object (no modifiers).
EDITED = {"demo": "Cube", "million": "Gold Torus", "instances": "Mirror Floor"}
EDITS = ("transform", "material", "geometry", "instancer")
TARGETS_MS = {"demo": 2.0, "million": 10.0, "instances": 10.0}  # transform: sync + compile
LATENCY_TARGET_MS = 50.0


# --- inside Blender: the sync measurement ---------------------------------------------


def child_sync(args):
    import bpy

    enable_addon()
    from whitted.native import load_native
    from whitted.properties.presets import preset
    from whitted.sync import SceneSync, SyncParams

    native = load_native()
    scene = bpy.context.scene
    params = SyncParams.of(scene, preset("PREVIEW"))
    settings = native.Settings(width=64, height=64, threads=1)
    live = SceneSync(native)
    live.sync(bpy.context.evaluated_depsgraph_get(), params)
    reports = []

    def on_update(scene, depsgraph):
        reports.append(live.sync(depsgraph, params))

    bpy.app.handlers.depsgraph_update_post.append(on_update)

    def compile_seconds(sync):
        return native.RenderJob(sync.scene, settings).stats()["compile_seconds"]

    obj = bpy.data.objects[args.edited]
    material = obj.material_slots[0].material
    principled = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    scatter = bpy.data.objects.get("Scatter")

    def edit(kind, i):
        sign = 1.0 if i % 2 == 0 else -1.0
        if kind == "transform":
            obj.location.x += 0.01 * sign
        elif kind == "material":
            principled.inputs["Base Color"].default_value = (0.5 + 0.1 * sign, 0.5, 0.5, 1.0)
        elif kind == "geometry":
            obj.data.vertices[0].co.z += 0.001 * sign
            obj.data.update()
        else:
            scatter.location.z += 0.01 * sign

    results = {}
    for kind in EDITS:
        if kind == "instancer" and scatter is None:
            continue
        rows = []
        for i in range(args.repeats):
            reports.clear()
            started = time.perf_counter()
            edit(kind, i)
            bpy.context.view_layer.update()
            total = time.perf_counter() - started
            sync = sum(r.seconds for r in reports)
            rows.append(
                {
                    "sync": sync,
                    "compile": compile_seconds(live),
                    "depsgraph": total - sync,
                    "report": [r.as_dict() for r in reports],
                }
            )
        results[kind] = rows
    full = []
    for _ in range(args.repeats):
        started = time.perf_counter()
        fresh = SceneSync(native)
        fresh.sync(bpy.context.evaluated_depsgraph_get(), params)
        full.append({"export": time.perf_counter() - started, "compile": compile_seconds(fresh)})
    results["full"] = full
    stats = native.RenderJob(live.scene, settings).stats()
    results["scene"] = {"triangles": stats["triangles"], "instances": stats["instances"]}
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(results, out)


# --- outside Blender: run, then write the page ----------------------------------------


def median_ms(rows, *keys):
    return 1000.0 * statistics.median(sum(row[k] for k in keys) for row in rows)


def sync_section(measured, repeats):
    lines = [
        "## Sync after an edit, beside a full export",
        "",
        f"Median of {repeats} edits each (milliseconds). *sync*: SceneSync's work for the "
        "update; *compile*: the next job's native compile (the top-level BVH over every "
        "instance, rebuilt only when an instance or mesh changed); *sync + compile* is "
        "what Whitted adds before the first ray; *depsgraph*: Blender's own evaluation "
        "of the edit, which any engine waits for. *full export*: a sync from empty (mesh "
        "BVHs included) and its compile, in the same process.",
        "",
        "| scene | triangles | instances | edit | sync | compile | sync + compile | "
        "depsgraph | full export + compile | full / edit |",
        "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, results in measured.items():
        full = median_ms(results["full"], "export", "compile")
        info = results["scene"]
        for kind in EDITS:
            rows = results.get(kind)
            if rows is None:
                continue
            edit = median_ms(rows, "sync", "compile")
            lines.append(
                f"| {name} | {info['triangles']:,} | {info['instances']:,} | {kind} | "
                f"{median_ms(rows, 'sync'):.2f} | {median_ms(rows, 'compile'):.2f} | "
                f"{edit:.2f} | {median_ms(rows, 'depsgraph'):.1f} | {full:.0f} | "
                f"{full / edit:.0f}x |"
            )
    lines.append("")
    return lines


def targets_section(measured, latency):
    lines = ["## Targets", "", "| target | measured | result |", "|---|---|---|"]
    for name, limit in TARGETS_MS.items():
        if name not in measured:
            continue
        value = median_ms(measured[name]["transform"], "sync", "compile")
        verdict = "pass" if value <= limit else f"**missed** by {value - limit:.1f} ms"
        lines.append(
            f"| transform edit, {name}: sync + compile <= {limit:g} ms | {value:.2f} ms | "
            f"{verdict} |"
        )
    if latency:
        first = statistics.median(e["first_ms"] for e in latency["edits"])
        verdict = (
            "pass"
            if first <= LATENCY_TARGET_MS
            else f"**missed** by {first - LATENCY_TARGET_MS:.0f} ms"
        )
        lines.append(
            f"| demo: first refreshed image <= {LATENCY_TARGET_MS:g} ms after the edit | "
            f"{first:.0f} ms (median) | {verdict} |"
        )
        idle = latency["idle"]
        lines.append(
            f"| CPU idle once converged | {idle['cpu_percent']:.1f}% of one core over "
            f"{idle['seconds']:.0f} s, {idle['frames']} frames drawn | "
            f"{'pass' if idle['cpu_percent'] < 5.0 and idle['frames'] == 0 else '**missed**'} |"
        )
    lines.append("")
    return lines


def latency_section(latency):
    if not latency:
        return ["## Latency in a window", "", "Not measured in this run.", ""]
    lines = [
        "## Latency in a window (the demo, Blender 3.4 under Xvfb)",
        "",
        f"A {latency['region'][0]}x{latency['region'][1]} Rendered 3D view in camera view, "
        "Mesa's software OpenGL (llvmpipe).",
        "",
        "Milliseconds from the sync of an edit (view_update) to the first view_draw that "
        "shows a pass of the new state, and to the full-resolution pass at 1 sample per "
        "pixel; the first pass's pixel size is chosen from the measured speed.",
        "",
        "| edit | sync | first image | first pixel size | full resolution, 1 spp |",
        "|---|---:|---:|---:|---:|",
    ]
    for edit in latency["edits"]:
        lines.append(
            f"| {edit['name']} | {edit['sync_ms']:.1f} | {edit['first_ms']:.0f} | "
            f"{edit['first_pixel_size']} | {edit['full_ms']:.0f} |"
        )
    lines.append("")
    return lines


def run_latency(args, workdir, demo_blend):
    """The window measurement (viewport_latency.py beside this file), or None."""
    scenario = Path(__file__).with_name("viewport_latency.py")
    result = os.path.join(workdir, "latency.json")
    env_log = os.path.join(workdir, "latency.jsonl")
    command = [
        "xvfb-run",
        "-a",
        "-s",
        # A screen whose maximised 3D view is about 1000x700 (the page states it).
        "-screen 0 1000x700x24",
        "env",
        f"WHITTED_VIEWPORT_LOG={env_log}",
        args.blender,
        "--factory-startup",
        str(demo_blend),
        "--python",
        str(scenario),
        "--",
        "--result",
        result,
        "--out",
        workdir,
    ]
    measured, problem = run_for_json(command, result, 600)
    if problem:
        print(f"latency: {problem}")
        return None
    return measured["data"]


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(REPO / "docs" / "VIEWPORT.md"))
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--child-sync", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--edited", help=argparse.SUPPRESS)
    parser.add_argument("--json", help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    if args.child_sync:
        child_sync(args)
        return
    started = time.perf_counter()
    repeats = 3 if args.quick else args.repeats
    measured = {}
    latency = None
    with tempfile.TemporaryDirectory(prefix="whitted-bench-viewport-") as workdir:
        for name in SCENES:
            path = os.path.join(workdir, f"{name}.blend")
            extra = ["--triangles", "20000"] if args.quick and name == "million" else []
            extra += ["--instances", "400"] if args.quick and name == "instances" else []
            problem = build_scene(name, path, (320, 240), 900, args.blender, extra)
            if problem:
                sys.exit(f"building {name}: {problem}")
            out = os.path.join(workdir, f"{name}.json")
            command = verb_in_blender(
                "bench-viewport",
                *("--child-sync", "--edited", EDITED[name], "--json", out, "--repeats", repeats),
                blend=path,
                blender=args.blender,
            )
            measured[name], problem = run_for_json(command, out, 900)
            if problem:
                sys.exit(f"sync on {name}: {problem}")
        latency = run_latency(args, workdir, os.path.join(workdir, "demo.blend"))
    elapsed = time.perf_counter() - started
    command = python_line("bench-viewport", *(["--quick"] if args.quick else []))
    page = [
        "# The live sync and the Rendered viewport",
        "",
        f"Generated by `{command}` in {elapsed / 60:.1f} min; do not "
        "edit by hand. Blender 3.4 (Debian's), Whitted's Preview viewport preset.",
        "",
        *machine_lines(),
        "",
        *targets_section(measured, latency),
        *sync_section(measured, repeats),
        *latency_section(latency),
    ]
    write_page(args.out, page)
