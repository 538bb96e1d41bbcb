"""What shader programs cost (in Blender): the Cost section of docs/MATERIALS.md.

What shader programs cost: one scene traced with constant materials, with the same
materials computed per hit by a program (the same values), and with texture-heavy
materials (image textures on base colour and roughness, a normal map, a noise
texture), interleaved in one run; trace time from each render's stats.

    .venv/bin/python -m whitted_tools bench-materials --out docs          (bpy 5.0 module)
    blender -b --factory-startup --python-exit-code 1 \\
        --python tools/whitted_tools/__main__.py -- bench-materials --out docs

Writes OUT/images/materials/cost-blender-X.Y.json and rewrites OUT/MATERIALS.md
(whitted_tools gallery-materials shows the figures of every Blender that ran this).
"""

import json
import os

import bpy

# isort: split
import numpy as np

from whitted_tools import material_scenes, shader_graphs
from whitted_tools.blender import factory_scene
from whitted_tools.cli import page_parser
from whitted_tools.materials_page import write_markdown
from whitted_tools.pages import machine_lines
from whitted_tools.verbs import blender_line, python_line

WIDTH, HEIGHT = 480, 270
AA_SAMPLES = 4
GRID = 8  # GRID x GRID spheres
REPEATS = 3
VARIANTS = ("constant", "program", "textured")
COMMANDS = (
    python_line("bench-materials", "--out", "docs"),
    blender_line("bench-materials", "--out", "docs"),
)


def parse_args(argv):
    return page_parser(__name__, __doc__, REPEATS).parse_args(argv)


def build_scene():
    scene = factory_scene()
    for i in range(GRID):
        for j in range(GRID):
            location = (1.1 * (i - (GRID - 1) / 2), 1.1 * (j - (GRID - 1) / 2), 0.5)
            material_scenes.smooth_sphere(f"Ball.{i}.{j}", location, radius=0.5)
    material_scenes.add_floor(scene, size=12.0)
    material_scenes.add_sun(scene)
    material_scenes.add_camera(scene, (0.0, -9.0, 6.0), (0.0, 0.0, 0.0), lens=35.0)
    material_scenes.black_world(scene)
    render = scene.render
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    scene.render.engine = "WHITTED"
    scene.whitted.aa_samples = AA_SAMPLES
    return scene


BASE = (0.6, 0.35, 0.2, 1.0)


def constant_material():
    material = shader_graphs.new_material("constant")
    bsdf = shader_graphs.principled(material)
    bsdf.inputs["Base Color"].default_value = BASE
    bsdf.inputs["Roughness"].default_value = 0.4
    return material


def program_material():
    """The constant material's values, but Base Color through an op that does not fold
    (BASE x clamp(Generated.x + 10, 0, 1) = BASE on every hit)."""
    material = constant_material()
    material.name = "program"
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    one = tree.nodes.new("ShaderNodeMath")
    one.operation = "ADD"
    one.use_clamp = True
    one.inputs[1].default_value = 10.0
    tint = tree.nodes.new("ShaderNodeMixRGB")
    tint.blend_type = "MULTIPLY"
    tint.inputs["Fac"].default_value = 1.0
    tint.inputs["Color1"].default_value = BASE
    tree.links.new(coordinates.outputs["Generated"], separate.inputs[0])
    tree.links.new(separate.outputs["X"], one.inputs[0])
    tree.links.new(one.outputs[0], tint.inputs["Color2"])
    tree.links.new(tint.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def textured_material():
    """Image textures on Base Color and Roughness, a tangent-space normal map, and a
    Noise texture mixed into the colour."""
    material = shader_graphs.new_material("textured")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    rng = np.random.default_rng(7)
    size = 256
    colour = material_scenes.numpy_image("colour", rng.uniform(0.1, 0.9, (size, size, 4)))
    rough = material_scenes.numpy_image(
        "rough", rng.uniform(0.2, 0.8, (size, size, 4)), non_color=True
    )
    normals = np.ones((size, size, 4))
    normals[..., :2] = rng.uniform(0.4, 0.6, (size, size, 2))
    normal_image = material_scenes.numpy_image("normals", normals, non_color=True)
    base = tree.nodes.new("ShaderNodeTexImage")
    base.image = colour
    roughness = tree.nodes.new("ShaderNodeTexImage")
    roughness.image = rough
    normal_texture = tree.nodes.new("ShaderNodeTexImage")
    normal_texture.image = normal_image
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 8.0
    mix = tree.nodes.new("ShaderNodeMixRGB")
    mix.inputs["Fac"].default_value = 0.3
    tree.links.new(base.outputs["Color"], mix.inputs["Color1"])
    tree.links.new(noise.outputs["Color"], mix.inputs["Color2"])
    tree.links.new(mix.outputs["Color"], bsdf.inputs["Base Color"])
    tree.links.new(roughness.outputs["Color"], bsdf.inputs["Roughness"])
    tree.links.new(normal_texture.outputs["Color"], normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    return material


def assign(scene, material):
    for obj in scene.objects:
        if obj.name.startswith("Ball."):
            obj.data.materials.clear()
            obj.data.materials.append(material)


def trace_seconds(scene):
    bpy.ops.render.render()
    stats = json.loads(scene.whitted.last_stats)
    return stats["phases"]["trace"], stats["rays"]["total"]


def main(argv):
    args = parse_args(argv)
    scene = build_scene()
    materials = {
        "constant": constant_material(),
        "program": program_material(),
        "textured": textured_material(),
    }
    times = {name: [] for name in VARIANTS}
    rays = {}
    for _ in range(args.repeats):
        for name in VARIANTS:
            assign(scene, materials[name])
            seconds, count = trace_seconds(scene)
            times[name].append(seconds)
            rays[name] = count
    best = {name: min(values) for name, values in times.items()}
    result = {
        "blender": bpy.app.version_string,
        "resolution": [WIDTH, HEIGHT],
        "aa_samples": AA_SAMPLES,
        "spheres": GRID * GRID,
        "repeats": args.repeats,
        "trace_seconds": times,
        "best": best,
        "rays": rays,
        "program_over_constant": best["program"] / best["constant"],
        "textured_over_constant": best["textured"] / best["constant"],
        "machine": machine_lines(),
        "commands": list(COMMANDS),
    }
    version = ".".join(str(v) for v in bpy.app.version[:2])
    directory = os.path.join(args.out, "images", "materials")
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, f"cost-blender-{version}.json"), "w") as file:
        json.dump(result, file, indent=2)
    for name in VARIANTS:
        print(f"bench_materials: {name}: best trace {best[name]:.3f} s, rays {rays[name]}")
    print(
        f"bench_materials: program / constant {result['program_over_constant']:.3f}, "
        f"textured / constant {result['textured_over_constant']:.3f}"
    )
    write_markdown(args.out)
