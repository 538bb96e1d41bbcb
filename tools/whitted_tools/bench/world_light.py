"""What the world light costs: docs/WORLD_LIGHT.md (issue 47's Proof).

    .venv/bin/python -m whitted_tools bench-world-light --out docs     (bpy 5.x module)

Runs in the bpy module or in Blender 3.4. Two sets of scenes, each lit by its world:

- a diffuse sphere (albedo 0.8) on a grey floor (0.5) under each of Blender's studio
  HDRIs (sunset, forest, interior) and under a Sky Texture (Nishita before 5.0, Single
  Scattering from it; sun 15 degrees up, strength 0.1), at --resolution
  (world_scenes.lit_by: no lamp, the world alone lights them);
- the third-party .blend files of Debian's assimp-testmodels
  (/usr/share/assimp/models/BLEND) whose world lights them as authored (the add-on's
  export.world.world_light says so: a world that lights diffuse surfaces and is not
  black), with their own lamps, cameras and materials, at --file-resolution.

Per scene: Whitted at each preset (Draft, Preview, Final) with the world light and with
it off (the same scene with World > Ray Visibility > Diffuse off: the world still seen,
lighting nothing), the wall-clock time of the render call (median of --repeats), its
trace time and the importance map's build time (the render statistics' phases), the
world feelers drawn; the error of each preset's image, with the world light, against
Whitted's converged image (the Reference preset without its noise threshold, a
--converged-grid square grid of samples a pixel, Seed 1) and against Cycles limited to
direct light (cycles_scenes.set_cycles_direct_light at CYCLES_SAMPLES, a box filter of
one pixel as Whitted's): the display RMSE in levels of 255 (the Estimate's measure,
estimate_model.display_error), and against Cycles the summed luminance ratio and the
SSIM after a 3 x 3 blur (world_scenes.compare). Images: Whitted Final with the world
light, without it, and Cycles, side by side.
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
from whitted_tools.blender import factory_scene
from whitted_tools.cli import page_parser
from whitted_tools.cycles_scenes import set_cycles_direct_light
from whitted_tools.material_scenes import lambert_material, numpy_image
from whitted_tools.pages import command_line, machine_lines, num, relative_link, table, write_page
from whitted_tools.render import render_exr, save_side_by_side
from whitted_tools.world_scenes import (
    HDRIS,
    compare,
    lit_by,
    scattering_model,
    sky_world,
    studio_hdri,
)

MODELS = Path("/usr/share/assimp/models/BLEND")
PRESETS = ("DRAFT", "PREVIEW", "FINAL")
CYCLES_SAMPLES = 512
SKY_ELEVATION = 15.0
IMAGES = "images/world_light"


def parse_args(argv):
    parser = page_parser(__name__, __doc__, repeats=1)
    parser.add_argument("--resolution", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--file-resolution", type=int, nargs=2, default=(96, 72))
    parser.add_argument(
        "--converged-grid", type=int, default=32, help="Whitted's converged image: n x n"
    )
    parser.add_argument("--scenes", nargs="*", help="HDRI and sky scenes (default: all)")
    parser.add_argument("--files", nargs="*", help="third-party .blend names (default: all)")
    return parser.parse_args(argv)


def build_scene(name, resolution):
    """The sphere on a floor under the world `name` (an HDRI or "sky")."""
    scene = factory_scene("whitted", "cycles")
    ball = lambert_material("Ball", 0.8)
    if name == "sky":
        # The sphere's scene, its world then replaced by the sky.
        lit_by(scene, numpy_image("Unused", np.ones((2, 4, 4))), ball, size=resolution)
        sky_world(scene, scattering_model(), SKY_ELEVATION)
    else:
        lit_by(scene, bpy.data.images.load(studio_hdri(name)), ball, size=resolution)
    scene.cycles.samples = CYCLES_SAMPLES
    return scene


def open_file(path, resolution):
    """The third-party file at `path` as authored (its lamps, camera, materials and
    world), both engines filtering pixels with a box of one pixel (Cycles limited to
    direct light, as in lit_by); where this Blender cannot open it, why (a str)."""
    try:
        bpy.ops.wm.open_mainfile(filepath=str(path))
    except RuntimeError as error:
        return str(error).strip().splitlines()[-1]
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    set_cycles_direct_light(scene, samples=CYCLES_SAMPLES)
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.whitted.pixel_filter_type = "BOX"
    return scene


def world_light_of(scene):
    """The add-on's decision for the scene's world: its WorldLightData (on, why)."""
    from whitted.export.world import convert_world

    return convert_world(scene.world, scene.whitted.ambient_strength, []).light


def world_colour(world):
    """The world's colour and strength: its Background node's unlinked Color and
    Strength, or without nodes (a 2.4x file in Blender 3.4) its colour at strength 1;
    None where a node sets the colour."""
    from whitted.export.nodes import uses_nodes

    if world is None:
        return None
    if not uses_nodes(world):
        return (*world.color, 1.0)
    node = world.node_tree.nodes.get("Background")
    if node is None or node.inputs["Color"].is_linked:
        return None
    r, g, b, _ = node.inputs["Color"].default_value
    return (r, g, b, node.inputs["Strength"].default_value)


def set_preset(scene, key, seed=0):
    from whitted.properties.presets import apply_quality, preset

    apply_quality(scene.whitted, preset(key))
    scene.whitted.seed = seed


def whitted_render(scene, path, stats_path):
    """(image, wall-clock seconds, the render's statistics)."""
    started = time.perf_counter()
    image = render_exr(scene, path, engine="WHITTED")
    seconds = time.perf_counter() - started
    return image, seconds, json.loads(Path(stats_path).read_text())


def measure(name, scene, work, repeats, converged_grid, image_dir):
    """Every figure of one scene (module docstring); writes its image to `image_dir`."""
    from whitted.estimate_model import display_error

    stats_path = os.path.join(work, "stats.json")
    os.environ["WHITTED_STATS"] = stats_path
    exr = os.path.join(work, "render.exr")
    light = world_light_of(scene)
    started = time.perf_counter()
    cycles = render_exr(scene, exr, engine="CYCLES")
    cycles_seconds = time.perf_counter() - started
    set_preset(scene, "REFERENCE", seed=1)
    scene.whitted.adaptive_sampling = False
    scene.whitted.aa_samples = converged_grid
    converged, converged_seconds, _ = whitted_render(scene, exr, stats_path)
    visibility = scene.world.cycles_visibility
    rows = []
    shown = {}
    for key in PRESETS:
        row = {"preset": key}
        for lit in (True, False):
            visibility.diffuse = lit
            set_preset(scene, key)
            runs = [whitted_render(scene, exr, stats_path) for _ in range(repeats)]
            image, _, stats = runs[-1]
            suffix = "on" if lit else "off"
            row[f"seconds_{suffix}"] = statistics.median(r[1] for r in runs)
            row[f"trace_{suffix}"] = statistics.median(r[2]["phases"]["trace"] for r in runs)
            row[f"rays_{suffix}"] = stats["rays"]["total"]
            # A noise threshold takes the samples each image needs: the time is theirs too.
            row[f"samples_{suffix}"] = stats["samples_per_pixel"]
            if lit:
                row["map_seconds"] = statistics.median(r[2]["phases"]["world_light"] for r in runs)
                row["world_feelers"] = stats["world_feelers"]
                row["effect"] = next(e for e in stats["effects"] if e["name"] == "world light")
                row["error_converged"] = display_error(image, converged)
                row["error_cycles"] = display_error(image, cycles)
                row["luminance_ratio"], row["ssim"] = compare(cycles, image)
            if key == "FINAL":
                shown[lit] = image
        visibility.diffuse = True
        rows.append(row)
        print(
            f"bench_world_light: {name} {key}: {row['seconds_on']:.2f} s lit, "
            f"{row['seconds_off']:.2f} s unlit, error {row['error_converged']:.2f}"
        )
    save_side_by_side((shown[True], shown[False], cycles), os.path.join(image_dir, f"{name}.png"))
    return {
        "scene": name,
        "world_light": light.why if light.on else f"off: {light.why}",
        "cycles_seconds": cycles_seconds,
        "converged_seconds": converged_seconds,
        "converged_bias": display_error(converged, cycles),
        "converged_ratio": compare(cycles, converged)[0],
        "rows": rows,
    }


def survey_files(names):
    """(name, path) of the third-party files asked for (default: every .blend there)."""
    paths = sorted(MODELS.glob("*.blend"))
    return [(p.name, p) for p in paths if not names or p.name in names]


def measure_files(names, resolution, work, repeats, converged_grid, image_dir):
    """(the files' survey rows, the measured results of those their world lights)."""
    survey = []
    results = []
    for name, path in survey_files(names):
        scene = open_file(path, resolution)
        if isinstance(scene, str):
            survey.append({"file": name, "lit": False, "why": f"not opened: {scene}"})
            continue
        light = world_light_of(scene)
        colour = world_colour(scene.world)
        lamps = sum(1 for o in scene.objects if o.type == "LIGHT")
        survey.append(
            {
                "file": name,
                "lit": light.on,
                "why": light.why,
                "world": colour,
                "lamps": lamps,
                "camera": scene.camera is not None,
            }
        )
        if light.on and scene.camera is not None:
            results.append(measure(name, scene, work, repeats, converged_grid, image_dir))
    return survey, results


def _scene_table(result):
    return table(
        [
            "preset",
            "s, world light",
            "s, off",
            "time ratio",
            "trace s, on / off",
            "samples/px, on / off",
            "map build s",
            "world feelers",
            "error vs converged (/255)",
            "error vs Cycles (/255)",
            "luminance / Cycles",
            "SSIM vs Cycles",
        ],
        [
            [
                r["preset"].title(),
                num(r["seconds_on"], 3),
                num(r["seconds_off"], 3),
                num(r["seconds_on"] / r["seconds_off"], 2),
                f"{num(r['trace_on'], 3)} / {num(r['trace_off'], 3)}",
                f"{num(r['samples_on'], 1)} / {num(r['samples_off'], 1)}",
                num(r["map_seconds"], 4),
                f"{r['world_feelers']:,}",
                num(r["error_converged"], 2),
                num(r["error_cycles"], 2),
                num(r["luminance_ratio"], 4),
                num(r["ssim"], 4),
            ]
            for r in result["rows"]
        ],
    )


def _result_lines(result, out):
    image = relative_link(Path(out) / IMAGES / f"{result['scene']}.png", Path(out))
    return [
        "",
        f"### {result['scene']}",
        "",
        f"World light: {result['world_light']}. Cycles ({CYCLES_SAMPLES} samples, direct "
        f"light): {num(result['cycles_seconds'], 2)} s; Whitted converged: "
        f"{num(result['converged_seconds'], 2)} s, against Cycles "
        f"{num(result['converged_bias'], 2)}/255, luminance "
        f"{num(result['converged_ratio'], 4)}.",
        "",
        *_scene_table(result),
        "",
        f"![{result['scene']}: Whitted Final with the world light, without it, Cycles]({image})",
    ]


def _summary(results):
    rows = []
    for result in results:
        final = next(r for r in result["rows"] if r["preset"] == "FINAL")
        rows.append(
            [
                result["scene"],
                result["world_light"],
                num(final["map_seconds"], 4),
                num(final["seconds_on"] / final["seconds_off"], 2),
                num(final["trace_on"] / final["trace_off"], 2),
                num(final["error_converged"], 2),
                num(final["error_cycles"], 2),
                num(final["luminance_ratio"], 4),
            ]
        )
    return table(
        [
            "scene",
            "world light",
            "map build s",
            "Final time, on / off",
            "Final trace, on / off",
            "Final error vs converged (/255)",
            "Final error vs Cycles (/255)",
            "Final luminance / Cycles",
        ],
        rows,
        align="ll" + "r" * 6,
    )


def _one_colour_build(results):
    """The longest world light build of the renders of `results` lit by a world of one
    colour (0 for none)."""
    return max(
        (
            r["map_seconds"]
            for result in results
            if result["world_light"].startswith("a world of one colour")
            for r in result["rows"]
        ),
        default=0.0,
    )


def write_markdown(out, data, command, args):
    width, height = args.resolution
    file_width, file_height = args.file_resolution
    lit = [s for s in data["survey"] if s["lit"]]
    one_colour = [s for s in lit if s["why"].startswith("a world of one colour")]
    lines = [
        "# What the world light costs",
        "",
        f"Generated by `{command}`; do not edit. Issue 47's Proof (native "
        "scene/world_light.h, docs/ARCHITECTURE.md): scenes lit by their world, each "
        "rendered by Whitted at the Draft, Preview and Final presets with the world light "
        "and again with it off (World > Ray Visibility > Diffuse off: the same world seen, "
        "lighting nothing), and compared with Whitted's converged image (the Reference "
        f"preset without its noise threshold, {args.converged_grid} x "
        f"{args.converged_grid} samples a pixel, Seed 1) and with Cycles limited to direct "
        f"light ({CYCLES_SAMPLES} samples). Time: the wall-clock time of the render call "
        f"(median of {args.repeats}), its trace phase, and the importance map's build "
        "(the render statistics' `world_light` phase, the world light's whole build: at "
        f"most {_one_colour_build(data['scenes'] + data['files']) * 1e6:.0f} microseconds "
        "where the world is of one colour and needs no map). Error: display RMSE in levels "
        "of 255 (the Estimate's measure); "
        "against Cycles also the summed luminance ratio and the SSIM after a 3 x 3 blur. "
        f"Both engines filter pixels with a one-pixel box. bpy {data['blender']}.",
        "",
        *machine_lines(),
        "",
        "## Summary (Final preset)",
        "",
        *_summary(data["scenes"] + data["files"]),
        "",
        f"## Studio HDRIs and a sky ({width}x{height})",
        "",
        "A diffuse sphere (albedo 0.8) on a grey floor (0.5), no lamp: Blender's studio "
        "HDRIs (`bpy.utils.system_resource('DATAFILES', path='studiolights/world')`) and a "
        f"{scattering_model().replace('_', ' ').title()} Sky Texture, sun "
        f"{SKY_ELEVATION:g} degrees up, strength 0.1. The world is their only light: "
        "with the world light off they are black but for the background, so their time "
        "ratio is the cost of lighting them at all, and under a noise threshold (every "
        "preset's) it counts the samples the lit image's noise asks for beside the "
        "feelers themselves. Images: Whitted Final with the world light | without it | "
        "Cycles.",
    ]
    for result in data["scenes"]:
        lines += _result_lines(result, out)
    lines += [
        "",
        f"## Third-party files ({file_width}x{file_height})",
        "",
        f"Debian's assimp-testmodels, `{MODELS}`, as authored: their lamps, cameras, "
        f"materials and worlds. {len(lit)} of the {len(data['survey'])} files have a world "
        "that lights them (the add-on's decision, export/world.py `world_light`), "
        f"{len(one_colour)} of them a world of one colour, whose light draws its feelers "
        "by the cosine and builds no map. Their lamps light them too: the world's share, "
        "and its cost, is small.",
        "",
        *table(
            ["file", "world lights it", "world colour, strength", "lamps", "why"],
            [
                [
                    s["file"],
                    "yes" if s["lit"] else "no",
                    "" if not s.get("world") else ", ".join(f"{v:.3g}" for v in s["world"]),
                    str(s.get("lamps", "")),
                    s["why"],
                ]
                for s in data["survey"]
            ],
            align="llrrl",
        ),
    ]
    for result in data["files"]:
        lines += _result_lines(result, out)
    write_page(Path(out) / "WORLD_LIGHT.md", lines)


def main(argv):
    args = parse_args(argv)
    image_dir = Path(args.out) / IMAGES
    image_dir.mkdir(parents=True, exist_ok=True)
    names = [n for n in (*HDRIS, "sky") if not args.scenes or n in args.scenes]
    with tempfile.TemporaryDirectory() as work:
        scenes = [
            measure(
                name,
                build_scene(name, tuple(args.resolution)),
                work,
                args.repeats,
                args.converged_grid,
                str(image_dir),
            )
            for name in names
        ]
        survey, files = measure_files(
            args.files,
            tuple(args.file_resolution),
            work,
            args.repeats,
            args.converged_grid,
            str(image_dir),
        )
    version = ".".join(str(v) for v in bpy.app.version[:2])
    data = {
        "blender": bpy.app.version_string,
        "scenes": scenes,
        "survey": survey,
        "files": files,
    }
    data_dir = Path(args.out) / "data"
    data_dir.mkdir(parents=True, exist_ok=True)
    (data_dir / f"world-light-blender-{version}.json").write_text(json.dumps(data, indent=2))
    write_markdown(args.out, data, command_line("bench-world-light", argv), args)
