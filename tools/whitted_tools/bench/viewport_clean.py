"""The viewport's time to a clean image after an edit, Whitted against Cycles: writes
docs/VIEWPORT_CLEAN.md.

    .venv/bin/python -m whitted_tools bench-viewport-clean [--out docs/VIEWPORT_CLEAN.md]
        [--scenes rough_gold demo] [--repeats 3] [--region 480 360] [--limit 30]
        [--reference-limit 240] [--quick] [--blender blender]

In one Blender 3.4 window under Xvfb (viewport_clean_window.py beside this file, on
tests/viewport's driver), each engine in turn is edited (an object moves a little) and
what the 3D view shows is captured over time. Outside Blender: each capture's RMSE, in
levels of 255 of the 8-bit image on screen, against its own engine's converged
capture, over the camera frame; the time to the first capture below each target, the
median over the repeats; and the two engines' converged captures against each other.

--quick: a tiny region, one repeat, one scene, short limits (the smoke test).
"""

import argparse
import itertools
import math
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from whitted_tools import REPO
from whitted_tools.blender import (
    blender_command,
    factory_scene,
    run_for_json,
    run_process,
    verb_in_blender,
)
from whitted_tools.pages import command_line, load_text, machine_lines, table, write_page
from whitted_tools.verbs import prog

TARGETS = (4.0, 2.0, 1.0)  # RMSE, levels of 255
# (row, what the page calls it, its reference's row)
ROWS = (
    ("cycles", "Cycles, no denoising", "cycles"),
    ("whitted", "Whitted, no denoising", "whitted"),
    ("whitted_denoised", "Whitted, viewport Denoise", "whitted"),
)
# The object each scene's edit moves.
EDITED = {"rough_gold": "Ball", "demo": "Cube"}
# Pixels cut off each side of the camera frame: the viewport draws a 1 px frame line
# there even with overlays off, and the projected frame is sub-pixel.
FRAME_INSET = 3
# The maximised area's "back to the previous screen" icon, drawn over the image in its
# top-right corner (at most 16 px, 6 px in from the corner, at UI scale 1): left out.
ICON_BOX = 24
QUICK = {"scenes": ["rough_gold"], "repeats": 1, "region": [160, 120], "limit": 3.0}
QUICK_REFERENCE_LIMIT = 6.0
QUICK_BEFORE = 1.0


# --- inside Blender (background): the scene -------------------------------------------


def child_build(args):
    """Save the effects gallery's rough_gold at the region's aspect."""
    import bpy

    from whitted_tools.gallery.effects import scene_rough_gold

    scene = factory_scene()
    scene_rough_gold(scene)
    render = scene.render
    render.resolution_x, render.resolution_y = args.region
    render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    bpy.ops.wm.save_as_mainfile(filepath=args.save)


def build_blend(name, path, region, blender):
    """The scene `name` saved to `path`; None, or why it failed."""
    if name == "demo":
        command = blender_command(
            REPO / "scripts" / "demo_scene.py",
            *("--no-render", "--save", path, "--resolution", *region),
            # demo_scene.py makes the output's folder even with --no-render.
            *("--output", os.path.join(os.path.dirname(path), "unused.png")),
            blender=blender,
        )
    else:
        command = verb_in_blender(
            "bench-viewport-clean",
            "--child-build",
            "--save",
            path,
            "--region",
            *region,
            blender=blender,
        )
    _, problem = run_process(command, 300)
    return problem


# --- the window run ---------------------------------------------------------------------


