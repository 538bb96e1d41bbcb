"""What accuracy costs in time: Whitted's quality controls on a .blend: docs/ACCURACY_COST.md.

For each .blend file: renders a reference with the Reference preset, then each
quality control on its own (the others at the Final preset, the baseline) and
the four presets, in one headless Blender process per file (so the times are
measured in the same run; each is the median of --repeats renders' total time
from the engine's statistics). Against the reference it computes, on linear RGB,

    RMSE = sqrt(mean((a - b)^2)),  PSNR = 10 log10(1 / MSE) dB,
    relMSE = mean((a - b)^2 / (b^2 + 0.01))          (pbrt's imgtool)

and writes one Markdown page (a table per control, the command line) with PNG
plots: error against time per control, all runs with their Pareto front, and
a heat map of the reference's per-pixel ray count (the "Whitted Rays" pass).

    .venv/bin/python -m whitted_tools accuracy-cost FILE.blend [FILE.blend ...] \\
        [--out docs/ACCURACY_COST.md] [--resolution 240 180] [--repeats 3] \\
        [--blender blender] [--notes NOTES.md ...]

--notes inserts Markdown files (a hand-written reading, say) after the intro.
"""

import argparse
import importlib.util
import json
import math
import statistics
import sys
import tempfile
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
import OpenEXR

from whitted_tools import REPO
from whitted_tools.blender import run_process, verb_in_blender
from whitted_tools.metrics import error_figures
from whitted_tools.pages import command_line, write_page
from whitted_tools.plots import plt, save
from whitted_tools.verbs import prog


