"""Node cases for normals and tangents (tests/blender/node_cases.py's harness): an
emission-only plane whose colour is a unit vector n as 0.5 n + 0.5, rendered by Cycles
and by Whitted.

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
    stretch: float = 1.0  # the plane's scale along its normal (object z)
    uniform: bool = True  # one vector over the whole plane (a radial tangent turns)


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


def displacement_case(name, coordinates, kx, ky, space, scale=1.0, tilt=False, stretch=1.0):
    """The material output's Displacement fed a Displacement node of the linear height
    (Cycles' default method, Bump Only, shades it as a bump): the Geometry node's Normal,
    the shading normal the bump sets for every node."""

    def build(tree):
        node = _node(tree, "ShaderNodeDisplacement", space=space)
        node.inputs["Scale"].default_value = scale
        tree.links.new(_linear_height(tree, coordinates, kx, ky), node.inputs["Height"])
        out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        tree.links.new(node.outputs["Displacement"], out.inputs["Displacement"])
        return _node(tree, "ShaderNodeNewGeometry").outputs["Normal"]

    return SurfaceCase(name, build, tilt, stretch)


def tangent_case(name, axis):
    """The Tangent node's radial tangent about object axis `axis`, or the Geometry node's
    Tangent (axis None; Cycles' default tangent, radial about Z), on the tilted plane.
    (About X or Y the flat plane's radial vector lies along its normal and the tangent has
    no direction: Cycles gives NaN, Whitted 0. test_glossy.py's brushed spheres read
    those axes.)"""

    def build(tree):
        if axis is None:
            return _node(tree, "ShaderNodeNewGeometry").outputs["Tangent"]
        return _node(tree, "ShaderNodeTangent", direction_type="RADIAL", axis=axis).outputs[0]

    return SurfaceCase(name, build, tilt=True, uniform=False)


def _uv_map_tangent(tree):
    """The Tangent node of a second UV map, "Turned", whose u runs at 35 degrees to the
    plane's x: the tangent leans in the plane and the tilt carries it off every axis."""
    mesh = bpy.data.objects["Plane"].data
    turned = mesh.uv_layers.new(name="Turned")
    c, s = math.cos(math.radians(35.0)), math.sin(math.radians(35.0))
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    turned.data.foreach_set("uv", [v for x, y in corners for v in (c * x + s * y, c * y - s * x)])
    return _node(tree, "ShaderNodeTangent", direction_type="UV_MAP", uv_map="Turned").outputs[0]


CASES = [
    SurfaceCase("texture_coordinate_normal_tilted", _normal, tilt=True),
    SurfaceCase("tangent_uv_map_tilted", _uv_map_tangent, tilt=True),
    tangent_case("tangent_radial_z_tilted", "Z"),
    tangent_case("geometry_tangent_tilted", None),
    bump_case("bump_object", "Object", 0.7, -0.4),
    bump_case("bump_uv_invert_strength", "UV", 1.5, 0.5, distance=0.6, strength=0.6, invert=True),
    bump_case("bump_generated_tilted", "Generated", -0.8, 1.1, distance=0.5, tilt=True),
    displacement_case("bump_displacement_world", "Object", 0.7, -0.4, "WORLD"),
    # Object space on a plane stretched 3 times along its normal: the displacement is 3
    # times as deep, as Cycles carries it from object space.
    displacement_case(
        "bump_displacement_object_stretched", "UV", 0.3, 0.2, "OBJECT", 0.5, True, 3.0
    ),
]


def build_surface_scene(scene, case):
    """The node_cases plane with the case's normal as its emission colour."""
    material = build_scene(scene, _Adapter(case))
    if case.tilt:
        bpy.data.objects["Plane"].rotation_euler = (TILT, 0.0, 0.0)
    bpy.data.objects["Plane"].scale = (1.0, 1.0, case.stretch)
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