def run_window(name, blend, workdir, args):
    """The scenario in a window the size of the region: its result, or exits."""
    out = os.path.join(workdir, name)
    result = os.path.join(out, "result.json")
    os.makedirs(out, exist_ok=True)
    width, height = args.region
    runs = args.repeats * len(ROWS)
    timeout = 120 + runs * (args.limit + args.before + 10) + 2 * (args.reference_limit + 20)
    command = [
        *("xvfb-run", "-a", "-s", f"-screen 0 {width}x{height}x24"),
        *("env", f"WHITTED_VIEWPORT_LOG={os.path.join(out, 'viewport.jsonl')}"),
        *(args.blender, "--factory-startup", blend),
        *("--python", str(Path(__file__).with_name("viewport_clean_window.py")), "--"),
        *("--result", result, "--out", out, "--timeout", str(timeout - 30)),
        *("--edited", EDITED[name], "--repeats", str(args.repeats)),
        *("--limit", str(args.limit), "--reference-limit", str(args.reference_limit)),
        *("--before", str(args.before)),
    ]
    measured, problem = run_for_json(command, result, timeout)
    if problem:
        raise SystemExit(f"bench-viewport-clean: {name}: {problem}")
    if not measured["ok"]:
        raise SystemExit(f"bench-viewport-clean: {name}: {measured['error']}")
    return measured["data"]


# --- outside Blender: the figures ------------------------------------------------------


def load_frame(path, frame):
    """The capture's camera frame (less FRAME_INSET a side) as float64 RGB, 0..255, the
    corner icon's box NaN."""
    from PIL import Image  # not in Blender's Python, where only child_build runs

    left, top, right, bottom = frame
    with Image.open(path) as image:
        pixels = np.asarray(image.convert("RGB"), dtype=np.float64).copy()
    pixels[:ICON_BOX, -ICON_BOX:] = np.nan
    return pixels[
        math.ceil(top) + FRAME_INSET : math.floor(bottom) - FRAME_INSET,
        math.ceil(left) + FRAME_INSET : math.floor(right) - FRAME_INSET,
    ]


def rmse(a, b):
    """RMSE over the pixels both images have (not NaN)."""
    return float(np.sqrt(np.nanmean((a - b) ** 2)))


def clean_times(errors, targets=TARGETS):
    """Per target, the time of the first (t, rmse) below it, or None."""
    return {target: next((t for t, e in errors if e < target), None) for target in targets}


def last_change(captures):
    """The time of the last capture that differs from the one before it (0: none)."""
    return max(
        (b["t"] for a, b in itertools.pairwise(captures) if b["hash"] != a["hash"]),
        default=0.0,
    )


def run_figures(run, reference, frame):
    """One edit's curve against `reference`: its (t, rmse), clean times, last error."""
    errors = [(c["t"], rmse(load_frame(c["path"], frame), reference)) for c in run["captures"]]
    return {
        "errors": errors,
        "clean": clean_times(errors),
        "last": errors[-1][1],
        "last_change": last_change(run["captures"]),
        "settled": run["settled"],
        "capture_ms": 1000.0 * statistics.mean(c["seconds"] for c in run["captures"]),
    }


def half_way(run):
    """The path of the capture nearest half the time of the run's last: for a sampler
    whose error falls as 1/sqrt(samples) its difference from the last is about the
    last's own remaining error (twice the samples halve the variance)."""
    half = run["captures"][-1]["t"] / 2.0
    return min(run["captures"], key=lambda c: abs(c["t"] - half))["path"]


def scene_figures(data):
    frame = data["camera_frame"]
    runs = {run["name"]: run for run in data["runs"]}
    references = {
        row: load_frame(runs[f"{row}-reference"]["captures"][-1]["path"], frame)
        for row in ("cycles", "whitted")
    }
    rows = {}
    for row, _, reference in ROWS:
        rows[row] = [
            run_figures(run, references[reference], frame)
            for name, run in runs.items()
            if name.rsplit("-", 1)[0] == row and not name.endswith("-reference")
        ]
    return {
        "rows": rows,
        "references": {
            row: {
                "settled": runs[f"{row}-reference"]["settled"],
                "seconds": runs[f"{row}-reference"]["seconds"],
                "half": rmse(load_frame(half_way(runs[f"{row}-reference"]), frame), image),
            }
            for row, image in references.items()
        },
        "cross": rmse(references["cycles"], references["whitted"]),
    }


