"""Benchmark (not a test): what simulating only the effects a scene calls for saves.

Builds four variants of the demo scene (diffuse only, mirrors only, glass, everything),
exports each through the add-on, and renders it twice in the same process: with the
scene analysis on (the default) and with every effect forced on and no ray skipped.
Prints, for each scene, rays by type, the median trace time of the repeats, and the
difference between the two images, as a Markdown table.

    blender -b --factory-startup --python scripts/bench_effects.py -- \\
        [--resolution 320 240] [--repeats 3] [--out docs/EFFECTS.md]
"""

import argparse
import importlib.util
import statistics
import sys
from pathlib import Path

import addon_utils
import bpy
import numpy as np

REPO = Path(__file__).resolve().parents[1]
RAY_KINDS = ("camera", "shadow", "reflection", "refraction", "transparent", "total")


def load_demo_scene():
    spec = importlib.util.spec_from_file_location("demo_scene", REPO / "scripts/demo_scene.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def set_input(material, names, value):
    principled = next(
        n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"
    )
    socket = next(principled.inputs[n] for n in names if n in principled.inputs)
    socket.default_value = value


def make_diffuse(material):
    set_input(material, ("Metallic",), 0.0)
    set_input(material, ("Transmission Weight", "Transmission"), 0.0)
    set_input(material, ("Roughness",), 1.0)


def make_mirror(material):
    set_input(material, ("Transmission Weight", "Transmission"), 0.0)
    set_input(material, ("Metallic",), 1.0)
    set_input(material, ("Roughness",), 0.0)


def make_glass(material):
    set_input(material, ("Metallic",), 0.0)
    set_input(material, ("Transmission Weight", "Transmission"), 1.0)
    set_input(material, ("Roughness",), 0.0)


# Scene variants: what to do to the demo's glass and mirror materials.
VARIANTS = {
    "diffuse only": {"Glass": make_diffuse, "Mirror": make_diffuse},
    "mirrors only": {"Glass": make_mirror, "Mirror": make_mirror},
    "glass": {"Glass": make_glass, "Mirror": make_glass},
    "everything": {},
}


def build(demo, variant, width, height):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("whitted", default_set=True)
    scene = demo.build_demo_scene()
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    for name, change in VARIANTS[variant].items():
        change(bpy.data.materials[name])
    return scene


def render(native, exported, analysis, repeats):
    times = []
    for _ in range(repeats):
        settings = native.Settings(
            width=exported.width, height=exported.height, aa_samples=2, analysis=analysis
        )
        job = native.RenderJob(exported.scene, settings)
        job.start()
        while not job.wait(1.0):
            pass
        times.append(job.stats()["trace_seconds"])
    return job.image(), job.stats(), statistics.median(times)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, nargs=2, default=(320, 240))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", help="also write the table to this Markdown file")
    args = parser.parse_args(argv)

    from whitted.export.scene import convert_scene
    from whitted.native import load_native

    native = load_native()
    demo = load_demo_scene()
    width, height = args.resolution
    lines = [
        f"Blender {bpy.app.version_string}, {width}x{height}, 2x2 samples per pixel, depth 5, "
        f"median trace time of {args.repeats} renders, analysis on vs every effect forced on.",
        "",
        "| scene | mode | " + " | ".join(f"{k} rays" for k in RAY_KINDS) + " | trace s | "
        "time ratio | max abs image difference |",
        "|---|---|" + "---:|" * (len(RAY_KINDS) + 3),
    ]
    for variant in VARIANTS:
        scene = build(demo, variant, width, height)
        exported = convert_scene(bpy.context.evaluated_depsgraph_get(), native)
        on_image, on_stats, on_time = render(native, exported, True, args.repeats)
        off_image, off_stats, off_time = render(native, exported, False, args.repeats)
        difference = float(np.abs(on_image - off_image).max())
        for mode, stats, seconds in (
            ("analysis", on_stats, on_time),
            ("forced", off_stats, off_time),
        ):
            rays = " | ".join(str(stats["rays"][k]) for k in RAY_KINDS)
            ratio = f"{seconds / off_time:.2f}"
            diff = f"{difference:.2e}" if mode == "analysis" else ""
            lines.append(f"| {variant} | {mode} | {rays} | {seconds:.3f} | {ratio} | {diff} |")
        skipped = on_stats["shadow_rays_skipped"]
        lines.append(
            f"| {variant} | skipped | feelers: {skipped['backfacing']} backfacing, "
            f"{skipped['unlit']} unlit, {skipped['cutoff']} below cutoff; "
            f"{on_stats['cutoff']} branches below cutoff | | | | | | | | |"
        )
        del scene
    effects_line = "; ".join(on_stats["effects"])
    lines += ["", f"Effects of the last scene: {effects_line}.", ""]
    lines.append(
        "Command: `blender -b --factory-startup --python scripts/bench_effects.py -- "
        f"--resolution {width} {height} --repeats {args.repeats}`"
    )
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
