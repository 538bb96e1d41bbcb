"""What each mechanism behind "simulate only the effects a scene calls for" saves (in Blender).

Benchmark (not a test): what each mechanism behind "simulate only the effects a scene
calls for" saves, against the plain Whitted tracer.

The plain tracer is the classic recursion: every effect on, a shadow feeler to every
light sample, a reflected or refracted ray wherever its coefficient is not zero and its
weight on the pixel is at least the cutoff. Each mechanism is then switched alone, in
the same process, renders interleaved (each repetition starts at the next mode):
(a) the scene analysis (effects the scene cannot show switched off), (b) per-surface
feeler pruning, (c) the weight cutoff (switched off: what it saves), and all together
(the default). (d), the kernels compiled per set of effects against one kernel with the
effects as run-time flags, needs two builds: --compare-native DIR names a folder with
another build's whitted_native module, and each repetition runs this build's and that
one's renders in turn, each in a Blender of its own.

    blender -b --factory-startup --python-exit-code 1 \\
        --python tools/whitted_tools/__main__.py -- bench-effects \\
        [--resolution 320 240] [--repeats 9] [--compare-native DIR] [--out docs/EFFECTS.md]
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import bpy

# isort: split
import numpy as np

from whitted_tools.blender import factory_scene, run_for_json, verb_in_same_blender
from whitted_tools.builds import interleaved, native_module, stand_in_for_addon
from whitted_tools.demo_scene import DEMO_VARIANTS, build_demo_variant
from whitted_tools.native_job import run_job
from whitted_tools.pages import load_text, machine_lines, table, write_page
from whitted_tools.timing import paired_ratios, spread_text
from whitted_tools.verbs import blender_line, prog

CUTOFF = 1.0 / 255.0
AA_SAMPLES = 2
# The modes of one build: Settings fields. "plain" is the baseline every ratio divides by.
MODES = {
    "plain": {"analysis": False, "feeler_pruning": False, "cutoff": CUTOFF},
    "analysis": {"analysis": True, "feeler_pruning": False, "cutoff": CUTOFF},
    "feeler pruning": {"analysis": False, "feeler_pruning": True, "cutoff": CUTOFF},
    "no cutoff": {"analysis": False, "feeler_pruning": False, "cutoff": 0.0},
    "all": {"analysis": True, "feeler_pruning": True, "cutoff": CUTOFF},
}
RAY_KINDS = ("camera", "shadow", "reflection", "refraction", "transparent", "total")
# What the code does with each mechanism, and why (the ratios on the page are the reason).
VERDICTS = {
    "(a) scene analysis": "kept: in each of these scenes it switches translucency off (no "
    "cut-outs, and glass casts opaque shadows by default), so a feeler is one occlusion "
    "query, not that and a walk, and in the diffuse scene reflection and refraction too; "
    "a scene that calls for every effect switches nothing off",
    "(b) feeler pruning": "kept: it sends fewer feelers in every scene (rays table) and "
    "its median ratios are below 1",
    "(c) weight cutoff": "kept: faster where branches fall below it (glass, everything); "
    "where none does (diffuse, mirrors) its ratio is 1 within the spread",
    "(d) kernels per effect set": "kept, for renders without passes only. On this "
    "shared machine the control column (the same run-time kernel in both builds) "
    "spreads as widely as the (d) column, so this page alone does not settle it; "
    "instruction counts do: `valgrind --tool=callgrind` over one render of "
    "`whitted_tools.builds`' 64 spheres of constant materials (its --small render: "
    "160x90, 2x2 samples, one thread) counts 2.0% fewer instructions in the render with "
    "them (167.5 M against 170.9 M, commit da74e9b). integrator/whitted.cpp compiles 12 "
    "of them (the sets the analysis decides with pruning on) beside one kernel with run-time flags "
    "for every other set, one for renders with passes and the inspector's: 15, not the "
    "96 that one per set for each would be (and the 14 render kernels again whose "
    "queries go through the benchmark's log: 29 in all)",
}


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.split("\n\n")[0])
    parser.add_argument("--resolution", type=int, nargs=2, default=(320, 240))
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--compare-native", help="a folder with another build's module")
    parser.add_argument("--out", help="write the page to this Markdown file")
    # A child's own arguments: its results file, which mode goes first, its module.
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--rotation", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--native", help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def load_module(folder):
    """whitted_native from `folder` (another build, which the add-on then uses too), or
    the add-on's own."""
    if folder is None:
        from whitted.native import load_native

        return load_native()
    module = native_module(folder)
    stand_in_for_addon(module)
    return module


def render(native, frame, mode, width, height):
    """(RGB image, stats, CPU seconds this process spent, all its threads)."""
    settings = native.Settings(width=width, height=height, aa_samples=AA_SAMPLES, **MODES[mode])
    job = frame.job(native, settings)
    started = time.process_time()
    run_job(job)
    return job.image()[..., :3], job.stats(), time.process_time() - started