def median_time(values, limit):
    """The median of the clean times (a missing one counts as later than any), as text."""
    ordered = sorted(math.inf if v is None else v for v in values)
    middle = statistics.median(ordered)
    return f"> {limit:g}" if math.isinf(middle) else f"{middle:.2f}"


# --- the page ---------------------------------------------------------------------------


def scene_lines(name, data, figures, args):
    settings = data["settings"]
    references = figures["references"]
    lines = [f"## {name}", ""]
    header = [
        "row",
        *(f"to {t:g} levels, s" for t in TARGETS),
        "last RMSE",
        "last change, s",
        "capture, ms",
    ]
    body = []
    for row, label, _ in ROWS:
        runs = figures["rows"][row]
        settled = sum(r["settled"] for r in runs)
        body.append(
            [
                label,
                *(median_time([r["clean"][t] for r in runs], args.limit) for t in TARGETS),
                f"{statistics.median(r['last'] for r in runs):.2f}",
                f"{statistics.median(r['last_change'] for r in runs):.1f}"
                + (f" (done {settled}/{len(runs)})" if row.startswith("whitted") else ""),
                f"{statistics.median(r['capture_ms'] for r in runs):.0f}",
            ]
        )
    lines += table(header, body)
    lines += [
        "",
        "Every repeat's times to 4, 2 and 1 levels (s; - not reached): "
        + "; ".join(
            f"{label}: "
            + ", ".join(
                "/".join("-" if r["clean"][t] is None else f"{r['clean'][t]:.2f}" for t in TARGETS)
                for r in figures["rows"][row]
            )
            for row, label, _ in ROWS
        ),
        "",
        f"References (the last capture): Cycles at {settings['cycles_preview_samples']} "
        "viewport samples without adaptive sampling, "
        f"{_reference_text(references['cycles'])}; Whitted's Reference "
        f"preset, {_reference_text(references['whitted'])}. "
        f"**Cycles' reference against Whitted's: RMSE {figures['cross']:.2f} levels** "
        "(the difference no sampling removes, plus what the references' own noise adds).",
        "",
    ]
    return lines


def _reference_text(reference):
    state = "done" if reference["settled"] else "still refining when stopped"
    return (
        f"{state} after {reference['seconds']:.0f} s (its capture at half that time differs "
        f"from it by {reference['half']:.2f} levels)"
    )


