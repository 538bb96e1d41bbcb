"""The classic Whitted demo scene, built with bpy (Blender 3.4 and 5.0).

A glass sphere and a mirror sphere, a cube and a cylinder on a red and yellow
checkerboard floor, lit by a point light and a sun with hard shadows, under a
sky-blue world. scripts/demo_scene.py renders it; tests and the benchmarks build it
with build_demo_scene() and read back the figures below.
"""

import math

import bpy

# isort: split
# Blender as a Python module makes bmesh and mathutils importable only after bpy.
import bmesh
from mathutils import Vector

from whitted_tools.scenes import (
    SPECULAR,
    TRANSMISSION,
    add_object,
    background_world,
    bmesh_mesh,
    cube_mesh,
    facing,
    principled_material,
    set_principled_inputs,
    sphere_mesh,
)

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
# The demo's spheres: smooth, 64 segments by 32 rings.
SPHERE_SEGMENTS, SPHERE_RINGS = 64, 32


def build_demo_scene(scene=None):
    """Fill `scene` (default: the context scene, expected empty) and return it."""
    if scene is None:
        scene = bpy.context.scene
    collection = scene.collection

    floor = add_object(collection, "Floor", floor_mesh())
    for color_index, color in enumerate(FLOOR_COLORS):
        # Lambertian: no highlight, so its brightness is kd * (Ia + E / pi) exactly.
        floor.data.materials.append(
            principled_material(
                f"Checker {color_index}", color, {SPECULAR: 0.0, ("Roughness",): 1.0}
            )
        )

    glass = add_object(collection, "Glass Sphere", demo_sphere_mesh(GLASS_RADIUS), GLASS_CENTER)
    glass.data.materials.append(
        principled_material(
            "Glass", (1.0, 1.0, 1.0), {TRANSMISSION: 1.0, ("IOR",): 1.5, ("Roughness",): 0.0}
        )
    )
    mirror = add_object(collection, "Mirror Sphere", demo_sphere_mesh(MIRROR_RADIUS), MIRROR_CENTER)
    mirror.data.materials.append(mirror_material("Mirror"))

    cube = add_object(collection, "Cube", cube_mesh("Cube", CUBE_SIZE), CUBE_CENTER)
    cube.rotation_euler = (0.0, 0.0, math.radians(25.0))
    cube.data.materials.append(principled_material("Diffuse Blue", (0.1, 0.25, 0.8), {}))
    cylinder = add_object(collection, "Cylinder", _cylinder_mesh(), CYLINDER_CENTER)
    cylinder.data.materials.append(principled_material("Diffuse Green", (0.1, 0.6, 0.15), {}))

    point = bpy.data.lights.new("Point Light", "POINT")
    point.energy = POINT_LIGHT_POWER
    point.shadow_soft_size = 0.0  # a true point: hard shadows
    add_object(collection, "Point Light", point, POINT_LIGHT_POSITION)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = SUN_STRENGTH
    sun.angle = 0.0
    sun_object = add_object(collection, "Sun", sun, (0.0, 0.0, 10.0))
    sun_object.rotation_euler = facing(SUN_DIRECTION)

    camera = bpy.data.cameras.new("Camera")
    camera.lens = CAMERA_LENS
    camera_object = add_object(collection, "Camera", camera, CAMERA_POSITION)
    camera_object.rotation_euler = facing(Vector(CAMERA_TARGET) - Vector(CAMERA_POSITION))
    scene.camera = camera_object

    scene.world = sky_world()
    return scene


# The demo's variants that call for fewer effects (whitted_tools bench-effects): what
# becomes of its Glass and Mirror materials.
DIFFUSE_INPUTS = {("Metallic",): 0.0, TRANSMISSION: 0.0, ("Roughness",): 1.0}
MIRROR_INPUTS = {TRANSMISSION: 0.0, ("Metallic",): 1.0, ("Roughness",): 0.0}
GLASS_INPUTS = {("Metallic",): 0.0, TRANSMISSION: 1.0, ("Roughness",): 0.0}
DEMO_VARIANTS = {
    "diffuse only": DIFFUSE_INPUTS,
    "mirrors only": MIRROR_INPUTS,
    "glass": GLASS_INPUTS,
    "everything": None,  # the demo as it is
}


def build_demo_variant(variant, scene=None):
    """The demo scene with both spheres' materials made as DEMO_VARIANTS[variant] says."""
    scene = build_demo_scene(scene)
    inputs = DEMO_VARIANTS[variant]
    if inputs is not None:
        for name in ("Glass", "Mirror"):
            set_principled_inputs(bpy.data.materials[name], inputs)
    return scene


def mirror_material(name, color=(0.9, 0.9, 0.9)):
    """The demo's mirror: a metallic Principled BSDF of roughness 0."""
    return principled_material(name, color, {("Metallic",): 1.0, ("Roughness",): 0.0})


def sky_world():
    return background_world("Sky", SKY_COLOR)


def demo_sphere_mesh(radius):
    return sphere_mesh("Sphere", SPHERE_SEGMENTS, SPHERE_RINGS, radius)


def floor_mesh():
    """The checkerboard floor: FLOOR_CELLS x FLOOR_CELLS unit squares, material slots 0
    and 1 alternating like the squares."""
    half = FLOOR_CELLS / 2

    def grid(bm):
        bmesh.ops.create_grid(bm, x_segments=FLOOR_CELLS, y_segments=FLOOR_CELLS, size=half)

    mesh = bmesh_mesh("Floor", grid, smooth=False)
    centers = [0.0] * (3 * len(mesh.polygons))
    mesh.polygons.foreach_get("center", centers)
    slots = [
        (math.floor(x + half) + math.floor(y + half)) % 2
        for x, y in zip(centers[0::3], centers[1::3], strict=True)
    ]
    mesh.polygons.foreach_set("material_index", slots)
    return mesh


def _cylinder_mesh():
    def build(bm):
        bmesh.ops.create_cone(
            bm,
            cap_ends=True,
            segments=48,
            radius1=CYLINDER_RADIUS,
            radius2=CYLINDER_RADIUS,
            depth=CYLINDER_HEIGHT,
        )

    return bmesh_mesh("Cylinder", build, smooth=False)