def run_child(args):
    """One repetition: every scene in every mode, the modes rotated by --rotation."""
    # First: importing the add-on loads its own module (its controls' tables), which
    # another build's could then no longer stand in for.
    native = load_module(args.native)
    from whitted.sync.frame import sync_frame

    width, height = args.resolution
    names = list(MODES)
    order = names[args.rotation % len(names) :] + names[: args.rotation % len(names)]
    results = {}
    for variant in DEMO_VARIANTS:
        scene = build_demo_variant(variant, factory_scene())
        scene.render.resolution_x, scene.render.resolution_y = width, height
        scene.render.resolution_percentage = 100
        frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
        render(native, frame, "all", width, height)  # a warm-up, not counted
        images, modes = {}, {}
        for mode in order:
            images[mode], stats, cpu_seconds = render(native, frame, mode, width, height)
            modes[mode] = {
                "trace_seconds": stats["trace_seconds"],
                "cpu_seconds": cpu_seconds,
                "rays": {kind: stats["rays"][kind] for kind in RAY_KINDS},
                "shadow_rays_skipped": stats["shadow_rays_skipped"],
                "cutoff_skipped": stats["cutoff_skipped"],
                "effects": stats["effects"],
            }
        brightest = float(images["plain"].max())
        for mode, image in images.items():
            difference = np.abs(image - images["plain"])
            modes[mode]["difference"] = [float(difference.max()), float(difference.mean())]
        results[variant] = {"modes": modes, "brightest": brightest}
    Path(args.child).write_text(json.dumps(results), encoding="utf-8")


def child_command(args, results, rotation, native):
    return verb_in_same_blender(
        "bench-effects",
        *("--resolution", *args.resolution, "--child", results, "--rotation", rotation),
        *(("--native", native) if native else ()),
    )


def run_repetitions(args, folder):
    """[repetition][build] -> that child's results; the builds alternate which goes first."""
    builds = [None] + ([os.path.abspath(args.compare_native)] if args.compare_native else [])

    def run(index, rotation):
        results = Path(folder) / f"{rotation}-{index}.json"
        command = child_command(args, results, rotation, builds[index])
        done, problem = run_for_json(command, results, timeout=900)
        if problem:
            sys.exit(f"bench_effects.py: a repetition {problem}")
        return done

    return interleaved(args.repeats, len(builds), run)


def ratios(repetitions, variant, numerator, denominator, clock, builds=(0, 0)):
    """'median [min..max]' over the repetitions of the `clock` seconds of (build, mode)
    numerator over denominator, taken within each repetition."""

    def seconds(build, mode):
        return [r[build][variant]["modes"][mode][clock] for r in repetitions]

    return spread_text(
        paired_ratios(seconds(builds[0], numerator), seconds(builds[1], denominator))
    )


def attribution(repetitions, clock):
    """The table of time ratios per mechanism and scene, by `clock`."""
    compared = len(repetitions[0]) > 1
    header = [
        "scene",
        "(a) analysis / plain",
        "(b) feeler pruning / plain",
        "(c) plain / no cutoff",
        "all / plain",
    ]
    if compared:
        header += ["(d) per effect set / run-time flags: all", "(d) control: plain"]
    rows = []
    for variant in DEMO_VARIANTS:
        row = [
            variant,
            ratios(repetitions, variant, "analysis", "plain", clock),
            ratios(repetitions, variant, "feeler pruning", "plain", clock),
            ratios(repetitions, variant, "plain", "no cutoff", clock),
            ratios(repetitions, variant, "all", "plain", clock),
        ]
        if compared:
            row.append(ratios(repetitions, variant, "all", "all", clock, builds=(0, 1)))
            row.append(ratios(repetitions, variant, "plain", "plain", clock, builds=(0, 1)))
        rows.append(row)
    return table(header, rows)


