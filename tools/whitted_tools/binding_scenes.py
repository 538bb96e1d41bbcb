"""Scenes built through the native bindings alone (no bpy): what the benchmark that
compares two builds of whitted_native (whitted_tools.builds) gives every build alike,
using only what every build accepts."""

import math

import numpy as np


def sphere(radius, segments=48, rings=24):
    """(positions, triangles, vertex normals) of a UV sphere at the origin."""
    points = []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            points.append(
                (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))
            )
    triangles = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            if i > 0:
                triangles.append((a, a + segments, b))
            if i < rings - 1:
                triangles.append((b, a + segments, b + segments))
    normals = np.array(points, np.float32)
    return radius * normals, np.array(triangles, np.uint32), normals


def constant_spheres(wn):
    """64 smooth spheres (48 x 24 quads) on a floor, Lambert + Phong constants, one sun,
    seen from 35 degrees above, in the `wn` module (whitted_native of any build)."""
    scene = wn.Scene()
    positions, triangles, normals = sphere(0.5)
    scene.set_mesh("ball", positions, triangles, vertex_normals=normals)
    floor = np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32)
    scene.set_mesh("floor", floor, np.array([[0, 1, 2], [0, 2, 3]], np.uint32))
    ball = wn.Material(diffuse=(0.6, 0.35, 0.2), specular=(0.04,) * 3, shininess=30.0, ambient=0.0)
    scene.set_material("ball", ball)
    scene.set_material("floor", wn.Material(diffuse=(0.5,) * 3, ambient=0.0))
    scene.set_instance("floor", "floor", np.eye(4), ["floor"])
    for i in range(8):
        for j in range(8):
            to_world = np.eye(4)
            to_world[:3, 3] = (1.1 * (i - 3.5), 1.1 * (j - 3.5), 0.5)
            scene.set_instance(f"ball.{i}.{j}", "ball", to_world, ["ball"])
    sun = wn.Light(type=wn.LightType.SUN, color=(3.0,) * 3, direction=(-0.3, 0.4, -0.8))
    scene.set_light("sun", sun)
    to_world = np.eye(4)
    c, s = math.cos(math.radians(35.0)), math.sin(math.radians(35.0))
    to_world[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]  # 35 degrees down at the spheres
    to_world[:3, 3] = (0.0, -9.0, 6.5)
    scene.camera = wn.Camera(to_world=to_world, window=(-0.6, 0.6, -0.3375, 0.3375), clip_end=1e4)
    scene.background = (0.0, 0.0, 0.0)
    return scene