def write(args, measured, seconds):
    any_data = next(iter(measured.values()))[0]
    settings = any_data["settings"]
    width, height = any_data["region"]
    lines = [
        "# The viewport: time to a clean image after an edit, Whitted against Cycles",
        "",
        f"Generated by `{command_line('bench-viewport-clean', args.argv)}` in "
        f"{seconds / 60:.1f} min; do not edit by hand.",
        "",
        *machine_lines(),
        "",
        f"One Blender 3.4 window (Debian's) under Xvfb, Mesa's software OpenGL: a "
        f"{width}x{height} 3D view in camera view, Rendered, without overlays or gizmos. "
        "For each repeat, each row in turn: the row's engine renders the scene for "
        f"{args.before:g} s, then an object moves 0.1 along x (the edit) and the view is "
        "captured (screen.screenshot_area: what the window last drew, after the view "
        "transform) every 0.1 s at first, then every tenth of the time since the edit, at "
        f"most 1 s apart, until Whitted is done, or {args.limit:g} s (Cycles' runs always: "
        "Blender 3.4's Python cannot read its viewport's sample count, and its display "
        "updates came up to 5 s apart). Error: the RMSE of "
        "the 8-bit capture over the camera frame (3 px in from its edge; the "
        f"maximised area's icon in its top-right {ICON_BOX} px square left out), in levels "
        "of 255, against the same engine's converged capture of the same edit. Times are "
        f"seconds from the edit, medians of {args.repeats} repeats (a repeat that never "
        "gets there counts as later than any).",
        "",
        f"Cycles: its viewport defaults ({settings['cycles_preview_samples']} samples, "
        f"adaptive sampling {'on' if settings['cycles_preview_adaptive'] else 'off'} at "
        f"threshold {settings['cycles_preview_adaptive_threshold']:g}, "
        f"{settings['cycles_pixel_filter'][0].replace('_', '-').title()} filter "
        f"{settings['cycles_pixel_filter'][1]:g} px) with the light paths Whitted traces "
        "(no diffuse or volume bounce, 8 glossy, transmission and transparent bounces, no "
        "caustics), CPU, no denoising (Debian's Cycles 3.4 has no Open Image Denoise). "
        f"Whitted: a new scene's viewport preset ({settings['whitted_viewport_preset'].title()}"
        f"), {settings['whitted_pixel_filter'][0].replace('_', '-').title()} filter "
        f"{settings['whitted_pixel_filter'][1]:g} px; the last row with its viewport "
        "Denoise on (compared with the same undenoised reference). *last change*: the "
        "time of the last capture that differed from the one before (Whitted: *done*, in "
        "how many repeats its viewport log said it converged, and denoised, and drew it, "
        "within the limit). Cycles' reference is done when its capture stays the same for "
        "30 s. *capture*: the time one screenshot took in Blender's main thread. "
        "Whitted's viewport workers run at nice 10 (addon/viewport/session.py "
        "WORKER_NICE), Cycles' at Blender's own priority: on a machine other work loads, "
        f"that favours Cycles. Load average when the run started: {args.load_at_start}.",
        "",
        "Why screenshots: in Blender 3.4 a POST_PIXEL draw handler "
        "(SpaceView3D.draw_handler_add) reading gpu.state.active_framebuffer_get()."
        "read_color() reads the overlay framebuffer (transparent, with only the camera "
        "frame's outline), not the rendered image; and numpy views of the gpu.types.Buffer "
        "it returns gave scrambled pixels (its to_list() took 0.45 s for 528x372).",
        "",
    ]
    for name, (data, figures) in measured.items():
        lines += scene_lines(name, data, figures, args)
    write_page(args.out, lines)


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(REPO / "docs" / "VIEWPORT_CLEAN.md"))
    parser.add_argument(
        "--scenes", nargs="+", choices=sorted(EDITED), default=["rough_gold", "demo"]
    )
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--region", nargs=2, type=int, default=[480, 360], metavar=("W", "H"))
    parser.add_argument("--limit", type=float, default=30.0, help="seconds per edit")
    parser.add_argument("--reference-limit", type=float, default=240.0)
    parser.add_argument("--before", type=float, default=2.0, help=argparse.SUPPRESS)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--keep", help="keep the scenes, captures and logs in this folder")
    parser.add_argument("--child-build", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--save", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    args.argv = argv
    if args.quick:
        for key, value in QUICK.items():
            setattr(args, key, value)
        args.reference_limit = QUICK_REFERENCE_LIMIT
        args.before = QUICK_BEFORE
    return args


def main(argv):
    args = parse_args(argv)
    if args.child_build:
        child_build(args)
        return
    started = time.perf_counter()
    args.load_at_start = load_text()
    measured = {}
    with tempfile.TemporaryDirectory(prefix="whitted-viewport-clean-") as temporary:
        workdir = args.keep or temporary
        os.makedirs(workdir, exist_ok=True)
        for name in args.scenes:
            blend = os.path.join(workdir, f"{name}.blend")
            problem = build_blend(name, blend, args.region, args.blender)
            if problem:
                raise SystemExit(f"bench-viewport-clean: building {name}: {problem}")
            data = run_window(name, blend, workdir, args)
            measured[name] = (data, scene_figures(data))
    write(args, measured, time.perf_counter() - started)
