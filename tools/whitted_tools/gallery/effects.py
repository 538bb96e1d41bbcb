"""Distributed ray tracing by Whitted beside Cycles (in Blender): docs/DISTRIBUTED.md.

The distributed ray tracing gallery: what Whitted simulates beyond the 1980 set
(glossy reflection, frosted glass, emissive meshes as lights, depth of field, motion
blur) beside Cycles, with the time of each render against the same scene with the
effect off.

    blender -b --factory-startup --python-exit-code 1 \
        --python tools/whitted_tools/__main__.py -- gallery-effects --out docs
    .venv-5.2/bin/python -m whitted_tools gallery-effects --out docs      (bpy 5.2 module)

Each run renders with the Blender that runs it and writes, for that Blender,
OUT/images/effects/blender-X.Y/<scene>.png (Whitted left, Cycles right) and
results.json; then it rewrites OUT/DISTRIBUTED.md from every Blender's results.

Measures, on the linear renders (transparent film): SSIM of the two images and the
median luminance ratio Whitted / Cycles over the subject's pixels (as the material
gallery: whitted_tools gallery-materials); and the engine's own total time (export, BVH,
trace, write-back: the render statistics) of the effect on and off, alternating, the
median of --repeats renders each, in one Blender process.
"""

import json
import os
import statistics
import tempfile
from dataclasses import dataclass
from pathlib import Path

import bpy

# isort: split
from whitted_tools import cycles_scenes
from whitted_tools.blender import factory_scene
from whitted_tools.camera_scenes import balls_in_a_row, cube_crossing
from whitted_tools.cli import page_parser
from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    emission_material,
    glass_bsdf_material,
    grey_world,
    lambert_material,
    panel_room,
    principled_sphere_material,
    smooth_sphere,
)
from whitted_tools.metrics import subject_figures
from whitted_tools.pages import command_line, machine_lines, num, relative_link, table, write_page
from whitted_tools.render import render_exr, save_side_by_side
from whitted_tools.verbs import blender_line, python_line

CYCLES_SAMPLES = 512


# --- the scenes: each builds itself and says how to turn its effect off ---------------


def sphere_on_floor(scene, material):
    """A sphere of `material` on a grey floor under a sun and a grey sky that lights no
    diffuse surface: what a rough surface reflects or refracts is the floor and sky."""
    grey_world(scene, 0.5)
    add_floor(scene, size=12.0, albedo=0.6)
    smooth_sphere("Ball", (0.0, 0.0, 1.0), 1.0, material, segments=64, rings=32)
    add_camera(scene, (0.0, -4.0, 1.4), (0.0, 0.0, 1.0), lens=60.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=2.0)
    scene.whitted.ambient_strength = 0.0


def glossy(scene, on):
    # Off: the seed's mirror and Phong highlight.
    scene.whitted.local_model = "BLENDER" if on else "LECTURE"


def emitters(scene, on):
    for material in bpy.data.materials:
        settings = material.cycles
        if hasattr(settings, "emission_sampling"):  # 4.0 on
            settings.emission_sampling = "AUTO" if on else "NONE"
        else:
            settings.sample_as_light = on


def depth_of_field(scene, on):
    scene.camera.data.dof.use_dof = on


def motion_blur(scene, on):
    scene.render.use_motion_blur = on


def scene_rough_gold(scene):
    sphere_on_floor(scene, principled_sphere_material("Gold", (1.0, 0.78, 0.34), 0.4, metallic=1.0))


def scene_rough_plastic(scene):
    sphere_on_floor(scene, principled_sphere_material("Plastic", (0.05, 0.05, 0.3), 0.3))


def scene_frosted_glass(scene):
    sphere_on_floor(scene, glass_bsdf_material("Frosted", 0.25))


def scene_panel_light(scene):
    panel_room(scene, lambert_material("Grey", 0.8))


