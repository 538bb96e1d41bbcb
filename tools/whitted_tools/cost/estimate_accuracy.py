"""How good is the Estimate button: predicted against actual time and error (in Blender).

Run inside Blender (3.4 binary or the bpy 5.0 module); for each .blend it makes the
Estimate button's prediction (estimate_presets, a probe of each preset:
addon/estimate.py), then renders every preset at the full resolution and compares the
engine's total time (the median of up to --repeats renders, made one of each preset
in turn, fewer once MAX_RENDER_SECONDS have been spent on a preset), its fixed costs
and its tracing, and the display error against the Reference render
(addon/estimate_model.py's display_error, on the whole frame) with the predictions:

    blender -b --factory-startup --python tools/whitted_tools/__main__.py -- estimate-accuracy \\
        FILE.blend [FILE.blend ...] [--resolution 320 240] [--repeats 3] \\
        [--out docs/notes/estimate_accuracy.md]

Writes a Markdown page (a table, the time, rays and error figures; docs/ACCURACY_COST.md
links to it) and prints it. --standard-scenes DIR builds the seven scenes of
docs/notes/estimate_accuracy.md into DIR first (STANDARD_SCENES: whitted_tools.
bench_scenes' demo, glass, diffuse, camera (depth of field and motion blur), glass8,
1,000 instances and 300,000 triangles, as whitted_tools perf-scenes and
whitted_tools cost-scenes save them) and measures them after any FILE.blend given;
--third-party NAME ... adds the material gallery's scenes of real models
(whitted_tools.materials_page.THIRD_PARTY), which nothing was tuned on.
That page was made with

    blender -b --factory-startup --python tools/whitted_tools/__main__.py -- estimate-accuracy \
        --standard-scenes /tmp/estimate-scenes --resolution 240 180 --repeats 5 \
        --out docs/notes/estimate_accuracy.md
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass

import bpy

from whitted_tools import bench_scenes
from whitted_tools.blender import enable_addon, factory_scene
from whitted_tools.material_scenes import frame_subject, import_file
from whitted_tools.materials_page import THIRD_PARTY, THIRD_PARTY_MODELS
from whitted_tools.pages import command_line, write_page
from whitted_tools.render import render_exr
from whitted_tools.verbs import prog

# Renders of one preset stop repeating once they have taken this long in all.
MAX_RENDER_SECONDS = 20.0


# The scenes of --standard-scenes: (name, builder, the builder's arguments, max depth;
# None: the cost report's scenes, which keep the presets' own settings).
STANDARD_SCENES = (
    ("demo", bench_scenes.build_demo, {}, bench_scenes.DEFAULT_MAX_DEPTH),
    ("glass", bench_scenes.build_glass_scene, None, None),
    ("diffuse", bench_scenes.build_diffuse_scene, None, None),
    ("camera", bench_scenes.build_camera_scene, None, None),
    ("glass8", bench_scenes.build_glass8, {}, bench_scenes.GLASS8_MAX_DEPTH),
    (
        "instances",
        bench_scenes.build_instances,
        {"instances": 1000, "ico_subdivisions": 3},
        bench_scenes.DEFAULT_MAX_DEPTH,
    ),
    (
        "triangles",
        bench_scenes.build_triangles,
        {"triangles": 300_000},
        bench_scenes.DEFAULT_MAX_DEPTH,
    ),
)
# The size the standard scenes are built for (the instances' grid is laid out for it);
# they are measured at --resolution.
BUILD_RESOLUTION = (320, 240)


def build_standard_scenes(directory):
    """Save the STANDARD_SCENES into `directory`; their paths."""
    os.makedirs(directory, exist_ok=True)
    paths = []
    for name, build, arguments, depth in STANDARD_SCENES:
        if arguments is None:
            scene = build(factory_scene())
            scene.render.engine = "WHITTED"
            scene.view_settings.view_transform = "Standard"
        else:
            options = {"triangles": None, "instances": None, "ico_subdivisions": None}
            options.update(arguments, resolution=BUILD_RESOLUTION)
            scene = build(factory_scene("whitted", "cycles"), argparse.Namespace(**options))
            bench_scenes.configure(scene, BUILD_RESOLUTION, depth)
        paths.append(os.path.join(os.path.abspath(directory), f"{name}.blend"))
        bpy.ops.wm.save_as_mainfile(filepath=paths[-1])
    return paths


def build_third_party_scenes(directory, names):
    """Save the material gallery's third-party scenes `names` (materials_page.THIRD_PARTY:
    real models by other people, framed under the gallery's sun) into `directory`, at
    Whitted's default settings; their paths. Scenes the presets were not tuned on."""
    entries = {entry["scene"]: entry for entry in THIRD_PARTY}
    os.makedirs(directory, exist_ok=True)
    paths = []
    for name in names:
        scene = factory_scene()
        import_file(THIRD_PARTY_MODELS / entries[name]["file"])
        frame_subject(scene)
        scene.render.engine = "WHITTED"
        scene.view_settings.view_transform = "Standard"
        paths.append(os.path.join(os.path.abspath(directory), f"{name}.blend"))
        bpy.ops.wm.save_as_mainfile(filepath=paths[-1])
    return paths


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("blend", nargs="*")
    parser.add_argument("--standard-scenes", metavar="DIR", help="build and measure those too")
    parser.add_argument(
        "--third-party",
        nargs="+",
        default=[],
        choices=[entry["scene"] for entry in THIRD_PARTY],
        help="build these gallery scenes into the --standard-scenes DIR and measure them too",
    )
    parser.add_argument("--resolution", nargs=2, type=int, default=(320, 240), metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3, help="renders of each preset at most")
    parser.add_argument("--out", help="Markdown file to write")
    return parser.parse_args(argv), argv


