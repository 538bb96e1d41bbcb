"""Real material set-ups and models by Whitted beside Cycles (in Blender): docs/MATERIALS.md.

The material gallery: real material set-ups rendered by Whitted beside Cycles
(direct light plus specular bounces; the world does not light diffuse surfaces).

    blender -b --factory-startup --python-exit-code 1 \
        --python tools/whitted_tools/__main__.py -- gallery-materials --out docs
    .venv/bin/python -m whitted_tools gallery-materials --out docs     (bpy 5.0 module)

Each run renders with the Blender that runs it and writes, for that Blender,
OUT/images/materials/blender-X.Y/<scene>.png (Whitted left, Cycles right) and
results.json; then it rewrites OUT/MATERIALS.md from every Blender's results.

Then the third-party scenes: real models made by other people, from Debian's
assimp-testmodels package (scripts/setup.sh installs it), each imported with
Blender's own importer, framed by a camera from its bounds, on a floor, under the
same sun and black world; results in third_party.json beside the others.

Measures, on the linear renders (transparent film, so alpha is the object mask):
SSIM of the two images (sRGB-encoded, clipped to [0, 1]) and the median of the
per-pixel luminance ratio Whitted / Cycles over the subject's pixels (the floor left
out) that both show covered and Cycles shows lit.
"""

import json
import math
import os
import tempfile
from pathlib import Path

import bpy

# isort: split
import numpy as np

from whitted_tools import cycles_scenes, shader_graphs
from whitted_tools.blender import enable_addon, factory_scene
from whitted_tools.cli import page_parser
from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    black_world,
    checker_pixels,
    frame_subject,
    grey_world,
    import_file,
    numpy_image,
    smooth_sphere,
    standard_film,
)
from whitted_tools.materials_page import (
    CYCLES_SAMPLES,
    TARGET_RATIO,
    TARGET_SSIM,
    THIRD_PARTY,
    THIRD_PARTY_MODELS,
    write_markdown,
)
from whitted_tools.metrics import subject_figures
from whitted_tools.render import render_exr, save_side_by_side
from whitted_tools.world_scenes import environment_world

WIDTH, HEIGHT = 240, 180


def parse_args(argv):
    parser = page_parser(__name__, __doc__)
    parser.add_argument("--only", nargs="*", help="scene names to render")
    return parser.parse_args(argv)


# --- the scenes -------------------------------------------------------------------


def scene_gltf_round_trip(scene, work):
    """A textured PBR sphere (base colour, metallic-roughness in G/B, normal map)
    exported with Blender's glTF exporter and imported back with its importer."""
    enable_addon("io_scene_gltf2")
    material = shader_graphs.new_material("PBR")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    base = tree.nodes.new("ShaderNodeTexImage")
    base.image = numpy_image("base", checker_pixels())
    tree.links.new(base.outputs["Color"], bsdf.inputs["Base Color"])
    rough = np.zeros((32, 32, 4))
    rough[..., 1] = np.linspace(0.1, 0.7, 32)[None, :]  # roughness in G
    rough[..., 2] = 0.0  # metallic in B
    rough[..., 3] = 1.0
    mr = tree.nodes.new("ShaderNodeTexImage")
    mr.image = numpy_image("metal_rough", rough, non_color=True)
    separate = tree.nodes.new("ShaderNodeSeparateColor")
    tree.links.new(mr.outputs["Color"], separate.inputs[0])
    tree.links.new(separate.outputs[1], bsdf.inputs["Roughness"])
    tree.links.new(separate.outputs[2], bsdf.inputs["Metallic"])
    smooth_sphere("Ball", (0.0, 0.0, 0.8), material=material)
    path = os.path.join(work, "ball.glb")
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB")
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    if not hasattr(np, "bool"):
        # Blender 3.4's importer still says np.bool, which numpy 1.24 removed.
        np.bool = bool
    bpy.ops.import_scene.gltf(filepath=path)
    add_floor(scene)
    add_sun(scene)
    add_camera(scene, (0.0, -4.5, 2.5), (0.0, 0.0, 0.7))
    black_world(scene)