def scene_neon_sign(scene):
    panel = panel_room(scene, lambert_material("Grey", 0.8), cuts=31)
    panel.data.materials.append(emission_material("Dark", 0.0))
    for polygon in panel.data.polygons:
        polygon.material_index = (polygon.index // 32) % 2  # stripes


def scene_metal_under_panel(scene):
    panel_room(scene, principled_sphere_material("Metal", (0.9, 0.9, 0.9), 0.3, metallic=1.0))


# Camera samples per axis where the default 2 x 2 is too few: the lens and the shutter
# are spread over the pixel's samples (the Reference preset's 6 x 6).
CAMERA_SAMPLES = {"depth_of_field": 6, "motion_blur": 6}

# (name, build, the effect's name in the report, what turns it on and off, how off)
SCENES = (
    ("rough_gold", scene_rough_gold, "glossy reflection", glossy, "Local Model: Lecture"),
    ("rough_plastic", scene_rough_plastic, "glossy reflection", glossy, "Local Model: Lecture"),
    ("frosted_glass", scene_frosted_glass, "glossy reflection", glossy, "Local Model: Lecture"),
    (
        "panel_light",
        scene_panel_light,
        "emissive meshes as lights",
        emitters,
        "Emission Sampling: None",
    ),
    (
        "neon_sign",
        scene_neon_sign,
        "emissive meshes as lights",
        emitters,
        "Emission Sampling: None",
    ),
    (
        "metal_under_panel",
        scene_metal_under_panel,
        "emissive meshes as lights",
        emitters,
        "Emission Sampling: None",
    ),
    ("depth_of_field", balls_in_a_row, "depth of field", depth_of_field, "Depth of Field off"),
    ("motion_blur", cube_crossing, "motion blur", motion_blur, "Render > Motion Blur off"),
)


# --- rendering and measures -----------------------------------------------------------


def set_engines(scene):
    render = scene.render
    render.resolution_x, render.resolution_y = 160, 120
    render.resolution_percentage = 100
    render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    cycles_scenes.set_cycles_reference(scene, CYCLES_SAMPLES, specular_bounces=8)
    scene.cycles.light_sampling_threshold = 0.0
    # Whitted at the Final preset's glossy and emitter samples, 2 x 2 camera samples.
    whitted = scene.whitted
    whitted.aa_mode = "REGULAR"
    whitted.aa_samples = 2
    whitted.max_depth = 8
    whitted.glossy_samples = 3
    whitted.emitter_samples = 4


def timed_whitted(scene, path, stats_path):
    """Whitted's render of `scene` and the engine's total time (its statistics)."""
    image = render_exr(scene, path, engine="WHITTED")
    stats = json.loads(Path(stats_path).read_text(encoding="utf-8"))
    return image, stats


def _decision(stats, effect):
    """The report's entry for `effect` in a render's statistics; None for a scene whose
    feature is a material's shading, which the report does not name, or for one the
    report names only where it is used (vertex displacement)."""
    return next((e for e in stats["effects"] if e["name"] == effect), None)


def _says(result):
    """The page's "the report says" cell of a result."""
    if result["decision"] is None:
        return "(not named in the report: a material's shading)"
    return f"{result['effect']} ({result['decision']['why']})"


def render_scene(entry, image_dir, repeats):
    name, build, effect, toggle, how = entry
    with tempfile.TemporaryDirectory() as work:
        stats_path = os.path.join(work, "stats.json")
        os.environ["WHITTED_STATS"] = stats_path
        scene = factory_scene()
        finish = build(scene)
        set_engines(scene)
        if finish is not None:  # what a scene sets that the engines' set-up would undo
            finish(scene)
        if name in CAMERA_SAMPLES:
            scene.whitted.aa_mode = "JITTERED"
            scene.whitted.aa_samples = CAMERA_SAMPLES[name]
        cycles = render_exr(scene, os.path.join(work, "cycles.exr"), engine="CYCLES")
        whitted, stats = timed_whitted(scene, os.path.join(work, "whitted.exr"), stats_path)
        decision = _decision(stats, effect)
        rays = stats["rays"]
        # The subject: what still covers the film with the floor hidden.
        floor = scene.objects["Floor"]
        floor.hide_render = True
        alone = render_exr(scene, os.path.join(work, "subject.exr"), engine="WHITTED")
        floor.hide_render = False
        ssim, ratio = subject_figures(whitted, cycles, alone[..., 3] > 0.99)
        save_side_by_side((whitted, cycles), os.path.join(image_dir, f"{name}.png"))
        # On and off alternating, so a change in the machine's load hits both alike.
        on, off = [], []
        for _ in range(repeats):
            on.append(timed_whitted(scene, os.path.join(work, "on.exr"), stats_path)[1])
            toggle(scene, False)
            off.append(timed_whitted(scene, os.path.join(work, "off.exr"), stats_path)[1])
            toggle(scene, True)
        del os.environ["WHITTED_STATS"]
    off_decision = _decision(off[0], effect)
    result = {
        "scene": name,
        "effect": effect,
        "decision": decision,
        "off_decision": off_decision,
        "turned_off_by": how,
        "ssim": ssim,
        "ratio": ratio,
        "seconds_on": statistics.median(s["phases"]["total"] for s in on),
        "seconds_off": statistics.median(s["phases"]["total"] for s in off),
        "trace_on": statistics.median(s["phases"]["trace"] for s in on),
        "trace_off": statistics.median(s["phases"]["trace"] for s in off),
        "rays_on": rays["total"],
        "glossy_rays": rays["glossy"],
        "shadow_rays": rays["shadow"],
        "rays_off": off[0]["rays"]["total"],
    }
    print(
        f"gallery: {name}: SSIM {ssim:.3f}, ratio {ratio:.3f}, "
        f"{result['seconds_on']:.3f} s on, {result['seconds_off']:.3f} s off"
    )
    return result


# --- the page ------------------------------------------------------------------------


@dataclass(frozen=True)
class Page:
    """One gallery page the harness writes: its verb, file, images' folder under
    OUT/images/, title, and the paragraph that says what it shows."""

    module: str  # the verb's module, whose docstring its --help shows
    doc: str
    verb: str
    file: str
    images: str
    title: str
    intro: str
    scenes: tuple


MEASURES = (
    "**Whitted on the left, Cycles on the right**, over a mid grey where the film is "
    f"transparent. Cycles: {CYCLES_SAMPLES} samples, direct light plus glossy and "
    "transmission bounces (no diffuse bounce, no caustics), no denoising; the sky lights no "
    "diffuse surface. Whitted: 2 x 2 samples per pixel (6 x 6 jittered for depth of field "
    "and motion blur, whose lens and shutter samples are the pixel's), depth 8, the Final "
    "preset's 3 x 3 glossy rays and 4 x 4 emitter feelers. SSIM (sRGB) and the median "
    "luminance ratio Whitted / Cycles over the subject's pixels (the floor left out). "
    "Time: the engine's total (export, BVH, trace, write-back) from its statistics, the "
    "median of the renders with the effect on and off, alternating in one process; the "
    "effect is turned off as the last column says."
)

EFFECTS_PAGE = Page(
    __name__,
    __doc__,
    "gallery-effects",
    "DISTRIBUTED.md",
    "effects",
    "Distributed ray tracing: Whitted beside Cycles",
    "What Whitted traces beyond the 1980 set where a scene calls for it (Cook, Porter and "
    "Carpenter 1984): rays drawn from a rough surface's GGX lobe (glossy reflection, "
    "frosted glass), feelers to emissive meshes, weighed against the glossy rays by "
    "multiple importance sampling, and camera rays spread over the lens (depth of field) "
    "and the shutter (motion blur). Turned off, each effect is named skipped in the "
    "report.",
    SCENES,
)


def write_markdown(out, command, page=EFFECTS_PAGE):
    """OUT/<page.file> from every Blender's results under OUT/images/<page.images>/;
    `command`: the one writing it."""
    out = Path(out)
    root = out / "images" / page.images
    versions = sorted(p for p in root.glob("blender-*") if (p / "results.json").is_file())
    lines = [
        f"# {page.title}",
        "",
        f"Generated by `python -m whitted_tools {page.verb}`; do not edit. {page.intro} {MEASURES}",
        "",
        "Regenerate:",
        "",
        f"    {blender_line(page.verb, '--out', 'docs')}",
        f"    {python_line(page.verb, '--out', 'docs', python='.venv-5.2/bin/python')}",
        "",
        "Last written by:",
        "",
        f"    {command}",
        "",
        *machine_lines(),
    ]
    for version_dir in versions:
        results = json.loads((version_dir / "results.json").read_text(encoding="utf-8"))
        version = version_dir.name.removeprefix("blender-")
        rows = [
            [
                r["scene"],
                num(r["ssim"]),
                num(r["ratio"]),
                num(r["seconds_on"], 3),
                num(r["seconds_off"], 3),
                num(r["seconds_on"] / r["seconds_off"], 2),
                f"{r['rays_on'] / 1e6:.2f} / {r['rays_off'] / 1e6:.2f}",
                _says(r),
                r["turned_off_by"],
            ]
            for r in results
        ]
        lines += [
            "",
            f"## Blender {version}",
            "",
            *table(
                [
                    "scene",
                    "SSIM",
                    "ratio",
                    "s on",
                    "s off",
                    "on / off",
                    "M rays on / off",
                    "the report says",
                    "off by",
                ],
                rows,
                align="lrrrrrrll",
            ),
            "",
        ]
        for r in results:
            image = relative_link(version_dir / f"{r['scene']}.png", out)
            lines += [f"**{r['scene']}** ({version})", "", f"![{r['scene']}]({image})", ""]
    write_page(out / page.file, lines)


def run(argv, page):
    """Render `page`'s scenes with the Blender running this, keep its results, and
    rewrite the page from every Blender's."""
    args = page_parser(page.module, page.doc, repeats=3).parse_args(argv)
    version = ".".join(str(v) for v in bpy.app.version[:2])
    image_dir = os.path.join(args.out, "images", page.images, f"blender-{version}")
    os.makedirs(image_dir, exist_ok=True)
    results = [render_scene(entry, image_dir, args.repeats) for entry in page.scenes]
    with open(os.path.join(image_dir, "results.json"), "w", encoding="utf-8") as file:
        json.dump(results, file, indent=2)
    write_markdown(args.out, command_line(page.verb, argv), page)


def main(argv):
    run(argv, EFFECTS_PAGE)
