"""Every render pass Whitted writes: its picture, definition and errors: docs/PASSES.md.

Writes docs/PASSES.md: every render pass Whitted writes, with an image of the demo
scene's and its definition, the recombination errors, the two compositing examples
and what the passes cost.

    .venv/bin/python -m whitted_tools passes-page [--out docs/PASSES.md] [--blender blender]

It runs Blender 3.4 on whitted_tools passes-render (the renders and the compositor
trees), reads the multilayer EXRs with the OpenEXR bindings, writes the pass images
into docs/images/passes/, and puts on the page the cost figures that
whitted_tools bench-passes wrote there (docs/images/passes/cost-blender-X.Y.json, one per
Blender that ran it).
"""

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np
import OpenEXR
from PIL import Image

from whitted_tools import REPO
from whitted_tools.blender import run_process, verb_in_blender
from whitted_tools.pages import machine_lines, table, write_page
from whitted_tools.verbs import prog, python_line

COMMAND = python_line("passes-page")

LIGHT = ("Diff", "Gloss", "Trans")
CONTRIBUTION_DEPTH = 3  # passes_render.py's

# Each pass: its definition on the page, and how its image is drawn ("color": sRGB
# of the linear values; "signed": 0.5 + 0.5 * v; "scaled": v over its largest finite
# value; "index": v / the largest index).
PASSES = (
    (
        "Combined",
        "color",
        "The image: RGBA, alpha the coverage (Blender's **Alpha** "
        "output of the Render Layers node is this A).",
    ),
    (
        "Depth",
        "scaled",
        "Distance from the camera along its view axis to the data "
        "surface (below); 10^10 where the camera ray meets none, as Cycles.",
    ),
    (
        "Mist",
        "scaled",
        "1 - the sum over the surfaces the camera ray meets of (1 - m) * "
        "coverage, m = clamp((d - start) / depth, 0, 1)^falloff, d the distance from the "
        "camera (World > Mist Pass: start, depth, falloff quadratic 2, linear 1, inverse "
        "quadratic 0.5); 1 where the ray escapes.",
    ),
    ("Position", "scaled", "World-space position of the data surface."),
    (
        "Normal",
        "signed",
        "World-space shading normal of the data surface, turned to face "
        "the camera (as Cycles), averaged over the pixel's samples.",
    ),
    ("UV", "color", "(u, v, 0) of UV map 0 at the data surface, averaged over the samples."),
    (
        "IndexOB",
        "index",
        "The object's Pass Index (Object Properties > Relations; here the demo's objects "
        "numbered 1, 2, ... by name).",
    ),
    (
        "IndexMA",
        "index",
        "The material's Pass Index (Material Properties > Settings; here numbered by name).",
    ),
    (
        "DiffDir",
        "color",
        "sum over lights of kd/pi * E * (n.l) * shadow transmittance at "
        "the camera hit, divided by DiffCol.",
    ),
    ("DiffInd", "color", "The ambient term Ia * ka * kd at the camera hit, divided by DiffCol."),
    ("DiffCol", "color", "kd of the camera hit."),
    (
        "GlossDir",
        "color",
        "The Phong highlights ks (f+2)/(2pi) (v.r)^f * E * (n.l) * shadow "
        "transmittance at the camera hit, divided by GlossCol.",
    ),
    (
        "GlossInd",
        "color",
        "sigma_r * L(reflected ray) at the camera hit, divided by GlossCol: "
        "everything the mirror ray brings back, to any depth.",
    ),
    ("GlossCol", "color", "ks + sigma_r of the camera hit (sigma_r after Fresnel)."),
    (
        "TransDir",
        "color",
        "Always 0: Whitted lights reach a surface only through shadow "
        "feelers, which are diffuse and glossy direct light.",
    ),
    ("TransInd", "color", "sigma_t * L(refracted ray) at the camera hit, divided by TransCol."),
    ("TransCol", "color", "sigma_t of the camera hit (after Fresnel)."),
    (
        "VolumeDir",
        "color",
        "The light the media along the camera ray (fog, smoke, a world's volume) scatter "
        "once towards it from the lamps, emitters and world, through their feelers, as "
        "Cycles' Volume Direct; what mirror and refracted rays meet in media is in GlossInd "
        "and TransInd. Black here: the demo has no media.",
    ),
    (
        "VolumeInd",
        "color",
        "Always 0: light scattered more than once is not simulated (Volume Bounces 0; "
        "Cycles' Volume Indirect is black then too).",
    ),
    (
        "Emit",
        "color",
        "Emission of the surfaces and the media the camera ray meets (a volume's, as Cycles).",
    ),
    (
        "Env",
        "color",
        "The world where the camera ray escapes (kept with a transparent "
        "film, as Cycles, where Combined leaves it out).",
    ),
    (
        "Shadow Catcher",
        "color",
        "Cycles' Shadow Catcher pass (switched by Cycles' view-layer property, in Blender "
        "3.x and 5.x alike): per channel, the light on the shadow catchers the camera ray "
        "meets with every object over that with the catchers alone (each light sample's "
        "feeler answered twice), summed over the pixel's samples; 1 where the pixel meets "
        "no catcher or a channel gets no light; then over white by the pixel's alpha with "
        "the catchers in it, as Cycles. With it on, Combined leaves the catchers out "
        "(black, alpha 0, over an opaque film too), as Cycles' does. White here: the demo "
        "has no catcher. A denoised render denoises it too, as Cycles: its normal as the "
        "guide, with a constant albedo of 0.5 where the guides include albedo.",
    ),
    (
        "Noisy Image",
        "color",
        "Combined before denoising (Render > Sampling > Denoise); Combined itself where "
        "the render is not denoised.",
    ),
    (
        "Noisy Shadow Catcher",
        "color",
        "The Shadow Catcher pass before denoising, written with the Denoising Data passes "
        "when the Shadow Catcher pass is on, as Cycles; the pass itself where the render "
        "is not denoised. White here: the demo has no catcher.",
    ),
    (
        "Denoising Normal",
        "signed",
        "The denoiser's normal guide, as Cycles': the shading normal (world space) of the "
        "first surface along the camera path that is not near-specular; a mirror or clear "
        "glass passes the path on, glass's reflection and refraction each adding their "
        "share of sigma_r + sigma_t (0 where a path escapes).",
    ),
    (
        "Denoising Albedo",
        "color",
        "The denoiser's albedo guide, as Cycles': at the first surface along the camera path "
        "whose rough lobes (diffuse, Phong, glossy rougher than GGX alpha 0.075) carry over "
        "a quarter of its weight, their colours plus its emission, clamped to [0, 1]; "
        "through a mirror, clear glass or a sharp coat, that of what is seen in it times "
        "the sigma_r or sigma_t of each branch followed (the world, clamped, where a branch "
        "escapes).",
    ),
    (
        "Whitted Rays",
        "scaled",
        "Rays traced for the pixel: camera, shadow, reflection, refraction and transparent, "
        "and in media the feelers from their scatter points (as shadow rays) and the rays "
        "through their bounds.",
    ),
    (
        "Whitted Cut Weight",
        "scaled",
        "The share of the pixel's ray tree not traced: the sum "
        "over the reflected and refracted rays stopped by the maximum depth or the cutoff of "
        "their weight on the pixel (mean over RGB). 0: nothing cut; at most 1.",
    ),
    (
        "Debug Sample Count",
        "scaled",
        "Camera samples the pixel took (Cycles' pass of that name; the count itself): "
        "the anti-aliasing grid, the points Whitted's adaptive anti-aliasing traced, or, "
        "with noise-driven sampling, the samples taken before the pixel stopped.",
    ),
    *(
        (
            f"Whitted Depth {d}",
            "color",
            f"What the nodes of the ray tree at depth {d} add: "
            "emission and local term of the surfaces its rays meet, the world where they "
            "escape" + (" (depth 0: the camera hit)." if d == 0 else "."),
        )
        for d in range(CONTRIBUTION_DEPTH)
    ),
    (
        f"Whitted Depth {CONTRIBUTION_DEPTH}+",
        "color",
        f"The same for depth {CONTRIBUTION_DEPTH}"
        " and beyond: the Whitted Depth passes sum to Combined.",
    ),
)


