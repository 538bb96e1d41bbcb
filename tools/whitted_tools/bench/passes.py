"""What render passes cost (in Blender): the costs of docs/PASSES.md.

What render passes cost (docs/PASSES.md): the demo scene traced with no extra pass,
with Depth alone, with the data passes, with the light passes, with the Whitted ones
(the per-depth passes and Cut Weight) and with every pass, interleaved in one run;
trace time from each render's stats.

    .venv/bin/python -m whitted_tools bench-passes --out docs          (bpy 5.0 module)
    blender -b --factory-startup --python-exit-code 1 \\
        --python tools/whitted_tools/__main__.py -- bench-passes --out docs

Writes OUT/images/passes/cost-blender-X.Y.json (whitted_tools passes-page puts the
figures of every Blender that ran this on the page). Renders without passes run the
kernels compiled without a pass recorder; any pass switches the render to the ones
with it, whose recorder fills only what the enabled groups of passes read
(native/src/integrator/passes.h).
"""

import json
import os
import time

import bpy

from whitted_tools import demo_scene
from whitted_tools.blender import factory_scene
from whitted_tools.cli import page_parser
from whitted_tools.pages import machine_lines
from whitted_tools.timing import median_or_none
from whitted_tools.verbs import blender_line, python_line

WIDTH, HEIGHT = 480, 360
AA_SAMPLES = 2
REPEATS = 9
CONTRIBUTION_DEPTH = 3
VARIANTS = ("none", "depth", "data", "light", "whitted", "all")
COMMANDS = (
    python_line("bench-passes", "--out", "docs"),
    blender_line("bench-passes", "--out", "docs"),
)


def parse_args(argv):
    return page_parser(__name__, __doc__, REPEATS).parse_args(argv)


def build_scene():
    scene = demo_scene.build_demo_scene(factory_scene())
    render = scene.render
    render.engine = "WHITTED"
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    scene.whitted.aa_samples = AA_SAMPLES
    return scene


def set_passes(view_layer, variant):
    """Switch on the passes of `variant`: none, Depth alone, the Data panel's, the Light
    panel's, the Whitted panel's (Cut Weight and the per-depth passes), or every pass of
    result.PASSES with the per-depth passes (Whitted Rays stays on: it is the ray cost
    every render counts)."""
    from whitted import result

    for spec in result.PASSES:
        if not spec.toggle or spec.source == "rays":
            continue
        wanted = (
            variant == "all"
            or spec.panel.lower() == variant
            or (variant == "depth" and spec.source == "depth")
        )
        holder, prop = spec.switch(view_layer)
        if holder is not None:
            setattr(holder, prop, wanted)
    view_layer.whitted.use_pass_contributions = variant in ("whitted", "all")
    view_layer.whitted.contribution_depth = CONTRIBUTION_DEPTH


def trace_seconds(scene):
    """(trace seconds, CPU seconds of the whole render, rays, passes written) of one
    render. The CPU seconds (every thread of this process, the export and the write-back
    of the passes included) move less than the wall clock when other work shares the
    cores."""
    started = time.process_time()
    bpy.ops.render.render()
    cpu = time.process_time() - started
    stats = json.loads(scene.whitted.last_stats)
    return stats["phases"]["trace"], cpu, stats["rays"]["total"], len(stats["passes"])


def main(argv):
    args = parse_args(argv)
    scene = build_scene()
    view_layer = scene.view_layers[0]
    times = {name: [] for name in VARIANTS}
    cpu = {name: [] for name in VARIANTS}
    rays, passes = {}, {}
    for _ in range(args.repeats):
        for name in VARIANTS:
            set_passes(view_layer, name)
            seconds, cpu_seconds, rays[name], passes[name] = trace_seconds(scene)
            times[name].append(seconds)
            cpu[name].append(cpu_seconds)
    median = {name: median_or_none(values) for name, values in times.items()}
    best = {name: min(values) for name, values in times.items()}
    result = {
        "blender": bpy.app.version_string,
        "resolution": [WIDTH, HEIGHT],
        "aa_samples": AA_SAMPLES,
        "contribution_depth": CONTRIBUTION_DEPTH,
        "repeats": args.repeats,
        "trace_seconds": times,
        "cpu_seconds": cpu,
        "cpu_median_over_none": {
            name: median_or_none(cpu[name]) / median_or_none(cpu["none"]) for name in VARIANTS
        },
        "median": median,
        "best": best,
        "rays": rays,
        "passes_written": passes,
        "median_over_none": {name: median[name] / median["none"] for name in VARIANTS},
        "best_over_none": {name: best[name] / best["none"] for name in VARIANTS},
        "machine": machine_lines(),
        "commands": list(COMMANDS),
    }
    version = ".".join(str(v) for v in bpy.app.version[:2])
    directory = os.path.join(args.out, "images", "passes")
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, f"cost-blender-{version}.json")
    with open(path, "w") as file:
        json.dump(result, file, indent=2)
    for name in VARIANTS:
        print(
            f"bench_passes: {name}: {passes[name]} passes, median trace {median[name]:.3f} s "
            f"(best {best[name]:.3f} s, {result['median_over_none'][name]:.3f}x), "
            f"render CPU {result['cpu_median_over_none'][name]:.3f}x, rays {rays[name]}"
        )
    print(f"bench_passes: {machine_lines()[-1][2:]}; wrote {path}")
