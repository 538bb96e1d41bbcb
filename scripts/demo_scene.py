"""The classic Whitted demo scene, built with bpy (Blender 3.4 and 5.0).

A glass sphere and a mirror sphere, a cube and a cylinder on a red and yellow
checkerboard floor, lit by a point light and a sun with hard shadows, under a
sky-blue world. Tests import build_demo_scene(); run as a script it also
renders the scene with the Whitted engine:

    blender -b --factory-startup --python scripts/demo_scene.py -- \\
        --output out/demo.png --resolution 640 480 [--save out/demo.blend]
    .venv/bin/python scripts/demo_scene.py --output out/demo.png     (bpy module)

and prints the absolute path of the image.
"""

import argparse
import math
import os
import sys

import bpy

# isort: split
# Blender as a Python module makes bmesh and mathutils importable only after bpy.
import bmesh
from mathutils import Vector

# Linear colours and sizes that the render tests read back.
FLOOR_CELLS = 16  # per side, 1 m each, centred on the origin
FLOOR_COLORS = ((0.8, 0.05, 0.03), (0.8, 0.65, 0.05))  # red, yellow
SKY_COLOR = (0.25, 0.45, 0.8)
GLASS_CENTER, GLASS_RADIUS = (-0.9, -1.6, 1.0), 1.0
MIRROR_CENTER, MIRROR_RADIUS = (1.2, 1.4, 1.0), 1.0
CUBE_CENTER, CUBE_SIZE = (2.9, -1.2, 0.6), 1.2
CYLINDER_CENTER, CYLINDER_RADIUS, CYLINDER_HEIGHT = (-3.2, 1.6, 0.9), 0.5, 1.8
POINT_LIGHT_POSITION, POINT_LIGHT_POWER = (-2.5, 5.5, 6.0), 2000.0  # W
SUN_DIRECTION, SUN_STRENGTH = (0.45, -0.55, -0.7), 2.0  # way the light travels; W/m^2
CAMERA_POSITION, CAMERA_TARGET, CAMERA_LENS = (0.0, -11.0, 3.6), (0.0, 0.0, 0.9), 35.0

# Principled BSDF inputs by name, newest first (Blender 4.0 renamed some).
_SPECULAR = ("Specular IOR Level", "Specular")
_TRANSMISSION = ("Transmission Weight", "Transmission")


def build_demo_scene(scene=None):
    """Fill `scene` (default: the context scene, expected empty) and return it."""
    if scene is None:
        scene = bpy.context.scene
    collection = scene.collection

    floor = _object(collection, "Floor", _floor_mesh())
    for color_index, color in enumerate(FLOOR_COLORS):
        # Lambertian: no highlight, so its brightness is kd * (Ia + E / pi) exactly.
        floor.data.materials.append(
            _material(f"Checker {color_index}", color, {_SPECULAR: 0.0, ("Roughness",): 1.0})
        )

    glass = _object(collection, "Glass Sphere", _sphere_mesh(GLASS_RADIUS), GLASS_CENTER)
    glass.data.materials.append(
        _material(
            "Glass",
            (1.0, 1.0, 1.0),
            {_TRANSMISSION: 1.0, ("IOR",): 1.5, ("Roughness",): 0.0},
        )
    )
    mirror = _object(collection, "Mirror Sphere", _sphere_mesh(MIRROR_RADIUS), MIRROR_CENTER)
    mirror.data.materials.append(
        _material("Mirror", (0.9, 0.9, 0.9), {("Metallic",): 1.0, ("Roughness",): 0.0})
    )

    cube = _object(collection, "Cube", _cube_mesh(CUBE_SIZE), CUBE_CENTER)
    cube.rotation_euler = (0.0, 0.0, math.radians(25.0))
    cube.data.materials.append(_material("Diffuse Blue", (0.1, 0.25, 0.8), {}))
    cylinder = _object(collection, "Cylinder", _cylinder_mesh(), CYLINDER_CENTER)
    cylinder.data.materials.append(_material("Diffuse Green", (0.1, 0.6, 0.15), {}))

    point = bpy.data.lights.new("Point Light", "POINT")
    point.energy = POINT_LIGHT_POWER
    point.shadow_soft_size = 0.0  # a true point: hard shadows
    _object(collection, "Point Light", point, POINT_LIGHT_POSITION)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = SUN_STRENGTH
    sun.angle = 0.0
    sun_object = _object(collection, "Sun", sun, (0.0, 0.0, 10.0))
    sun_object.rotation_euler = _facing(SUN_DIRECTION)

    camera = bpy.data.cameras.new("Camera")
    camera.lens = CAMERA_LENS
    camera_object = _object(collection, "Camera", camera, CAMERA_POSITION)
    camera_object.rotation_euler = _facing(Vector(CAMERA_TARGET) - Vector(CAMERA_POSITION))
    scene.camera = camera_object

    scene.world = _sky_world()
    return scene