def read_exr(path):
    """{pass name: float64[h, w, channels]} of a multilayer EXR, rows top to bottom."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = {
            n: c.pixels.astype(np.float64) for part in exr.parts for n, c in part.channels.items()
        }
    passes = {}
    for name in sorted(channels):
        layer, _, channel = name.rpartition(".")
        passes.setdefault(layer.partition(".")[2], []).append((channel, channels[name]))
    order = "RGBXYZUVAW"
    return {
        name: np.stack([p for _, p in sorted(c, key=lambda t: order.find(t[0][0]))], axis=-1)
        for name, c in passes.items()
    }


def read_rgb(path):
    """float64[h, w, 3] of a single-layer EXR (R, G, B), rows top to bottom."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = exr.parts[0].channels
        return np.stack([channels[c].pixels.astype(np.float64) for c in "RGB"], axis=-1)


def srgb(linear):
    linear = np.clip(linear, 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)


def picture(values, style):
    v = values[..., :3] if values.shape[-1] >= 3 else np.repeat(values[..., :1], 3, axis=-1)
    if style == "color":
        v = srgb(v)
    elif style == "signed":
        v = 0.5 + 0.5 * v
    else:
        finite = v[v < 1e9]
        top = finite.max() if finite.size and finite.max() > 0 else 1.0
        v = np.where(v < 1e9, v / top, 1.0)
    return Image.fromarray((np.clip(v, 0, 1) * 255 + 0.5).astype(np.uint8))