def scene_groups_three_deep(scene, work):
    """A textured diffuse colour tinted through node groups nested three deep."""
    inner, inner_in, inner_out = shader_graphs.new_group(
        "Inner",
        inputs=[("Color", "NodeSocketColor", (1, 1, 1, 1))],
        outputs=[("Color", "NodeSocketColor")],
    )
    hue = inner.nodes.new("ShaderNodeHueSaturation")
    hue.inputs["Hue"].default_value = 0.6
    inner.links.new(inner_in.outputs["Color"], hue.inputs["Color"])
    inner.links.new(hue.outputs[0], inner_out.inputs["Color"])
    trees = [inner]
    for level in ("Middle", "Outer"):
        tree, tree_in, tree_out = shader_graphs.new_group(
            level,
            inputs=[("Color", "NodeSocketColor", (1, 1, 1, 1))],
            outputs=[("Color", "NodeSocketColor")],
        )
        node = tree.nodes.new("ShaderNodeGroup")
        node.node_tree = trees[-1]
        gamma = tree.nodes.new("ShaderNodeGamma")
        gamma.inputs[1].default_value = 1.2
        tree.links.new(tree_in.outputs["Color"], gamma.inputs[0])
        tree.links.new(gamma.outputs[0], node.inputs["Color"])
        tree.links.new(node.outputs["Color"], tree_out.inputs["Color"])
        trees.append(tree)
    material = shader_graphs.new_material("Grouped")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    first = shader_graphs.first_input(bsdf, ("Specular IOR Level", "Specular"))
    first.default_value = 0.0
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = numpy_image("cells", checker_pixels())
    outer = shader_graphs.group_node(material, trees[-1])
    tree.links.new(texture.outputs["Color"], outer.inputs["Color"])
    tree.links.new(outer.outputs["Color"], bsdf.inputs["Base Color"])
    bpy.ops.mesh.primitive_cube_add(size=1.4, location=(0.0, 0.0, 0.7))
    bpy.context.active_object.data.materials.append(material)
    add_floor(scene)
    add_sun(scene)
    add_camera(scene, (3.0, -3.5, 2.8), (0.0, 0.0, 0.6))
    black_world(scene)


