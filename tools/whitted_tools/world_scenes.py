"""Scenes lit by their world (issue 47; bpy): Blender's studio HDRIs and Sky Texture
worlds over a sphere on a floor, set up alike for Cycles (direct light) and Whitted, and
the figures that compare two renders of them. tests/blender/test_world_light.py and the
bench-world-light verb share them."""

import math
from pathlib import Path

import bmesh
import bpy
import numpy as np
from mathutils import Vector

from whitted_tools.cycles_scenes import set_cycles_direct_light
from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    glass_bsdf_material,
    lambert_material,
    smooth_sphere,
)
from whitted_tools.metrics import luminance, srgb_encode, ssim
from whitted_tools.scenes import background_world

# Blender's own studio HDRIs (Poly Haven's, CC0), shipped in every Blender: a low sun
# over a harbour, a forest under an overcast sky, a room lit by its windows.
HDRIS = ("sunset", "forest", "interior")


def studio_hdri(name):
    folder = Path(bpy.utils.system_resource("DATAFILES", path="studiolights/world"))
    return str(folder / f"{name}.exr")


def environment_world(scene, image):
    """A world whose Background is `image` (an Environment Texture), lighting diffuse
    surfaces as a new world does."""
    world = background_world("HDRI", (1.0, 1.0, 1.0))
    tree = world.node_tree
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    scene.world = world
    return world


def lit_by(scene, image, material, size=(96, 72), samples=6):
    """A sphere of `material` on a grey floor under the world `image`, both engines
    averaging each pixel's square: Cycles at 256 samples of direct light, Whitted on a
    jittered samples x samples grid."""
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    environment_world(scene, image)
    smooth_sphere("Ball", (0.0, 0.0, 1.0), 1.0, material)
    add_floor(scene, size=8.0, albedo=0.5)
    add_camera(scene, (0.0, -7.0, 3.0), (0.0, 0.0, 0.8))
    set_cycles_direct_light(scene, samples=256)
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.whitted.pixel_filter_type = "BOX"
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = samples


def room_with_a_glass_wall(scene, image, size=(96, 72), samples=6):
    """A closed room under the world `image`: a floor, three walls and a ceiling (grey
    Lambertian), its fourth wall (towards -Y) a clear glass pane 4 cm thick. The camera
    inside looks out through the pane at a sphere on the floor outside: what it sees
    outside, the world and what the world lights, it sees only through glass. Both
    engines as lit_by sets them, with the two refractions through the pane (and a
    reflection off it) traced: Cycles' glossy and transmission bounces 2, Whitted's
    depth 2."""
    lit_by(scene, image, lambert_material("Ball", 0.8), size, samples)
    scene.objects["Ball"].location = (0.6, -3.0, 0.6)
    scene.objects["Ball"].scale = (0.6, 0.6, 0.6)
    scene.objects["Floor"].scale = (2.5, 2.5, 1.0)  # 20 m: out of the camera's view
    wall = lambert_material("Wall", 0.5)
    # A box over x in [-1.5, 1.5], y in [-1, 1.5], z in [0, 2], open towards -Y and
    # below; its walls reach a centimetre under the floor, so no feeler leaks at a seam.
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    room = bpy.context.active_object
    room.name = "Room"
    room.scale = (3.0, 2.5, 2.01)
    room.location = (0.0, 0.25, 0.995)
    mesh = room.data
    bpy.ops.object.transform_apply(location=True, scale=True)
    shell = bmesh.new()
    shell.from_mesh(mesh)
    open_sides = [f for f in shell.faces if f.normal.y < -0.5 or f.normal.z < -0.5]
    bmesh.ops.delete(shell, geom=open_sides, context="FACES")
    shell.to_mesh(mesh)
    shell.free()
    mesh.materials.append(wall)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, -1.0, 1.0))
    pane = bpy.context.active_object
    pane.name = "Pane"
    pane.scale = (3.02, 0.04, 2.02)
    pane.data.materials.append(glass_bsdf_material("Glass", 0.0, ior=1.5))
    scene.camera.location = (0.0, 1.2, 1.3)
    scene.camera.rotation_euler = (
        (Vector((0.0, -4.0, 0.4)) - Vector(scene.camera.location))
        .to_track_quat("-Z", "Y")
        .to_euler()
    )
    scene.camera.data.lens = 20.0
    scene.cycles.max_bounces = 2
    scene.cycles.glossy_bounces = scene.cycles.transmission_bounces = 2
    scene.whitted.max_depth = 2


def sky_world(scene, model, elevation_degrees):
    """A world of a Sky Texture of `model` (its sun disc on where the model has one), the
    sun `elevation_degrees` up and 30 degrees round, at a tenth of its strength (a clear
    sky's radiance is tens of W/(m^2 sr)); Hosek/Wilkie at ten times its strength (Cycles
    scales that model's radiance by 2 pi / 683, about a hundredth of Preetham's)."""
    world = background_world("Sky", (1.0, 1.0, 1.0))
    tree = world.node_tree
    sky = tree.nodes.new("ShaderNodeTexSky")
    sky.sky_type = model
    if model in ("PREETHAM", "HOSEK_WILKIE"):
        elevation = math.radians(elevation_degrees)
        sky.sun_direction = (
            math.cos(elevation) * math.sin(math.radians(30.0)),
            math.cos(elevation) * math.cos(math.radians(30.0)),
            math.sin(elevation),
        )
    else:
        sky.sun_elevation = math.radians(elevation_degrees)
        sky.sun_rotation = math.radians(30.0)
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    strength = 10.0 if model == "HOSEK_WILKIE" else 0.1
    tree.nodes["Background"].inputs["Strength"].default_value = strength
    scene.world = world


def scattering_model():
    """The Sky Texture's physical model: Nishita before Blender 5.0, Single Scattering
    from it."""
    return "NISHITA" if bpy.app.version < (5, 0, 0) else "SINGLE_SCATTERING"


def compare(cycles, whitted):
    """(Whitted's summed luminance over Cycles', the SSIM of their display images after
    a 3 x 3 blur)."""
    ratio = float(luminance(whitted[..., :3]).sum() / luminance(cycles[..., :3]).sum())

    def shown(image):
        display = srgb_encode(np.clip(image[..., :3], 0.0, 1.0))
        padded = np.pad(display, ((1, 1), (1, 1), (0, 0)), mode="edge")
        h, w = display.shape[:2]
        return sum(padded[y : y + h, x : x + w] for y in range(3) for x in range(3)) / 9.0

    return ratio, ssim(shown(cycles), shown(whitted), data_range=1.0)
