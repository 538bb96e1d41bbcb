"""The ray-tree inspector drawn in a real window: the camera view of the demo in Solid
mode, a screenshot, bpy.ops.whitted.inspect_ray_tree on a pixel of the mirror sphere,
another screenshot. Records where (in screenshot pixels) points along each drawn ray
project, with the ray's kind, so the test can look for the ray's colour there.
"""

import json

import bpy
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector
from whitted_tools import viewport_driver as driver

# Where along a ray its points are checked (fractions of its drawn length).
FRACTIONS = (0.3, 0.5, 0.7)
WIDTH, HEIGHT = 96, 72  # the final frame the pixel is picked from


def scenario(h):
    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    yield h.maximise()
    h.setup_view("SOLID")
    h.space.show_gizmo = True  # the tree is drawn by a gizmo
    yield 0.3
    yield from h.screenshot("before")
    mirror = bpy.data.objects["Mirror Sphere"]
    u, v, _ = world_to_camera_view(scene, scene.camera, mirror.matrix_world.translation)
    h.step("inspect")
    result = bpy.ops.whitted.inspect_ray_tree(x=int(u * WIDTH), y=int(v * HEIGHT))
    h.record("inspect", sorted(result))
    tree = json.loads(scene.whitted.last_ray_tree)
    from whitted.ray_tree.tree import segments

    points = []
    for kind, start, end, _weight, blocked in segments(tree):
        if kind == "camera":
            continue  # seen end-on from the camera: a dot
        for f in FRACTIONS:
            at = Vector(start).lerp(Vector(end), f)
            x, y = h.project(at)
            points.append({"kind": kind, "blocked": blocked, "xy": [x, y]})
    h.record("points", points)
    h.record("area", [h.area.width, h.area.height])
    yield from h.screenshot("after")


driver.main(scenario)
