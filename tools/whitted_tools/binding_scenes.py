"""Pieces of scenes built through the native bindings alone (no bpy): what the
benchmarks that compare two builds of whitted_native (scripts/bench_builds.py,
scripts/bench_shadow_scenes.py) give every build alike."""

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