def page(args, repetitions, load_before, load_after):
    width, height = args.resolution
    first = repetitions[0][0]
    compared = len(repetitions[0]) > 1
    header = ["scene", "mode", *(f"{k} rays" for k in RAY_KINDS), "median trace s"]
    rays_rows = []
    differences = []
    for variant in DEMO_VARIANTS:
        modes = first[variant]["modes"]
        for mode in MODES:
            median = statistics.median(
                r[0][variant]["modes"][mode]["trace_seconds"] for r in repetitions
            )
            rays = [modes[mode]["rays"][kind] for kind in RAY_KINDS]
            rays_rows.append([variant, mode, *rays, f"{median:.3f}"])
        bound = CUTOFF * first[variant]["brightest"]
        for mode in ("analysis", "feeler pruning", "no cutoff", "all"):
            skipped = modes[mode]["shadow_rays_skipped"]
            largest, mean = modes[mode]["difference"]
            differences.append(
                [
                    variant,
                    mode,
                    f"{largest:.2e}",
                    f"{mean:.2e}",
                    f"{bound:.2e}",
                    f"{skipped['backfacing']} / {skipped['unlit']} / {skipped['cutoff']}",
                    modes[mode]["cutoff_skipped"],
                ]
            )
    decisions = [
        f"- {variant}: "
        + "; ".join(
            f"{e['name']} {'on' if e['on'] else 'off'} ({e['why']})"
            for e in first[variant]["modes"]["all"]["effects"]
        )
        for variant in DEMO_VARIANTS
    ]
    command = blender_line(
        "bench-effects",
        *("--resolution", width, height, "--repeats", args.repeats),
        *(("--compare-native", args.compare_native) if compared else ()),
        *("--out", "docs/EFFECTS.md"),
    )
    return [
        "# Simulate only the effects a scene calls for: what each part saves",
        "",
        "Generated by the bench-effects verb; do not edit by hand. The baseline is the plain",
        "Whitted tracer: every effect on, a shadow feeler to every light sample, a",
        "reflected or refracted ray wherever its coefficient is not zero and its weight on",
        "the pixel is at least the cutoff, one kernel. Each mechanism is then switched",
        "alone: (a) the scene analysis, which switches off the effects the scene cannot",
        "show (shadows, reflection, refraction, translucency: a scene without a",
        "translucent material sends each feeler as one occlusion query instead of an",
        "occlusion query and a walk through cut-outs); (b) per-surface feeler pruning (no",
        "feeler to a light behind the surface, to a point no light reaches, or when the",
        "whole light's contribution is below the cutoff); (c) the weight cutoff (a",
        "branch whose weight on the pixel is below it is not traced; the plain tracer",
        "has it, so its saving is measured by switching it off); all: the default.",
        "(d) compares the kernels compiled per set of effects (the effects a template",
        "parameter; this build) against the same code reading the effects at run time,",
        "each build's module in its own Blender, in turn: the other build",
        "(`--compare-native`) is this commit built with `-DWHITTED_EFFECT_KERNELS=OFF`;",
        "(d) is this build's time over its. Only renders without passes and with pruning",
        "on get a kernel per set of effects, so the plain mode runs the run-time kernel in",
        "both builds: its (d) column is a control, 1 but for noise.",
        "",
        f"Blender {bpy.app.version_string}, the demo scene's variants at {width}x{height}, "
        f"{AA_SAMPLES}x{AA_SAMPLES} samples per pixel, depth 5, cutoff 1/255. Trace seconds "
        f"from each render's statistics; {args.repeats} repetitions, the modes interleaved "
        "(each repetition starts at the next mode, after a warm-up render). A ratio is taken "
        "within each repetition and shown as median [min..max] over the repetitions; below 1 "
        "is faster.",
        "",
        *machine_lines(),
        "- Load average before and after the run (1, 5, 15 min): "
        f"{load_text(load_before)} / {load_text(load_after)}",
        "",
        "## Time ratios per mechanism",
        "",
        "Trace seconds (wall clock, from the render's statistics):",
        "",
        *attribution(repetitions, "trace_seconds"),
        "",
        "CPU seconds the Blender process spent during the render (all its threads; less",
        "sensitive to what else runs on the machine than the wall clock):",
        "",
        *attribution(repetitions, "cpu_seconds"),
        "",
        "What the code keeps, and why:",
        "",
        *(f"- {name}: {verdict}." for name, verdict in VERDICTS.items()),
        "",
        "## Rays per mode",
        "",
        *table(header, rays_rows, "ll" + "r" * (len(header) - 2)),
        "",
        "The analysis's decisions in the default mode:",
        "",
        *decisions,
        "",
        "## The images against the plain tracer",
        "",
        "The analysis only switches off what cannot show: its image is the plain one bit",
        "for bit. A feeler skipped below the cutoff leaves out less than the cutoff, a",
        "branch not traced less than the cutoff times what it would have returned; a",
        "pixel can lose several, so the difference is compared with the cutoff times the",
        "brightest pixel of the plain render.",
        "",
        *table(
            [
                "scene",
                "mode",
                "max abs difference",
                "mean abs difference",
                "cutoff x brightest pixel",
                "feelers skipped (behind surface / no light / below cutoff)",
                "branches below cutoff",
            ],
            differences,
            "llrrrlr",
        ),
        "",
        f"Command: `{command}`",
    ]


def main(argv):
    args = parse_args(argv)
    if args.child:
        run_child(args)
        return
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as folder:
        repetitions = run_repetitions(args, folder)
    lines = page(args, repetitions, load_before, os.getloadavg())
    print("\n".join(lines))
    if args.out:
        write_page(args.out, lines)
