"""How close Whitted's local term comes to Cycles' direct light, lobe by lobe: a smooth
Principled BSDF sphere under a sun (no angular size) on a black world, seen side-on,
rendered by both engines; per pixel the ratio Whitted / Cycles over the pixels Cycles
shows lit. Prints, for each metallic / roughness / base colour, the median ratio, the
ratio of the image sums and the 10th and 90th percentiles.

    blender -b --factory-startup --python-exit-code 1 --python scripts/lobes_vs_cycles.py
    .venv/bin/python scripts/lobes_vs_cycles.py                 (bpy 5.0 module)

Cycles' direct light from a sun of angle 0 is deterministic per pixel (light sampling
only, a centre-point filter), so a few samples suffice.
"""

import tempfile
from pathlib import Path

import bpy

# isort: split
import numpy as np
from whitted_tools.blender import factory_scene
from whitted_tools.material_scenes import sphere_under_sun
from whitted_tools.render import render_exr

SIZE = 64
CASES = [  # (metallic, roughness, base grey)
    (metallic, roughness, base)
    for metallic in (0.0, 1.0)
    for roughness in (0.2, 0.35, 0.5, 0.7)
    for base in (0.2, 0.8)
]


def build(metallic, roughness, base):
    scene = factory_scene()
    material = bpy.data.materials.new("Principled")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (base, base, base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    sphere_under_sun(scene, material, SIZE)
    cycles = scene.cycles
    cycles.samples, cycles.use_denoising, cycles.max_bounces = 16, False, 0
    cycles.filter_width = 0.01
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 0
    return scene


def main():
    print(f"Blender {bpy.app.version_string}: Whitted / Cycles per lit pixel")
    print("metallic roughness base: median, sum ratio, 10th..90th percentile")
    with tempfile.TemporaryDirectory() as directory:
        for metallic, roughness, base in CASES:
            scene = build(metallic, roughness, base)
            cycles = render_exr(scene, Path(directory) / "c.exr", engine="CYCLES")
            whitted = render_exr(scene, Path(directory) / "w.exr", engine="WHITTED")
            lit = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99) & (cycles[..., 0] > 0.01)
            w, c = whitted[lit][:, 0], cycles[lit][:, 0]
            ratio = w / c
            low, high = np.percentile(ratio, [10, 90])
            print(
                f"{metallic:.0f} {roughness:.2f} {base:.1f}: {np.median(ratio):.3f}, "
                f"{w.sum() / c.sum():.3f}, {low:.3f}..{high:.3f}"
            )


main()