def _object(collection, name, data, location=(0.0, 0.0, 0.0)):
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    collection.objects.link(obj)
    return obj


def _facing(direction):
    # Rotation that points the object's local -Z (where cameras look and lights
    # shine) along `direction`, keeping local +Y up.
    return Vector(direction).to_track_quat("-Z", "Y").to_euler()


def _uses_node_tree_always():
    # Blender 5.0 always shades with node trees and deprecates `use_nodes`.
    return bpy.app.version >= (5, 0, 0)


def _material(name, base_color, inputs):
    material = bpy.data.materials.new(name)
    material.diffuse_color = (*base_color, 1.0)  # the viewport shows the same colour
    if not _uses_node_tree_always():
        material.use_nodes = True
    principled = next(
        node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled"
    )
    principled.inputs["Base Color"].default_value = (*base_color, 1.0)
    for names, value in inputs.items():
        socket = next(principled.inputs[n] for n in names if n in principled.inputs)
        socket.default_value = value
    return material


def _sky_world():
    world = bpy.data.worlds.new("Sky")
    world.color = SKY_COLOR
    if not _uses_node_tree_always():
        world.use_nodes = True
    background = next(
        node for node in world.node_tree.nodes if node.bl_idname == "ShaderNodeBackground"
    )
    background.inputs["Color"].default_value = (*SKY_COLOR, 1.0)
    background.inputs["Strength"].default_value = 1.0
    return world


def _mesh_from_bmesh(name, build, smooth):
    bm = bmesh.new()
    try:
        build(bm)
        mesh = bpy.data.meshes.new(name)
        bm.to_mesh(mesh)
    finally:
        bm.free()
    mesh.polygons.foreach_set("use_smooth", [smooth] * len(mesh.polygons))
    return mesh


def _floor_mesh():
    half = FLOOR_CELLS / 2
    mesh = _mesh_from_bmesh(
        "Floor",
        lambda bm: bmesh.ops.create_grid(
            bm, x_segments=FLOOR_CELLS, y_segments=FLOOR_CELLS, size=half
        ),
        smooth=False,
    )
    # A checkerboard of per-face materials: slot 0 and 1 alternate like the squares.
    centers = [0.0] * (3 * len(mesh.polygons))
    mesh.polygons.foreach_get("center", centers)
    slots = [
        (math.floor(x + half) + math.floor(y + half)) % 2
        for x, y in zip(centers[0::3], centers[1::3], strict=True)
    ]
    mesh.polygons.foreach_set("material_index", slots)
    return mesh


def _sphere_mesh(radius):
    return _mesh_from_bmesh(
        "Sphere",
        lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=64, v_segments=32, radius=radius),
        smooth=True,
    )


def _cube_mesh(size):
    return _mesh_from_bmesh("Cube", lambda bm: bmesh.ops.create_cube(bm, size=size), smooth=False)


def _cylinder_mesh():
    return _mesh_from_bmesh(
        "Cylinder",
        lambda bm: bmesh.ops.create_cone(
            bm,
            cap_ends=True,
            segments=48,
            radius1=CYLINDER_RADIUS,
            radius2=CYLINDER_RADIUS,
            depth=CYLINDER_HEIGHT,
        ),
        smooth=False,
    )


def _parse_args():
    # Inside the blender binary our arguments follow "--"; as a module, sys.argv is ours.
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description="Render the Whitted demo scene.")
    parser.add_argument("--output", default="out/demo.png", help="PNG to write")
    parser.add_argument("--resolution", nargs=2, type=int, default=(640, 480), metavar=("W", "H"))
    parser.add_argument("--save", help="also save the scene as this .blend file")
    parser.add_argument(
        "--no-render", action="store_true", help="only build the scene (and --save it)"
    )
    return parser.parse_args(argv)


def main():
    args = _parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Blender's own module, importable once bpy is loaded.
    import addon_utils

    if addon_utils.enable("whitted", default_set=True) is None:
        sys.exit(
            "demo_scene: the add-on 'whitted' is not installed; run scripts/setup.sh, which "
            "links addon/ into Blender's user add-on folder"
        )
    scene = build_demo_scene()
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    # The classic look: linear radiance shown without a film curve.
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    output = os.path.abspath(args.output)
    os.makedirs(os.path.dirname(output), exist_ok=True)
    scene.render.filepath = output
    if args.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
        print(f"demo_scene: saved {os.path.abspath(args.save)}")
    if not args.no_render:
        bpy.ops.render.render(write_still=True)
        print(f"demo_scene: wrote {output}", flush=True)


if __name__ == "__main__":
    main()
