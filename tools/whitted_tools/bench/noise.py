"""Time to a clean image, Whitted against Cycles: docs/NOISE.md (issue 46).

    .venv/bin/python -m whitted_tools bench-noise --out docs          (bpy 5.x module)

Runs in the bpy module (Blender 3.4 from Debian has no Open Image Denoise in Cycles).
For each scene of the distributed ray tracing gallery (gallery-effects: glossy metal,
plastic and glass, emissive meshes, depth of field, motion blur), at --resolution:

- the reference: Cycles with REFERENCE_SAMPLES samples a pixel, limited to what Whitted
  traces (direct light and specular bounces: cycles_scenes.set_cycles_reference), no
  noise threshold, not denoised;
- Cycles at its new scene's settings (noise threshold 0.01, up to 4096 samples, the
  automatic minimum, Open Image Denoise on), and its threshold ladder without denoising;
- Whitted at each preset (noise thresholds), denoised and not, and its own converged
  image (the Reference preset without its noise threshold: every pixel takes its 32 x 32
  grid, 1,024 samples, not denoised; with the threshold it keeps noise of its own; Seed
  1, so its draws are not those of the renders it measures).

Each render's error is its RMSE against the Cycles reference as a display shows both
(linear RGB clipped to [0, 1], sRGB-encoded, in levels of 255: metrics.srgb_encode, the
Estimate's measure; a few emitter edges of linear value 6 would otherwise carry most of
a linear RMSE, which the page gives too), and its noise the same RMSE against its own
engine's converged image (Cycles': the reference; Whitted's: CONVERGED). Both engines
filter pixels as a new scene does (Film > Pixel Filter: Blackman-Harris, 1.5 px).
Where the two engines' converged images differ (their bias: how Whitted's shading
differs from Cycles', docs/DISTRIBUTED.md), no number of samples closes that part of the
error; the noise is what sampling and denoising decide. Time: the wall-clock time of
bpy.ops.render.render (what an artist waits for), the median of --repeats renders taken
in turns, engine after engine, in one process. The page gives, per scene, the time,
error and noise of each render, and the ratio of Whitted's Final (denoised) time to
Cycles' default time, with whether its noise is no larger than the Cycles default's
error.
"""

import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import bpy
import numpy as np

# isort: split
from whitted_tools import cycles_scenes
from whitted_tools.blender import factory_scene
from whitted_tools.cli import page_parser
from whitted_tools.gallery.effects import SCENES
from whitted_tools.metrics import srgb_encode
from whitted_tools.pages import command_line, machine_lines, num, table, write_page
from whitted_tools.render import render_exr

REFERENCE_SAMPLES = 2048
# Whitted's converged image: the Reference preset at threshold 0 (its whole grid).
# Seed 1: draws of its own, so that the measured renders' noise (seed 0, a new scene's)
# is not measured against their own first samples.
CONVERGED = "the Reference preset at threshold 0 (32 x 32 samples a pixel), Seed 1"
# Cycles' new scene (its Sampling > Render defaults).
CYCLES_DEFAULT = {"threshold": 0.01, "samples": 4096, "denoise": True}
CYCLES_LADDER = (0.1, 0.05, 0.02, 0.01)
WHITTED_PRESETS = ("DRAFT", "PREVIEW", "FINAL")


def parse_args(argv):
    parser = page_parser(__name__, __doc__, repeats=3)
    parser.add_argument("--resolution", type=int, nargs=2, default=(320, 240))
    parser.add_argument("--scenes", nargs="*", help="scene names (default: all)")
    return parser.parse_args(argv)


def set_cycles(scene, threshold, samples, denoise):
    """Cycles as the reference's light paths, with a noise threshold (0: none)."""
    cycles_scenes.set_cycles_reference(scene, samples, specular_bounces=8)
    cycles = scene.cycles
    cycles.use_adaptive_sampling = threshold > 0.0
    cycles.adaptive_threshold = threshold
    cycles.adaptive_min_samples = 0  # automatic
    cycles.use_denoising = denoise
    cycles.denoiser = "OPENIMAGEDENOISE"
    cycles.light_sampling_threshold = 0.0