def _load_presets():
    # The add-on's preset table; presets.py needs no bpy, but the add-on package
    # does, so load the file alone.
    spec = importlib.util.spec_from_file_location(
        "whitted_presets", REPO / "addon" / "properties" / "presets.py"
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


presets = _load_presets()
PRESETS, preset = presets.PRESETS, presets.preset

BASELINE = "FINAL"
REFERENCE = "REFERENCE"

# (key, title, [(label, overrides of the baseline)]): each control on its own. The
# override "use_denoising" is the scene's Denoise switch, not a Quality field (Run).
SWEEPS = (
    ("max_depth", "Max depth", [(str(d), {"max_depth": d}) for d in (0, 1, 2, 3, 4, 6, 8, 12, 16)]),
    (
        "noise_threshold",
        "Noise threshold (each pixel stops once its noise is below it, up to the grid)",
        [(f"{t:g}", {"noise_threshold": t}) for t in (0.1, 0.05, 0.02, 0.01, 0.005, 0.002)],
    ),
    (
        "denoise",
        "Denoising (Open Image Denoise guided by albedo and normal, after the render)",
        [("off", {}), ("on", {"use_denoising": True})],
    ),
    (
        "aa_grid",
        "Anti-aliasing without a noise threshold: regular and jittered grids (camera "
        "samples per axis, each at its own point of the pixel, the lens and the shutter)",
        [
            (f"regular {n}", {"aa_mode": "REGULAR", "aa_samples": n, "adaptive_sampling": False})
            for n in (1, 2, 3, 4, 6)
        ]
        + [
            (f"jittered {n}", {"aa_mode": "JITTERED", "aa_samples": n, "adaptive_sampling": False})
            for n in (2, 4, 6, 8)
        ],
    ),
    (
        "aa_threshold",
        "Adaptive anti-aliasing (Whitted's corners, without a noise threshold): threshold "
        "(depth 2)",
        [
            (
                f"{t:g}",
                {
                    "aa_mode": "ADAPTIVE",
                    "aa_threshold": t,
                    "aa_depth": 2,
                    "adaptive_sampling": False,
                },
            )
            for t in (1.0, 0.3, 0.1, 0.03)
        ],
    ),
    (
        "aa_depth",
        "Adaptive anti-aliasing (Whitted's corners, without a noise threshold): depth "
        "(threshold 0.1)",
        [
            (
                str(d),
                {
                    "aa_mode": "ADAPTIVE",
                    "aa_threshold": 0.1,
                    "aa_depth": d,
                    "adaptive_sampling": False,
                },
            )
            for d in (0, 1, 2, 3)
        ],
    ),
    (
        "light_samples",
        "Soft-shadow samples per axis (sized lights)",
        [(str(n), {"light_samples": n}) for n in (1, 2, 3, 4, 6)],
    ),
    (
        "glossy_samples",
        "Glossy rays per axis (rough reflections)",
        [(str(n), {"glossy_samples": n}) for n in (1, 2, 3, 4, 6)],
    ),
    (
        "emitter_samples",
        "Emitter feelers per axis (emissive meshes and the world light)",
        [(str(n), {"emitter_samples": n}) for n in (1, 2, 3, 4, 6)],
    ),
    ("fresnel", "Fresnel", [(f, {"fresnel": f}) for f in ("OFF", "SCHLICK", "EXACT")]),
    (
        "cutoff",
        "Adaptive depth cutoff (ray weight)",
        [(f"{c:.4g}", {"cutoff": c}) for c in (0.1, 0.03, 0.01, 1 / 255, 0.001, 0.0001)],
    ),
    (
        "texture_filter",
        "Texture filtering",
        [(f, {"texture_filter": f}) for f in ("AUTHORED", "CLOSEST")],
    ),
    (
        "volume_step_rate",
        "Volume step rate (heterogeneous media are marched in steps of their voxel, or a "
        "tenth of their object, times this)",
        [(f"{r:g}", {"volume_step_rate": r}) for r in (4.0, 2.0, 1.0, 0.5, 0.25)],
    ),
)


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("blend", nargs="+", type=Path)
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "ACCURACY_COST.md")
    parser.add_argument("--resolution", nargs=2, type=int, default=(240, 180), metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--notes", nargs="*", type=Path, default=[])
    return parser.parse_args(argv)


@dataclass(frozen=True)
class Run:
    """What one render is made with: a Quality and the scene's Denoise switch."""

    quality: object  # presets.Quality
    use_denoising: bool = False


def run_of(quality, use_denoising=False, **overrides):
    return Run(replace(quality, **overrides), use_denoising)


def quality_key(run):
    """A file-name-safe name for a Run."""
    values = asdict(run.quality)
    name = "-".join(f"{v:g}" if isinstance(v, float) else str(v) for v in values.values())
    return name + ("-denoised" if run.use_denoising else "")


def plan_runs():
    """(reference Run, [(sweep key, label, Run)]), presets as the sweep 'presets'."""
    baseline = preset(BASELINE)
    runs = [
        (key, label, run_of(baseline, **overrides))
        for key, _, values in SWEEPS
        for label, overrides in values
    ]
    runs += [("presets", label, Run(values)) for _, label, _, values in PRESETS]
    return Run(preset(REFERENCE)), runs


def render_all(blender, blend, qualities, resolution, repeats, workdir):
    """Render each distinct Run once (with repeats); name -> (stats list, exr path)."""
    unique = {quality_key(q): q for q in qualities}
    runs_file = workdir / "runs.json"
    runs_file.write_text(
        json.dumps(
            [
                {"name": name, "quality": asdict(q.quality), "use_denoising": q.use_denoising}
                for name, q in unique.items()
            ]
        )
    )
    command = verb_in_blender(
        "cost-render",
        *("--runs", runs_file, "--out", workdir, "--resolution", *resolution),
        *("--repeats", repeats),
        blend=blend,
        blender=blender,
    )
    # No time limit: one Blender renders the whole sweep of a file.
    _, problem = run_process(command, timeout=None)
    if problem:
        sys.exit(f"accuracy_cost: Blender on {blend}: {problem}")
    return {
        name: (json.loads((workdir / f"{name}.json").read_text()), workdir / f"{name}.exr")
        for name in unique
    }


def read_exr(path):
    """(linear RGB float64[H,W,3], rays per pixel float64[H,W]) of a multilayer EXR."""
    channels = OpenEXR.File(str(path), separate_channels=True).parts[0].channels

    def channel(suffix):
        name = next(n for n in channels if n.endswith(suffix))
        return channels[name].pixels.astype(np.float64)

    rgb = np.stack([channel(f".Combined.{c}") for c in "RGB"], axis=-1)
    return rgb, channel("Whitted Rays.X")


def measure(rendered, reference_name, runs):
    """One row per run: its numbers against the reference."""
    reference_image, _ = read_exr(rendered[reference_name][1])
    rows = []
    for sweep, label, quality in runs:
        stats_list, exr = rendered[quality_key(quality)]
        image, _ = read_exr(exr)
        last = stats_list[-1]
        rows.append(
            {
                "sweep": sweep,
                "label": label,
                "quality": quality.quality,
                "use_denoising": quality.use_denoising,
                "seconds": statistics.median(s["phases"]["total"] for s in stats_list),
                "rays": last["rays"]["total"],
                "rays_per_pixel": last["rays"]["total"] / last["pixels"],
                "samples_per_pixel": last["samples_per_pixel"],
                "is_baseline": quality == Run(preset(BASELINE)),
                "is_reference": quality_key(quality) == reference_name,
                **error_figures(image, reference_image),
            }
        )
    return rows


def pareto_front(rows):
    """Rows no other row beats in both time and relMSE, by increasing time."""
    front = []
    for row in sorted(rows, key=lambda r: (r["seconds"], r["relmse"])):
        if not front or row["relmse"] < front[-1]["relmse"]:
            front.append(row)
    return front


def _plot_error(axis, rows, **style):
    # relMSE 0 (the reference itself) cannot sit on a log axis: left out.
    shown = [r for r in rows if r["relmse"] > 0.0]
    axis.plot([r["seconds"] for r in shown], [r["relmse"] for r in shown], **style)
    return shown


def plot_sweeps(rows, path, title):
    count = len(SWEEPS) + 1
    columns = 3
    figure, axes = plt.subplots(
        math.ceil(count / columns), columns, figsize=(13, 3.4 * math.ceil(count / columns))
    )
    axes = axes.ravel()
    for axis, (key, sweep_title) in zip(
        axes, [(k, t) for k, t, _ in SWEEPS] + [("presets", "Presets")], strict=False
    ):
        sweep_rows = [r for r in rows if r["sweep"] == key]
        shown = _plot_error(axis, sweep_rows, marker="o", linestyle="-")
        for row in shown:
            axis.annotate(row["label"], (row["seconds"], row["relmse"]), fontsize=7)
        axis.set_title(sweep_title, fontsize=9)
        axis.set_yscale("log")
        axis.set_xlabel("time (s)", fontsize=8)
        axis.set_ylabel("relMSE", fontsize=8)
        axis.tick_params(labelsize=7)
    for axis in axes[count:]:
        axis.axis("off")
    figure.suptitle(f"{title}: error against time, one control at a time (others at Final)")
    save(figure, path)


def plot_pareto(rows, path, title):
    figure, axis = plt.subplots(figsize=(8, 5))
    for key, sweep_title, _ in SWEEPS:
        _plot_error(
            axis,
            [r for r in rows if r["sweep"] == key],
            marker="o",
            linestyle="",
            alpha=0.6,
            label=sweep_title,
        )
    presets = _plot_error(
        axis,
        [r for r in rows if r["sweep"] == "presets"],
        marker="*",
        markersize=14,
        linestyle="",
        color="black",
        label="presets",
    )
    for row in presets:
        axis.annotate(row["label"], (row["seconds"], row["relmse"]), fontsize=9)
    _plot_error(axis, pareto_front(rows), drawstyle="steps-post", color="red", label="Pareto front")
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_xlabel("render time (s)")
    axis.set_ylabel("relMSE against the reference")
    axis.set_title(f"{title}: every run, and the Pareto front")
    axis.legend(fontsize=7)
    save(figure, path)


def plot_cost(rays, path, title):
    figure, axis = plt.subplots(figsize=(7, 5))
    # EXR rows run top to bottom, as the image is seen.
    image = axis.imshow(rays, cmap="inferno", interpolation="nearest")
    figure.colorbar(image, ax=axis, label="rays per pixel")
    axis.set_title(f"{title}: rays per pixel, Reference preset")
    axis.axis("off")
    save(figure, path)


def _number(value, digits):
    return "inf" if math.isinf(value) else f"{value:.{digits}f}"


def scene_section(blend, rows, rendered, reference_name, image_dir, page_dir):
    stem = blend.stem
    _, rays = read_exr(rendered[reference_name][1])
    images = {
        "cost": image_dir / f"{stem}-cost.png",
        "pareto": image_dir / f"{stem}-pareto.png",
        "sweeps": image_dir / f"{stem}-sweeps.png",
    }
    plot_cost(rays, images["cost"], stem)
    plot_pareto(rows, images["pareto"], stem)
    plot_sweeps(rows, images["sweeps"], stem)
    reference_stats = rendered[reference_name][0][-1]
    lines = [
        f"## {stem}",
        "",
        f"Reference: the Reference preset, {reference_stats['phases']['total']:.2f} s, "
        f"{reference_stats['rays']['total']:,} rays "
        f"({reference_stats['rays']['total'] / reference_stats['pixels']:.0f} per pixel, "
        f"at most {rays.max():.0f}), {reference_stats['triangles']:,} triangles, "
        f"{reference_stats['lights']} lights, {reference_stats['threads']} threads, "
        f"Blender {reference_stats['blender']}.",
        "",
    ]
    for name, path in images.items():
        lines += [f"![{stem}: {name}]({path.relative_to(page_dir).as_posix()})", ""]
    for key, title in [(k, t) for k, t, _ in SWEEPS] + [("presets", "Presets")]:
        lines += [
            f"### {stem}: {title}",
            "",
            "| setting | time (s) | rays | rays/px | samples/px | RMSE | PSNR (dB) | relMSE |",
            "|---|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for row in (r for r in rows if r["sweep"] == key):
            note = " (reference)" if row["is_reference"] else ""
            note += " (baseline)" if row["is_baseline"] and key != "presets" else ""
            lines.append(
                f"| {row['label']}{note} | {row['seconds']:.3f} | {row['rays']:,} | "
                f"{row['rays_per_pixel']:.1f} | {row['samples_per_pixel']:.2f} | "
                f"{row['rmse']:.5f} | {_number(row['psnr'], 2)} | {row['relmse']:.2e} |"
            )
        lines.append("")
    return lines


def presets_table():
    fields = list(asdict(preset(BASELINE)))
    lines = [
        "| preset | " + " | ".join(fields) + " |",
        "|---|" + "---|" * len(fields),
    ]
    for _, label, _, values in PRESETS:
        cells = [f"{v:.4g}" if isinstance(v, float) else str(v) for v in asdict(values).values()]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines


def main(argv):
    args = parse_args(argv)
    page_dir = args.out.resolve().parent
    image_dir = page_dir / "images" / "accuracy_cost"
    image_dir.mkdir(parents=True, exist_ok=True)
    reference, runs = plan_runs()
    reference_name = quality_key(reference)
    command = command_line("accuracy-cost", argv)
    lines = [
        "# What accuracy costs in time",
        "",
        "Generated by the accuracy-cost verb; do not edit by hand (the reading and the "
        "estimate's accuracy come from the --notes files). Command:",
        "",
        f"    {command}",
        "",
        f"Each control is swept on its own with the others at the {BASELINE.title()} "
        f"preset; errors are against the {REFERENCE.title()} preset, on linear RGB "
        f"({args.resolution[0]}x{args.resolution[1]} pixels). Times are the median of "
        f"{args.repeats} renders in one Blender process (the engine's total: export, "
        "BVH, trace and write-back). relMSE = mean((a-b)^2/(b^2+0.01)); PSNR takes "
        "1.0 as the peak.",
        "",
        "The presets (addon/properties/presets.py):",
        "",
        *presets_table(),
        "",
    ]
    for note in args.notes:
        lines += [note.read_text().rstrip(), ""]
    for blend in args.blend:
        with tempfile.TemporaryDirectory(prefix="whitted-cost-") as tmp:
            qualities = [reference] + [q for _, _, q in runs]
            rendered = render_all(
                args.blender, blend.resolve(), qualities, args.resolution, args.repeats, Path(tmp)
            )
            rows = measure(rendered, reference_name, runs)
            lines += scene_section(blend, rows, rendered, reference_name, image_dir, page_dir)
        print(f"accuracy_cost: {blend}: {len(rows)} runs", flush=True)
    write_page(args.out, lines)