def recombined(p):
    total = p["Emit"][..., :3] + p["Env"][..., :3] + p["VolumeDir"] + p["VolumeInd"]
    for c in LIGHT:
        total = total + p[f"{c}Col"] * (p[f"{c}Dir"] + p[f"{c}Ind"])
    return total


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "PASSES.md")
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args(argv)
    images = args.out.parent / "images" / "passes"
    images.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        command = verb_in_blender("passes-render", "--out", work, blender=args.blender)
        output, problem = run_process(command, 900)
        if problem:
            sys.exit(f"passes_page: {problem}")
        blender_version = next(
            (line for line in output.splitlines() if line.startswith("Blender ")), "Blender"
        )
        passes = read_exr(work / "passes.exr")
        rebuilt_node = read_rgb(work / "rebuild.exr")
        tinted = read_rgb(work / "tint.exr")
    combined = passes["Combined"][..., :3]
    error_light = float(np.abs(recombined(passes) - combined).max())
    depths = sum(passes[f"Whitted Depth {d}"] for d in range(CONTRIBUTION_DEPTH))
    depths = depths + passes[f"Whitted Depth {CONTRIBUTION_DEPTH}+"]
    error_depth = float(np.abs(depths - combined).max())
    error_node = float(np.abs(rebuilt_node[..., :3] - combined).max())
    for name, style, _ in PASSES:
        picture(passes[name], style).save(images / f"{name.replace(' ', '_')}.png")
    picture(rebuilt_node, "color").save(images / "composite_rebuild.png")
    picture(tinted, "color").save(images / "composite_tint.png")

    costs = [json.loads(path.read_text()) for path in sorted(images.glob("cost-blender-*.json"))]
    builds = images / "builds.json"
    costs_of_builds = json.loads(builds.read_text()) if builds.exists() else None
    print(
        f"passes_page: max |recombined - Combined| {error_light:.2e}, depth passes summed "
        f"{error_depth:.2e}, compositor rebuild {error_node:.2e}"
    )
    write_page(
        args.out,
        page(passes, error_light, error_depth, error_node, costs, costs_of_builds, blender_version),
    )