def set_whitted(scene, preset_key, denoise, prefilter="ACCURATE"):
    from whitted.properties.presets import apply_quality, preset

    apply_quality(scene.whitted, preset(preset_key))
    scene.whitted.use_denoising = denoise
    scene.whitted.denoising_prefilter = prefilter


def rmse(image, reference):
    """The display RMSE in levels of 255."""
    a, b = srgb_encode(image[..., :3]), srgb_encode(reference[..., :3])
    return 255.0 * float(np.sqrt(np.mean((a - b) ** 2)))


def linear_rmse(image, reference):
    return float(np.sqrt(np.mean((image[..., :3] - reference[..., :3]) ** 2)))


def timed(scene, engine, path):
    started = time.perf_counter()
    image = render_exr(scene, path, engine=engine)
    return image, time.perf_counter() - started


def runs():
    """(label, engine, setter) of every measured render."""
    out = [
        (
            "Cycles default (0.01, denoised)",
            "CYCLES",
            lambda s: set_cycles(s, **CYCLES_DEFAULT),
        )
    ]
    out += [
        (f"Cycles {t}", "CYCLES", lambda s, t=t: set_cycles(s, t, 4096, False))
        for t in CYCLES_LADDER
    ]
    for key in WHITTED_PRESETS:
        out.append((f"Whitted {key.title()}", "WHITTED", lambda s, k=key: set_whitted(s, k, False)))
        out.append(
            (
                f"Whitted {key.title()} denoised",
                "WHITTED",
                lambda s, k=key: set_whitted(s, k, True),
            )
        )
    out.append(
        (
            "Whitted Final denoised, fast prefilter",
            "WHITTED",
            lambda s: set_whitted(s, "FINAL", True, "FAST"),
        )
    )
    return out


def measure_scene(entry, resolution, repeats):
    name, build, *_ = entry
    with tempfile.TemporaryDirectory() as work:
        scene = factory_scene("whitted", "cycles")
        build(scene)
        # A new scene's film in both engines: Blackman-Harris 1.5 px (the tools' scenes
        # start with Whitted's Box, SEED_QUALITY).
        scene.whitted.property_unset("pixel_filter_type")
        scene.whitted.property_unset("filter_width")
        scene.render.resolution_x, scene.render.resolution_y = resolution
        scene.render.resolution_percentage = 100
        scene.render.film_transparent = True
        scene.view_settings.view_transform = "Standard"
        set_cycles(scene, 0.0, REFERENCE_SAMPLES, False)
        reference, reference_seconds = timed(scene, "CYCLES", os.path.join(work, "ref.exr"))
        set_whitted(scene, "REFERENCE", False)
        scene.whitted.noise_threshold = 0.0
        scene.whitted.seed = 1
        converged, converged_seconds = timed(scene, "WHITTED", os.path.join(work, "own.exr"))
        scene.whitted.seed = 0
        own = {"CYCLES": reference, "WHITTED": converged}
        measured = runs()
        seconds = {label: [] for label, _, _ in measured}
        errors = {}
        linear = {}
        noise = {}
        for _ in range(repeats):
            for label, engine, setter in measured:
                setter(scene)
                image, elapsed = timed(scene, engine, os.path.join(work, "run.exr"))
                seconds[label].append(elapsed)
                errors[label] = rmse(image, reference)
                linear[label] = linear_rmse(image, reference)
                noise[label] = rmse(image, own[engine])
    rows = [
        {
            "label": label,
            "seconds": statistics.median(seconds[label]),
            "rmse": errors[label],
            "linear_rmse": linear[label],
            "noise": noise[label],
        }
        for label, _, _ in measured
    ]
    print(f"bench_noise: {name}: " + ", ".join(f"{r['label']} {r['seconds']:.2f} s" for r in rows))
    return {
        "scene": name,
        "reference_seconds": reference_seconds,
        "converged_seconds": converged_seconds,
        "bias": rmse(converged, reference),
        "mean": float(np.mean(reference[..., :3])),
        "rows": rows,
    }


