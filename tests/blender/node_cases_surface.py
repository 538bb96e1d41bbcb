"""Node cases for normals (tests/blender/node_cases.py's harness): an emission-only
plane whose colour is a normal n as 0.5 n + 0.5, rendered by Cycles and by Whitted.

`tilt` turns the plane about X after node_cases.build_scene, so that object and world
space differ (the orthographic camera still sees all of the plane's middle).
"""

import math
from dataclasses import dataclass

import bpy
from node_cases import _node, build_scene

TILT = math.radians(30.0)


@dataclass(frozen=True)
class SurfaceCase:
    name: str
    build: object  # function(tree) -> vector output socket (a unit normal)
    tilt: bool = False


def _as_colour(tree, vector):
    node = _node(tree, "ShaderNodeVectorMath", operation="MULTIPLY_ADD")
    node.inputs[1].default_value = (0.5, 0.5, 0.5)
    node.inputs[2].default_value = (0.5, 0.5, 0.5)
    tree.links.new(vector, node.inputs[0])
    return node.outputs[0]


def _normal(tree):
    return _node(tree, "ShaderNodeTexCoord").outputs["Normal"]


def _linear_height(tree, coordinates, kx, ky):
    """kx * x + ky * y of a Texture Coordinate output."""
    separate = _node(tree, "ShaderNodeSeparateXYZ")
    tree.links.new(_node(tree, "ShaderNodeTexCoord").outputs[coordinates], separate.inputs[0])
    x = _node(tree, "ShaderNodeMath", operation="MULTIPLY")
    x.inputs[1].default_value = kx
    tree.links.new(separate.outputs["X"], x.inputs[0])
    total = _node(tree, "ShaderNodeMath", operation="MULTIPLY_ADD")
    total.inputs[1].default_value = ky
    tree.links.new(separate.outputs["Y"], total.inputs[0])
    tree.links.new(x.outputs[0], total.inputs[2])
    return total.outputs[0]


def bump_case(name, coordinates, kx, ky, distance=1.0, strength=1.0, invert=False, tilt=False):
    def build(tree):
        node = _node(tree, "ShaderNodeBump", invert=invert)
        node.inputs["Distance"].default_value = distance
        node.inputs["Strength"].default_value = strength
        tree.links.new(_linear_height(tree, coordinates, kx, ky), node.inputs["Height"])
        return node.outputs["Normal"]

    return SurfaceCase(name, build, tilt)


CASES = [
    SurfaceCase("texture_coordinate_normal_tilted", _normal, tilt=True),
    bump_case("bump_object", "Object", 0.7, -0.4),
    bump_case("bump_uv_invert_strength", "UV", 1.5, 0.5, distance=0.6, strength=0.6, invert=True),
    bump_case("bump_generated_tilted", "Generated", -0.8, 1.1, distance=0.5, tilt=True),
]


def build_surface_scene(scene, case):
    """The node_cases plane with the case's normal as its emission colour."""
    material = build_scene(scene, _Adapter(case))
    if case.tilt:
        bpy.data.objects["Plane"].rotation_euler = (TILT, 0.0, 0.0)
    return material


@dataclass(frozen=True)
class _Adapter:
    # node_cases.build_scene's view of a case: build(tree, uv) -> colour.
    case: SurfaceCase

    @property
    def name(self):
        return self.case.name

    def build(self, tree, uv):
        return _as_colour(tree, self.case.build(tree))