def render_image(scene, path):
    """Render the scene to an EXR at `path`; (the engine's phases in seconds, rays per
    pixel, float[H, W, 4])."""
    pixels = render_exr(scene, path)
    stats = json.loads(scene.whitted.last_stats)
    return stats["phases"], stats["rays"]["total"] / stats["pixels"], pixels


@dataclass(frozen=True)
class Row:
    label: str  # the preset's
    predicted: float  # seconds, the whole render
    actual: float  # seconds, the engine's total (median of the renders)
    predicted_fixed: float  # export, BVHs and scene compile
    actual_fixed: float  # (median)
    predicted_trace: float  # thread start-up and tracing
    actual_trace: float  # (median)
    predicted_error: float  # display RMSE against Reference, 8-bit levels
    actual_error: float
    predicted_rays: float  # rays per pixel
    actual_rays: float


def measure(path, resolution, repeats, workdir):
    """(probe description, Estimate seconds, [Row per preset]) for one .blend. Calls
    what the Estimate operator calls (estimate.estimate_presets), to see its parts."""
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path))
    enable_addon()
    from whitted.estimate import REFERENCE, estimate_presets
    from whitted.estimate_model import display_error
    from whitted.native import load_native
    from whitted.properties.presets import PRESETS, apply_quality

    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    started = time.perf_counter()
    probe, estimates, _ = estimate_presets(bpy.context.evaluated_depsgraph_get(), load_native())
    estimate_seconds = time.perf_counter() - started
    predicted = {e.preset: e for e in estimates}
    # The renders go round the presets, one of each per round, rather than one preset's
    # renders back to back: the machine's speed drifts over seconds, and a preset's
    # median should not be taken in one moment of it.
    phases = {key: [] for key, _, _, _ in PRESETS}
    actual = {}
    for _ in range(repeats):
        for key, _, _, values in PRESETS:
            if sum(p["total"] for p in phases[key]) >= MAX_RENDER_SECONDS:
                continue
            apply_quality(scene.whitted, values)
            times, rays, image = render_image(scene, os.path.join(workdir, f"{key}.exr"))
            phases[key].append(times)
            actual[key] = (phases[key], image, rays)
    reference = actual[REFERENCE][1]
    rows = []
    for key, label, _, _ in PRESETS:
        estimate, (phases, image, rays) = predicted[key], actual[key]
        rows.append(
            Row(
                label=label,
                predicted=estimate.seconds,
                actual=statistics.median(p["total"] for p in phases),
                predicted_fixed=probe.fixed_seconds,
                actual_fixed=statistics.median(
                    p["export"] + p["mesh_bvh"] + p["scene_bvh"] + p["world_light"] for p in phases
                ),
                predicted_trace=estimate.seconds - probe.fixed_seconds,
                actual_trace=statistics.median(p["trace"] for p in phases),
                predicted_error=estimate.error,
                actual_error=display_error(image, reference),
                predicted_rays=estimate.rays_per_pixel,
                actual_rays=rays,
            )
        )
    return probe.describe(), estimate_seconds, rows


def rank(values):
    """The order of `values` (indices, largest first)."""
    return sorted(range(len(values)), key=lambda i: -values[i])