def page(passes, error_light, error_depth, error_node, costs, builds, blender_version):
    h, w = passes["Combined"].shape[:2]
    lines = [
        "# Render passes",
        "",
        f"Generated by `{COMMAND}` ({blender_version}; the demo scene, "
        f"{w}x{h}, 2x2 samples, contribution depth {CONTRIBUTION_DEPTH}). Do not edit by hand.",
        "",
        "Whitted writes the passes enabled in View Layer Properties > Passes (its Data, "
        "Light and Whitted sub-panels, which offer only these) into the render result: the "
        "compositor's Render Layers node shows them and a multilayer OpenEXR holds them "
        "under these names (Cycles' names; Blender 4.0 and later use Cycles' long names, "
        "Diffuse Direct for DiffDir and so on: `LONG_NAMES` in `addon/result.py`). The "
        "table of passes is `addon/result.py`; the kernel fills a per-sample record only "
        "when some pass is enabled (`native/src/integrator/passes.h`): renders without "
        "passes run kernels compiled without the pass recorder. Cryptomatte is written "
        "apart (`addon/cryptomatte.py`).",
        "",
        "**The data surface** is the first surface the camera ray meets whose alpha is at "
        "least the view layer's Alpha Threshold (0.5 by default; 0: the first surface), as "
        "in Cycles: a cut-out below the threshold is looked through. Depth, Position and the "
        "indices are the pixel's first sample's; Normal and UV the mean over its samples.",
        "",
        "**The light passes** split the camera hit's Whitted step, "
        "`Le + Ia ka kd + sum_i delta_i (kd/pi + ks (f+2)/(2pi) (v.r)^f) E_i (n.l) + "
        "sigma_r L_r + sigma_t L_t`, into Blender's components: direct diffuse and "
        "glossy from the lights, the ambient term as indirect diffuse, the mirror ray as "
        "indirect glossy, the refracted ray as indirect transmission. Everything deeper in "
        "the ray tree is inside `L_r` and `L_t`, so it folds into the camera hit's "
        "indirect glossy and transmission. Each term is weighted by the hit's share of the "
        "sample (behind cut-outs, the coverage of the layers in front) and summed over the "
        "pixel's samples; Color holds the same weighted sum of kd, ks + sigma_r and sigma_t. "
        "As in Cycles, Direct and Indirect are then divided by their Color (where it is "
        "not 0) when the Color pass is enabled too, so that Blender's recombination gives "
        "back Combined:",
        "",
        "    Combined = DiffCol (DiffDir + DiffInd) + GlossCol (GlossDir + GlossInd)",
        "             + TransCol (TransDir + TransInd) + VolumeDir + VolumeInd + Emit + Env",
        "",
        f"Measured on the render below (every pixel, RGB): **max |recombined - Combined| = "
        f"{error_light:.2e}**; the Whitted Depth passes summed: **{error_depth:.2e}**.",
        "",
        "## The passes",
        "",
        "| pass | image | definition |",
        "|---|---|---|",
    ]
    for name, _, definition in PASSES:
        image = f"images/passes/{name.replace(' ', '_')}.png"
        lines.append(f"| {name} | ![{name}]({image}) | {definition} |")
    lines += [
        "",
        "## Compositing examples",
        "",
        "Both node trees are built by `python -m whitted_tools passes-render` and rendered "
        "by Blender's compositor from the passes above.",
        "",
        "**Combined rebuilt from the light passes**: for each of Diffuse, Glossy and "
        "Transmission a Mix (Add) of Direct and Indirect into a Mix (Multiply) with Color, "
        "then the three added with VolumeDir, VolumeInd, Emit and Env. Max difference from "
        "Combined: "
        f"**{error_node:.2e}**.",
        "",
        "![rebuilt](images/passes/composite_rebuild.png)",
        "",
        "**Only what the mirror reflects, tinted orange**: G = GlossCol x GlossInd is the "
        "reflected light in Combined; the tree outputs Combined - G + (1, 0.45, 0.1) x G. "
        "The mirror sphere's reflection turns orange (the glass's reflection too, which is "
        "its glossy indirect), the rest of the image is unchanged.",
        "",
        "![tinted](images/passes/composite_tint.png)",
        "",
        "## What passes cost",
        "",
        *cost_lines(costs),
        "",
        *builds_lines(builds),
        "",
        "Machine when this page was written:",
        "",
        *machine_lines(),
    ]
    return lines