def scene_normal_mapped(scene, work):
    """Ribs from a tangent-space normal map on a plane, lit at a grazing angle."""
    size = 64
    x = (np.arange(size) + 0.5) / size
    slope = 0.6 * np.cos(2 * np.pi * 6 * x)
    normal = np.stack([-slope, np.zeros_like(x), np.ones_like(x)], axis=-1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    pixels = np.ones((size, size, 4))
    pixels[..., :3] = (normal[None, :, :] + 1.0) / 2.0
    material = shader_graphs.new_material("Ribbed")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    bsdf.inputs["Base Color"].default_value = (0.7, 0.6, 0.5, 1.0)
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = numpy_image("ribs", pixels, non_color=True)
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    tree.links.new(texture.outputs["Color"], normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    bpy.ops.mesh.primitive_plane_add(size=3.0)
    bpy.context.active_object.data.materials.append(material)
    add_sun(scene, rotation=(70.0, 0.0, 90.0))
    add_camera(scene, (0.0, -3.2, 3.2), (0.0, 0.0, 0.0))
    black_world(scene)


def scene_bump_mapped(scene, work):
    """Dimples from a Bump node on a diffuse plane: the height sin(kx) sin(ky) of the
    Object coordinates built from Math nodes, under a sun at 45 degrees."""
    material = shader_graphs.new_material("Dimpled")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    bsdf.inputs["Base Color"].default_value = (0.6, 0.65, 0.7, 1.0)
    # Diffuse only, so that the figures measure the bent normals (a Phong highlight is
    # not Cycles' GGX one at roughness 0.5: see gltf_round_trip).
    shader_graphs.first_input(bsdf, ("Specular IOR Level", "Specular")).default_value = 0.0
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coordinates.outputs["Object"], separate.inputs[0])
    waves = []
    for axis in ("X", "Y"):
        scaled = tree.nodes.new("ShaderNodeMath")
        scaled.operation = "MULTIPLY"
        scaled.inputs[1].default_value = 2.0 * math.pi * 1.5
        tree.links.new(separate.outputs[axis], scaled.inputs[0])
        wave = tree.nodes.new("ShaderNodeMath")
        wave.operation = "SINE"
        tree.links.new(scaled.outputs[0], wave.inputs[0])
        waves.append(wave)
    height = tree.nodes.new("ShaderNodeMath")
    height.operation = "MULTIPLY"
    tree.links.new(waves[0].outputs[0], height.inputs[0])
    tree.links.new(waves[1].outputs[0], height.inputs[1])
    bump = tree.nodes.new("ShaderNodeBump")
    bump.inputs["Distance"].default_value = 0.08
    tree.links.new(height.outputs[0], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    bpy.ops.mesh.primitive_plane_add(size=3.0)
    bpy.context.active_object.data.materials.append(material)
    add_sun(scene, rotation=(45.0, 0.0, 60.0))
    add_camera(scene, (0.0, -3.2, 3.2), (0.0, 0.0, 0.0))
    black_world(scene)


def scene_vertex_colours(scene, work):
    """A Color Attribute on a subdivided grid into Base Color."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=3.0)
    grid = bpy.context.active_object
    mesh = grid.data
    paint = mesh.color_attributes.new("Paint", "FLOAT_COLOR", "POINT")
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    colors = np.ones((len(co), 4), dtype=np.float32)
    colors[:, 0] = (co[:, 0] + 1.5) / 3.0
    colors[:, 1] = (co[:, 1] + 1.5) / 3.0
    colors[:, 2] = 0.5 + 0.5 * np.sin(3.0 * co[:, 0])
    paint.data.foreach_set("color", colors.reshape(-1))
    material = shader_graphs.new_material("Painted")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    attribute = tree.nodes.new("ShaderNodeVertexColor")
    attribute.layer_name = "Paint"
    tree.links.new(attribute.outputs["Color"], bsdf.inputs["Base Color"])
    mesh.materials.append(material)
    add_sun(scene, rotation=(20.0, 0.0, 0.0))
    add_camera(scene, (0.0, -3.5, 3.0), (0.0, 0.0, 0.0))
    black_world(scene)


def scene_alpha_cards(scene, work):
    """Leaf cards: an image's alpha into Principled Alpha, shadows through the holes."""
    size = 64
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    leaf = ((x - 0.5) / 0.45) ** 2 + ((y - 0.5) / 0.3) ** 2 < 1.0
    pixels = np.zeros((size, size, 4))
    pixels[..., 0], pixels[..., 1], pixels[..., 2] = 0.2, 0.5 + 0.3 * y, 0.1
    pixels[..., 3] = leaf
    image = numpy_image("leaf", pixels)
    material = shader_graphs.new_material("Leaf")
    tree = material.node_tree
    bsdf = shader_graphs.principled(material)
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Closest"
    tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    tree.links.new(texture.outputs["Alpha"], bsdf.inputs["Alpha"])
    if hasattr(material, "blend_method"):
        material.blend_method = "CLIP"
    for k, (px, pz, rz) in enumerate(((-0.8, 1.0, 20.0), (0.3, 1.4, -15.0), (0.9, 0.8, 40.0))):
        bpy.ops.mesh.primitive_plane_add(size=1.2, location=(px, 0.2 * k, pz))
        card = bpy.context.active_object
        card.rotation_euler = (math.radians(70.0), 0.0, math.radians(rz))
        card.data.materials.append(material)
    add_floor(scene)
    add_sun(scene, rotation=(30.0, 0.0, 20.0))
    add_camera(scene, (0.0, -4.5, 2.4), (0.0, 0.0, 0.8))
    black_world(scene)


def scene_hdri_mirror_glass(scene, work):
    """An HDRI (Environment Texture, equirectangular) in a mirror and through glass."""
    width, height = 128, 64
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    sky = np.zeros((height, width, 4))
    elevation = (v - 0.5) * np.pi
    sky[..., 0] = (0.2 + 0.6 * np.clip(np.sin(elevation), 0, 1))[:, None]
    sky[..., 1] = (0.3 + 0.5 * np.clip(np.sin(elevation), 0, 1))[:, None]
    sky[..., 2] = 0.9
    sky[v < 0.5] = (0.25, 0.2, 0.15, 1.0)  # ground
    bands = (np.floor(u * 8) % 2 == 0)[None, :] & (np.abs(v - 0.55) < 0.04)[:, None]
    sky[bands] = (3.0, 1.0, 0.2, 1.0)
    sky[..., 3] = 1.0
    image = numpy_image("sky", sky)
    # Set as the scene's world before its Cycles settings, whose update reads it.
    world = environment_world(scene, image)
    world.cycles_visibility.diffuse = False
    mirror = shader_graphs.new_material("Mirror")
    mirror_bsdf = shader_graphs.principled(mirror)
    mirror_bsdf.inputs["Metallic"].default_value = 1.0
    mirror_bsdf.inputs["Roughness"].default_value = 0.0
    mirror_bsdf.inputs["Base Color"].default_value = (0.9, 0.9, 0.9, 1.0)
    glass = shader_graphs.new_material("Glass")
    glass.node_tree.nodes.remove(shader_graphs.principled(glass))
    glass_bsdf = glass.node_tree.nodes.new("ShaderNodeBsdfGlass")
    glass_bsdf.inputs["Roughness"].default_value = 0.0
    glass_bsdf.inputs["IOR"].default_value = 1.5
    glass.node_tree.links.new(glass_bsdf.outputs[0], shader_graphs.output(glass).inputs["Surface"])
    smooth_sphere("Mirror ball", (-0.9, 0.0, 0.8), material=mirror)
    smooth_sphere("Glass ball", (0.9, 0.0, 0.8), material=glass)
    add_floor(scene)
    add_sun(scene)
    add_camera(scene, (0.0, -4.8, 1.6), (0.0, 0.0, 0.8))


def scene_coat(scene, work):
    """A clear coat (3.x: Clearcoat) over a red diffuse base: the coat's highlight and
    its Fresnel-weighted reflection of the sky and the floor on top."""
    material = shader_graphs.new_material("Coated")
    bsdf = shader_graphs.principled(material)
    bsdf.inputs["Base Color"].default_value = (0.6, 0.05, 0.03, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.6
    # No specular layer of the base's own: the coat is the only gloss.
    shader_graphs.first_input(bsdf, ("Specular IOR Level", "Specular")).default_value = 0.0
    shader_graphs.first_input(bsdf, ("Coat Weight", "Clearcoat")).default_value = 1.0
    roughness = shader_graphs.first_input(bsdf, ("Coat Roughness", "Clearcoat Roughness"))
    roughness.default_value = 0.03  # Blender 4.0+'s default
    smooth_sphere("Ball", (0.0, 0.0, 0.8), material=material)
    add_floor(scene, albedo=0.8)
    add_sun(scene, rotation=(50.0, 0.0, 30.0))
    add_camera(scene, (0.0, -4.0, 1.8), (0.0, 0.0, 0.7))
    grey_world(scene)


SCENES = {
    "gltf_round_trip": scene_gltf_round_trip,
    "groups_three_deep": scene_groups_three_deep,
    "normal_mapped": scene_normal_mapped,
    "bump_mapped": scene_bump_mapped,
    "vertex_colours": scene_vertex_colours,
    "alpha_cards": scene_alpha_cards,
    "hdri_mirror_glass": scene_hdri_mirror_glass,
    "coat": scene_coat,
}


# --- third-party scenes --------------------------------------------------------------


def third_party_scene(entry):
    def build(scene, work):
        import_file(THIRD_PARTY_MODELS / entry["file"])
        frame_subject(scene)

    return build


# --- rendering and measures -----------------------------------------------------------


def set_engines(scene):
    standard_film(scene, WIDTH, HEIGHT, transparent=True)
    # Direct light plus specular bounces: mirrors and glass deep.
    cycles_scenes.set_cycles_reference(scene, CYCLES_SAMPLES, specular_bounces=8, max_bounces=12)
    scene.cycles.filter_width = 0.01
    whitted = scene.whitted
    whitted.aa_samples = 1
    whitted.max_depth = 8


def render_scene(name, build, image_dir):
    with tempfile.TemporaryDirectory() as work:
        scene = factory_scene()
        build(scene, work)
        set_engines(scene)
        whitted = render_exr(scene, os.path.join(work, "whitted.exr"), engine="WHITTED")
        cycles = render_exr(scene, os.path.join(work, "cycles.exr"), engine="CYCLES")
        # The subject's pixels: the floor hidden, what still covers the film.
        floor = scene.objects.get("Floor")
        subject = None
        if floor is not None:
            floor.hide_render = True
            alone = render_exr(scene, os.path.join(work, "subject.exr"), engine="WHITTED")
            floor.hide_render = False
            subject = alone[..., 3] > 0.99
        ssim, ratio = subject_figures(whitted, cycles, subject)
        save_side_by_side((whitted, cycles), os.path.join(image_dir, f"{name}.png"))
    passed = ssim >= TARGET_SSIM and TARGET_RATIO[0] <= ratio <= TARGET_RATIO[1]
    print(f"gallery_materials: {name}: SSIM {ssim:.3f}, ratio {ratio:.3f}, passed {passed}")
    return {"scene": name, "ssim": ssim, "ratio": ratio, "passed": passed}


def main(argv):
    args = parse_args(argv)
    version = ".".join(str(v) for v in bpy.app.version[:2])
    image_dir = os.path.join(args.out, "images", "materials", f"blender-{version}")
    os.makedirs(image_dir, exist_ok=True)
    results_path = os.path.join(image_dir, "results.json")
    # With --only, the other scenes keep this Blender's earlier results.
    earlier = {}
    if args.only and os.path.isfile(results_path):
        with open(results_path, encoding="utf-8") as file:
            earlier = {r["scene"]: r for r in json.load(file)}
    results = []
    for name, build in SCENES.items():
        if args.only and name not in args.only:
            if name in earlier:
                results.append(earlier[name])
            continue
        results.append(render_scene(name, build, image_dir))
    with open(results_path, "w", encoding="utf-8") as file:
        json.dump(results, file, indent=2)
    render_third_party(args, image_dir)
    write_markdown(args.out)


def render_third_party(args, image_dir):
    """The third-party scenes this Blender can import, into third_party.json."""
    if not THIRD_PARTY_MODELS.is_dir():
        raise SystemExit(
            f"gallery_materials: {THIRD_PARTY_MODELS} is missing: run scripts/setup.sh "
            "(it installs Debian's assimp-testmodels)"
        )
    path = Path(image_dir) / "third_party.json"
    earlier = {}
    if args.only and path.is_file():
        earlier = {r["scene"]: r for r in json.loads(path.read_text(encoding="utf-8"))}
    results = []
    for entry in THIRD_PARTY:
        name = entry["scene"]
        if Path(entry["file"]).suffix.lower() == ".dae" and bpy.app.version >= (5, 0, 0):
            continue  # Blender 5.0 has no Collada importer
        if args.only and name not in args.only:
            if name in earlier:
                results.append(earlier[name])
            continue
        results.append(render_scene(name, third_party_scene(entry), image_dir))
    path.write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")