def verdict(result):
    """Whitted's Final (denoised) against Cycles' default: the time ratio, and whether
    its noise is no larger than Cycles' error."""
    rows = {r["label"]: r for r in result["rows"]}
    whitted = rows["Whitted Final denoised"]
    cycles = rows["Cycles default (0.01, denoised)"]
    return whitted["seconds"] / cycles["seconds"], whitted["noise"] <= cycles["rmse"]


def write_markdown(out, results, command, resolution, repeats):
    lines = [
        "# Time to a clean image: Whitted against Cycles",
        "",
        f"Generated by `{command}`; do not edit. Issue 46's benchmark: each scene of the "
        "distributed ray tracing gallery (docs/DISTRIBUTED.md) at "
        f"{resolution[0]}x{resolution[1]}, against a reference rendered by Cycles with "
        f"{REFERENCE_SAMPLES} samples a pixel limited to the light paths Whitted traces "
        "(direct light, specular bounces); both engines filter pixels as a new scene does "
        "(Blackman-Harris, 1.5 px). Error: RMSE against the reference as a display "
        "shows both (clipped to [0, 1], sRGB, in levels of 255; the linear RMSE, which a few "
        "bright emitter edges dominate, beside it); time: the wall-clock time of the render "
        "call, median of "
        f"{repeats} renders taken in turns in one process (bpy "
        f"{bpy.app.version_string}). Noise: RMSE against the engine's own converged image "
        f"(Whitted's: {CONVERGED}, so its draws are not the measured renders'); bias: "
        "Whitted's converged image against the "
        "reference, the part of the error no sampling removes. The target: Whitted's "
        "Final preset, denoised, no noisier than Cycles' default (noise threshold 0.01, "
        "denoised) in at most a third of its time.",
        "",
        *machine_lines(),
        "",
        "## Summary",
        "",
    ]
    summary = []
    for result in results:
        ratio, as_clean = verdict(result)
        summary.append(
            [
                result["scene"],
                num(ratio, 2),
                "yes" if as_clean else "no",
                num(result["bias"], 2),
                num(result["mean"], 3),
            ]
        )
    lines += table(
        [
            "scene",
            "time, Whitted Final denoised / Cycles default",
            "noise no larger",
            "bias (/255: Whitted converged vs reference)",
            "mean of the reference",
        ],
        summary,
    )
    for result in results:
        lines += [
            "",
            f"## {result['scene']}",
            "",
            f"Reference (Cycles, {REFERENCE_SAMPLES} samples): "
            f"{num(result['reference_seconds'], 2)} s; Whitted converged ({CONVERGED}): "
            f"{num(result['converged_seconds'], 2)} s.",
            "",
        ]
        lines += table(
            ["render", "seconds", "error (/255)", "noise (/255)", "linear RMSE"],
            [
                [
                    r["label"],
                    num(r["seconds"], 3),
                    num(r["rmse"], 2),
                    num(r["noise"], 2),
                    num(r["linear_rmse"], 4),
                ]
                for r in result["rows"]
            ],
        )
    write_page(Path(out) / "NOISE.md", lines)


def main(argv):
    args = parse_args(argv)
    selected = [e for e in SCENES if not args.scenes or e[0] in args.scenes]
    results = [measure_scene(e, tuple(args.resolution), args.repeats) for e in selected]
    version = ".".join(str(v) for v in bpy.app.version[:2])
    data = Path(args.out) / "data"
    data.mkdir(parents=True, exist_ok=True)
    (data / f"noise-blender-{version}.json").write_text(json.dumps(results, indent=2))
    write_markdown(
        args.out,
        results,
        command_line("bench-noise", argv),
        args.resolution,
        args.repeats,
    )