VARIANT_LABELS = {
    "none": "no extra pass",
    "depth": "Depth alone",
    "data": "the Data passes",
    "light": "the Light passes",
    "whitted": "the Whitted passes (per-depth, Cut Weight)",
    "all": "every pass",
}


def cost_lines(costs):
    """The table of each bench_passes.py run found beside the images."""
    if not costs:
        return [
            "Not measured yet: run `python -m whitted_tools bench-passes` (its docstring says how)."
        ]
    first = costs[0]
    lines = [
        f"`{first['commands'][0]}` (and `{first['commands'][1]}`): the demo scene at "
        f"{first['resolution'][0]}x{first['resolution'][1]}, {first['aa_samples']}x"
        f"{first['aa_samples']} samples, the variants in turns ({first['repeats']} renders "
        "each), trace time from each render's statistics and the CPU seconds of the whole "
        "render (every thread; export and write-back too, medians). Without passes a render "
        "runs the kernels compiled without a pass recorder; any pass switches it to those with "
        "one, "
        "whose recorder fills only what the enabled groups of passes read.",
        "",
    ]
    header = ["variant", "passes written"]
    rows = []
    for name, label in VARIANT_LABELS.items():
        row = [label, str(first["passes_written"][name])]
        for cost in costs:
            row += [
                f"{cost['median'][name]:.3f}",
                f"{cost['median_over_none'][name]:.2f}x",
                f"{cost['best_over_none'][name]:.2f}x",
                f"{cost['cpu_median_over_none'][name]:.2f}x",
            ]
        rows.append(row)
    for cost in costs:
        header += [
            f"median trace (s), {cost['blender']}",
            "/ no pass",
            "best / best no pass",
            "render CPU / no pass",
        ]
    lines += table(header, rows)
    for cost in costs:
        lines += ["", f"Blender {cost['blender']}'s run:", "", *cost["machine"]]
    lines += [
        "",
        "The machine is shared (2 cores, other jobs running): figures from a loaded machine "
        "are noisy; the ratios, taken in turns in one run, are what to read.",
    ]
    return lines


def builds_lines(builds):
    """No pass enabled against the build before passes existed (`python -m
    whitted_tools.builds ... --json images/passes/builds.json`)."""
    if builds is None:
        return [
            "Against the build before passes: not measured yet (python -m whitted_tools.builds)."
        ]
    old, new = builds["builds"]["old"], builds["builds"]["new"]
    same = old["rays"] == new["rays"] and old["image_mean"] == new["image_mean"]
    return [
        "**No pass enabled, against the build before passes existed**: "
        f"`{builds['command']}` traces one scene (64 spheres on a floor, constant "
        "materials, 480x270, 3x3 samples, 2 threads, no pass) with each build's module "
        f"in turns, {builds['rounds']} rounds of a process per build that keeps the best "
        f"of 3 renders. Old: {old['label']}; new: {new['label']}.",
        "",
        *table(
            ["build", "best trace (s)", "median trace (s)", "rays", "image mean"],
            [
                [
                    b["label"],
                    f"{b['best']:.3f}",
                    f"{b['median']:.3f}",
                    b["rays"],
                    f"{b['image_mean']:.6f}",
                ]
                for b in (old, new)
            ],
            align="lrrrr",
        ),
        "",
        f"New / old: best trace {builds['best_ratio']:.3f}, the rounds' paired ratios "
        f"{builds['paired_text']} (median [min..max]) of the trace and "
        f"{builds['paired_cpu_text']} of the CPU seconds (every thread); "
        + ("the same rays and image." if same else "**the rays or the image differ**."),
        "",
        *builds["machine"],
    ]
