"""Scenes for the cost report (scripts/accuracy_cost.py), built with bpy (3.4 and 5.0).

    glass    a 3 x 3 grid of glass spheres and a glass slab over the demo's
             checkerboard, lit by a sphere light (soft shadows): deep refraction
    diffuse  matte boxes and spheres on an image-textured floor under an area
             light and a sun with an angle: soft shadows, textures, no mirrors

    blender -b --factory-startup --python scripts/cost_scenes.py -- \\
        --scene glass --save out/glass.blend
"""

import argparse
import math
import os
import sys

import bpy

# isort: split
import bmesh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_scene

GLASS_IORS = (1.2, 1.33, 1.5, 1.33, 1.5, 1.8, 1.5, 1.8, 2.4)
TEXTURE_SIZE = 64  # pixels per side of the floor's image


def build_glass_scene(scene):
    collection = scene.collection
    demo_scene.build_demo_scene(scene)
    for name in ("Glass Sphere", "Mirror Sphere", "Cube", "Cylinder", "Point Light"):
        bpy.data.objects.remove(bpy.data.objects[name])
    for index, ior in enumerate(GLASS_IORS):
        row, column = divmod(index, 3)
        sphere = demo_scene._object(
            collection,
            f"Glass {index}",
            demo_scene._sphere_mesh(0.6),
            (-2.0 + 2.0 * column, -1.5 + 2.0 * row, 0.6),
        )
        sphere.data.materials.append(_glass(f"Glass {ior}", ior))
    slab = demo_scene._object(collection, "Slab", demo_scene._cube_mesh(1.0), (0.0, -3.6, 0.9))
    slab.scale = (4.0, 0.3, 1.8)
    slab.data.materials.append(_glass("Slab Glass", 1.5))
    light = bpy.data.lights.new("Sphere Light", "POINT")
    light.energy = 2500.0
    light.shadow_soft_size = 0.5
    demo_scene._object(collection, "Sphere Light", light, (-2.5, 3.5, 6.0))
    return scene


def build_diffuse_scene(scene):
    collection = scene.collection
    demo_scene.build_demo_scene(scene)
    for name in ("Glass Sphere", "Mirror Sphere", "Point Light", "Floor"):
        bpy.data.objects.remove(bpy.data.objects[name])
    floor = demo_scene._object(collection, "Floor", _uv_floor())
    floor.data.materials.append(_textured("Floor", _floor_image()))
    for index, (x, y, color) in enumerate(
        ((-1.0, -1.0, (0.8, 0.3, 0.1)), (1.2, 0.8, (0.2, 0.7, 0.3)), (-1.6, 1.6, (0.7, 0.7, 0.7)))
    ):
        sphere = demo_scene._object(
            collection, f"Ball {index}", demo_scene._sphere_mesh(0.8), (x, y, 0.8)
        )
        sphere.data.materials.append(
            demo_scene._material(f"Matte {index}", color, {demo_scene._SPECULAR: 0.0})
        )
    area = bpy.data.lights.new("Area Light", "AREA")
    area.energy = 1500.0
    area.size = 2.5
    area_object = demo_scene._object(collection, "Area Light", area, (-2.0, 1.0, 5.0))
    area_object.rotation_euler = demo_scene._facing((0.3, -0.1, -1.0))
    sun = bpy.data.lights["Sun"]
    sun.angle = math.radians(8.0)
    return scene


def _glass(name, ior):
    return demo_scene._material(
        name,
        (1.0, 1.0, 1.0),
        {demo_scene._TRANSMISSION: 1.0, ("IOR",): ior, ("Roughness",): 0.0},
    )


def _uv_floor():
    half = demo_scene.FLOOR_CELLS / 2

    def build(bm):
        bm.loops.layers.uv.new("UVMap")  # calc_uvs fills an existing UV layer
        bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=half, calc_uvs=True)

    return demo_scene._mesh_from_bmesh("Floor", build, smooth=False)


def _floor_image():
    # Tiles with a thin grout, so closest and linear sampling differ visibly.
    image = bpy.data.images.new("Floor Tiles", TEXTURE_SIZE, TEXTURE_SIZE)
    pixels = []
    for y in range(TEXTURE_SIZE):
        for x in range(TEXTURE_SIZE):
            grout = x % 16 == 0 or y % 16 == 0
            tile = (x // 16 + y // 16) % 2
            value = 0.1 if grout else (0.75 if tile else 0.45)
            pixels += [value, value * 0.9, value * 0.8, 1.0]
    image.pixels.foreach_set(pixels)
    image.pack()
    return image


def _textured(name, image):
    material = demo_scene._material(name, (0.8, 0.8, 0.8), {demo_scene._SPECULAR: 0.0})
    nodes = material.node_tree.nodes
    principled = next(n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"
    material.node_tree.links.new(texture.outputs["Color"], principled.inputs["Base Color"])
    return material


BUILDERS = {"glass": build_glass_scene, "diffuse": build_diffuse_scene}


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=sorted(BUILDERS), required=True)
    parser.add_argument("--save", required=True, help=".blend file to write")
    args = parser.parse_args(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Blender's own module, importable once bpy is loaded.
    import addon_utils

    if addon_utils.enable("whitted", default_set=True) is None:
        sys.exit("cost_scenes: the add-on 'whitted' is not installed; run scripts/setup.sh")
    scene = BUILDERS[args.scene](bpy.context.scene)
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = 640, 480
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
    print(f"cost_scenes: saved {os.path.abspath(args.save)}")


if __name__ == "__main__":
    main()
