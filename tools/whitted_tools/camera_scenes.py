"""The camera effects' scenes (depth of field, motion blur), shared by their tests
against Cycles (tests/blender/test_depth_of_field.py, test_motion_blur.py) and the
distributed ray tracing gallery (whitted_tools gallery-effects)."""

import math

import bpy

from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    dark_stage,
    lambert_material,
    smooth_sphere,
)


def balls_in_a_row(scene):
    """Three diffuse balls 3.5, 5 and 8 m down the view of a camera that looks along
    them, on a floor under a sun: near (left), in focus (centre) and far (right), all in
    the frame at 3:2 and 4:3."""
    dark_stage(scene, 96, 64)
    add_floor(scene, size=40.0, albedo=0.5)
    for name, x, y, albedo in (
        ("Near", -0.7, 3.5, 0.8),
        ("Middle", 0.0, 5.0, 0.5),
        ("Far", 1.0, 8.0, 0.3),
    ):
        smooth_sphere(name, (x, y, 0.5), 0.5, lambert_material(name, albedo))
    add_camera(scene, (0.0, 0.0, 1.0), (0.0, 5.0, 0.5), lens=50.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=3.0)
    scene.whitted.ambient_strength = 0.0
    camera = scene.camera.data
    camera.dof.use_dof = True
    camera.dof.aperture_fstop = 0.5
    camera.dof.focus_object = bpy.data.objects["Middle"]


def linear_keys(obj):
    # Linear keys, so Whitted and Cycles sample one path (the default is Bezier, which
    # both would follow too; linear makes the test's expectations plain).
    action = obj.animation_data.action
    if bpy.app.version < (5, 0, 0):
        curves = action.fcurves
    else:
        curves = [
            curve
            for layer in action.layers
            for strip in layer.strips
            for bag in strip.channelbags
            for curve in bag.fcurves
        ]
    for curve in curves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"


def cube_crossing(scene, travel=4.0, turn=180.0, floor_albedo=0.5):
    """A diffuse cube on a floor under a sun, moving `travel` m along X and turning
    `turn` degrees about Z between frames 0 and 2; the scene at frame 1, motion blur on
    (the default shutter: 0.5 frames around the frame)."""
    dark_stage(scene, 96, 64)
    add_floor(scene, size=20.0, albedo=floor_albedo)
    mesh = bpy.data.meshes.new("Cube")
    h = 0.5
    corners = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh.from_pydata(corners, [], faces)
    mesh.materials.append(lambert_material("Cube", 0.8))
    cube = bpy.data.objects.new("Cube", mesh)
    scene.collection.objects.link(cube)
    for frame, x, angle in ((0, -travel / 2, 0.0), (2, travel / 2, math.radians(turn))):
        cube.location = (x, 0.0, 0.5)
        cube.rotation_euler.z = angle
        cube.keyframe_insert("location", frame=frame)
        cube.keyframe_insert("rotation_euler", frame=frame)
    linear_keys(cube)
    add_camera(scene, (0.0, -6.0, 3.0), (0.0, 0.0, 0.5), lens=35.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=3.0)
    scene.whitted.ambient_strength = 0.0
    scene.frame_set(1)
    scene.render.use_motion_blur = True
    return cube