def main(argv):
    args, argv = parse_args(argv)
    if args.standard_scenes:
        args.blend += build_standard_scenes(args.standard_scenes)
        args.blend += build_third_party_scenes(args.standard_scenes, args.third_party)
    if not args.blend:
        sys.exit("estimate_accuracy: no scenes (give .blend files or --standard-scenes DIR)")
    load = os.getloadavg()[0]
    lines = [
        "## How accurate is the Estimate button",
        "",
        "Predicted (the Estimate button: each preset traces one tile in n^2 of the frame "
        "at full resolution, addon/estimate.py) against actual render time (the engine's "
        f"total, median of up to {args.repeats} renders, made one of each preset in turn) "
        "and error against the Reference render (RMSE as an 8-bit sRGB display shows the "
        "image, in levels of 255: "
        f"addon/estimate_model.py), at {args.resolution[0]}x{args.resolution[1]}, "
        f"Blender {bpy.app.version_string}, {os.cpu_count()} cores. Command:",
        "",
        "    " + command_line("estimate-accuracy", argv),
        "",
        "| scene | preset | predicted (s) | actual (s) | time error | fixed: predicted / "
        "actual (s) | tracing: predicted / actual (s) | predicted rays/px | actual rays/px "
        "| predicted error | actual error |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    time_errors, fixed_errors, trace_errors, error_ratios, ray_errors = [], [], [], [], []
    ranks_right, probes, estimate_seconds = 0, set(), []
    with tempfile.TemporaryDirectory() as workdir:
        for path in args.blend:
            probe, seconds, rows = measure(path, args.resolution, args.repeats, workdir)
            probes.add(probe)
            estimate_seconds.append(seconds)
            for r in rows:
                error = (r.predicted - r.actual) / r.actual
                time_errors.append(abs(error))
                # Each part's miss as a share of the actual total: the two add up to it,
                # less what the prediction leaves out (the write-back, the engine's own).
                fixed_errors.append(abs(r.predicted_fixed - r.actual_fixed) / r.actual)
                trace_errors.append(abs(r.predicted_trace - r.actual_trace) / r.actual)
                ray_errors.append(abs(r.predicted_rays / r.actual_rays - 1.0))
                if r.actual_error > 0.0:
                    error_ratios.append(r.predicted_error / r.actual_error)
                lines.append(
                    f"| {os.path.basename(path)} | {r.label} | {r.predicted:.3f} | "
                    f"{r.actual:.3f} | {100 * error:+.0f}% | {r.predicted_fixed:.3f} / "
                    f"{r.actual_fixed:.3f} | {r.predicted_trace:.3f} / {r.actual_trace:.3f} | "
                    f"{r.predicted_rays:.1f} | {r.actual_rays:.1f} | "
                    f"{r.predicted_error:.2f} | {r.actual_error:.2f} |"
                )
            ranks_right += rank([r.predicted_error for r in rows]) == rank(
                [r.actual_error for r in rows]
            )
    scenes = len(args.blend)
    lines += [
        "",
        f"Time, over {len(time_errors)} renders: mean absolute error "
        f"{100 * statistics.fmean(time_errors):.1f}%, worst {100 * max(time_errors):.0f}%. "
        f"Rays: mean absolute error {100 * statistics.fmean(ray_errors):.1f}%, worst "
        f"{100 * max(ray_errors):.1f}%. Where the time error comes from, as a share of "
        "the actual total (mean absolute): the fixed costs (export, BVHs, scene compile; "
        "the Estimate's median of up to 3 exports) "
        f"{100 * statistics.fmean(fixed_errors):.1f}%, the tracing "
        f"{100 * statistics.fmean(trace_errors):.1f}%.",
        "",
        f"Error: the predicted order of the presets is right on {ranks_right} of {scenes} "
        f"scenes; predicted / actual error over the {len(error_ratios)} presets below "
        f"Reference: median {statistics.median(error_ratios):.2f}, from "
        f"{min(error_ratios):.2f} to {max(error_ratios):.2f}.",
        "",
        f"Probe: {'; '.join(sorted(probes))}. The Estimate button took "
        f"{statistics.fmean(estimate_seconds):.1f} s a scene on average (at most "
        f"{max(estimate_seconds):.1f} s). Load average over 1 minute when the run began: "
        f"{load:.1f} (times vary with the load of the machine).",
    ]
    print("\n".join(lines))
    if args.out:
        write_page(args.out, lines)
