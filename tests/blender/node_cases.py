"""One case per node and mode: an emission-only plane whose colour is that node's
output, driven by the UV coordinates, so that a render of it (one sample at each
pixel centre, nothing lit) is the node's value over a range of inputs.

Shared by tests/blender/test_nodes_vs_cycles.py and scripts. The plane is 2 x 2 at
the origin, seen from above by an orthographic camera that fits it: pixel (row,
column) of a SIZE x SIZE render shows UV ((column + 0.5) / SIZE, (row + 0.5) / SIZE).
"""

import math
import os
from dataclasses import dataclass

import bpy
import numpy as np
from whitted_tools.material_scenes import empty_node_material, plain_film, top_camera

SIZE = 16


@dataclass(frozen=True)
class NodeCase:
    name: str
    build: object  # function(tree, uv output socket) -> colour output socket
    family: str  # the docs' name for the node
    image: bool = False  # reads an image (bound 1e-3)
    # A procedural texture read at pixel centres (_pixel_centres): the rendered image
    # compared value for value (bound 2e-5).
    procedural: bool = False
    # How far Cycles may lie outside the reference's range (test_nodes_vs_cycles).
    tolerance: float = 2e-5


def _node(tree, kind, **settings):
    node = tree.nodes.new(kind)
    for key, value in settings.items():
        setattr(node, key, value)
    return node


def _x(tree, uv):
    separate = _node(tree, "ShaderNodeSeparateXYZ")
    tree.links.new(uv, separate.inputs[0])
    return separate.outputs["X"], separate.outputs["Y"]


def _combine(tree, r, g=None, b=None):
    combine = _node(tree, "ShaderNodeCombineXYZ")
    for socket, value in zip(combine.inputs, (r, g, b), strict=True):
        if value is None:
            continue
        if isinstance(value, float):
            socket.default_value = value
        else:
            tree.links.new(value, socket)
    return combine.outputs[0]


def _spread(tree, value, scale, offset):
    node = _node(tree, "ShaderNodeMath", operation="MULTIPLY_ADD")
    node.inputs[1].default_value = scale
    node.inputs[2].default_value = offset
    tree.links.new(value, node.inputs[0])
    return node.outputs[0]


def math_case(operation, c=0.25, scale=3.871, offset=-1.9317):
    """Math on a in [offset, offset + scale) (from U) and b in (0.05, 0.96) (from V):
    off the pixel grid, so no pixel centre sits on a discontinuity."""

    def build(tree, uv):
        x, y = _x(tree, uv)
        node = _node(tree, "ShaderNodeMath", operation=operation)
        tree.links.new(_spread(tree, x, scale, offset), node.inputs[0])
        tree.links.new(_spread(tree, y, 0.913, 0.0437), node.inputs[1])
        node.inputs[2].default_value = c
        return _combine(tree, node.outputs[0], 0.0, 0.0)

    return NodeCase(f"math_{operation.lower()}", build, "Math")


def vector_math_case(operation):
    def build(tree, uv):
        mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
        mapping.inputs["Location"].default_value = (-0.5, -0.3, 0.2)
        mapping.inputs["Scale"].default_value = (2.0, 3.0, 1.0)
        tree.links.new(uv, mapping.inputs["Vector"])
        node = _node(tree, "ShaderNodeVectorMath", operation=operation)
        tree.links.new(mapping.outputs[0], node.inputs[0])
        node.inputs[1].default_value = (0.3, -0.7, 0.5)
        node.inputs[2].default_value = (0.2, 0.4, -0.1)
        if "Scale" in node.inputs:  # Blender 5.0 lists only the operands used
            node.inputs["Scale"].default_value = 1.3
        value = node.outputs["Value"] if operation in VALUE_OPS else None
        return _combine(tree, value) if value is not None else node.outputs["Vector"]

    return NodeCase(f"vector_math_{operation.lower()}", build, "Vector Math")


VALUE_OPS = {"DOT_PRODUCT", "DISTANCE", "LENGTH"}


def mix_rgb_case(blend, clamp=False):
    def build(tree, uv):
        mix = _node(tree, "ShaderNodeMixRGB", blend_type=blend, use_clamp=clamp)
        x, _ = _x(tree, uv)
        tree.links.new(x, mix.inputs[0])
        tree.links.new(uv, mix.inputs[1])
        mix.inputs[2].default_value = (0.9, 0.2, 0.6, 1.0)
        return mix.outputs[0]

    return NodeCase(f"mix_{blend.lower()}{'_clamp' if clamp else ''}", build, "MixRGB")


def ramp_case(interpolation, color_mode="RGB", hue="NEAR"):
    def build(tree, uv):
        x, _ = _x(tree, uv)
        ramp = _node(tree, "ShaderNodeValToRGB")
        ramp.color_ramp.color_mode = color_mode
        if color_mode != "RGB":
            ramp.color_ramp.hue_interpolation = hue
        ramp.color_ramp.interpolation = interpolation
        ramp.color_ramp.elements[0].color = (1.0, 0.1, 0.0, 1.0)
        ramp.color_ramp.elements.new(0.4).color = (0.0, 0.8, 0.2, 1.0)
        ramp.color_ramp.elements[-1].position = 0.9
        ramp.color_ramp.elements[-1].color = (0.2, 0.3, 1.0, 1.0)
        tree.links.new(x, ramp.inputs[0])
        return ramp.outputs["Color"]

    name = f"color_ramp_{interpolation.lower()}"
    if color_mode != "RGB":
        name += f"_{color_mode.lower()}_{hue.lower()}"
    return NodeCase(name, build, "Color Ramp")


def _rgb_curves(tree, uv):
    curves = _node(tree, "ShaderNodeRGBCurve")
    points = curves.mapping.curves[3].points
    points.new(0.3, 0.6)
    red = curves.mapping.curves[0].points
    red.new(0.5, 0.2)
    curves.mapping.update()
    tree.links.new(uv, curves.inputs["Color"])
    return curves.outputs[0]


def _float_curve(tree, uv):
    x, _ = _x(tree, uv)
    curve = _node(tree, "ShaderNodeFloatCurve")
    curve.mapping.curves[0].points.new(0.4, 0.8)
    curve.mapping.update()
    tree.links.new(x, curve.inputs["Value"])
    return _combine(tree, curve.outputs[0])


def _vector_curves(tree, uv):
    """X bent through a new point, Y extrapolated past its ends, on a Mapping that
    takes UV to [-1.2, 1.2] (beyond the curves' [-1, 1])."""
    mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
    mapping.inputs["Location"].default_value = (-1.2, -1.2, 0.3)
    mapping.inputs["Scale"].default_value = (2.4, 2.4, 1.0)
    tree.links.new(uv, mapping.inputs["Vector"])
    curves = _node(tree, "ShaderNodeVectorCurve")
    curves.mapping.curves[0].points.new(0.2, 0.7)
    curves.mapping.curves[1].points.new(-0.4, -0.1)
    curves.mapping.extend = "EXTRAPOLATED"
    curves.mapping.update()
    curves.inputs[0].default_value = 0.8
    tree.links.new(mapping.outputs[0], curves.inputs["Vector"])
    return curves.outputs[0]


def _separate_hsv(tree, uv):
    separate = _node(tree, "ShaderNodeSeparateColor", mode="HSV")
    tree.links.new(uv, separate.inputs[0])
    return _combine(tree, separate.outputs[0], separate.outputs[1], separate.outputs[2])


def combine_color_case(mode, third):
    """Combine Color in `mode` of U, V and the constant `third`."""

    def build(tree, uv):
        x, y = _x(tree, uv)
        combine = _node(tree, "ShaderNodeCombineColor", mode=mode)
        tree.links.new(x, combine.inputs[0])
        tree.links.new(y, combine.inputs[1])
        combine.inputs[2].default_value = third
        return combine.outputs[0]

    return NodeCase(f"combine_{mode.lower()}", build, "Combine Color")


def _hue_saturation(tree, uv):
    node = _node(tree, "ShaderNodeHueSaturation")
    node.inputs["Hue"].default_value = 0.3
    node.inputs["Saturation"].default_value = 1.5
    node.inputs["Value"].default_value = 0.8
    tree.links.new(uv, node.inputs["Color"])
    return node.outputs[0]


def _gamma(tree, uv):
    node = _node(tree, "ShaderNodeGamma")
    node.inputs[1].default_value = 2.2
    tree.links.new(uv, node.inputs[0])
    return node.outputs[0]


def _bright_contrast(tree, uv):
    node = _node(tree, "ShaderNodeBrightContrast")
    node.inputs[1].default_value = 0.1
    node.inputs[2].default_value = 0.5
    tree.links.new(uv, node.inputs[0])
    return node.outputs[0]


def _invert(tree, uv):
    node = _node(tree, "ShaderNodeInvert")
    node.inputs[0].default_value = 0.75
    tree.links.new(uv, node.inputs["Color"])
    return node.outputs[0]


def map_range_case(kind, clamp=True):
    def build(tree, uv):
        x, _ = _x(tree, uv)
        node = _node(tree, "ShaderNodeMapRange", interpolation_type=kind, clamp=clamp)
        node.inputs["From Min"].default_value = 0.2
        node.inputs["From Max"].default_value = 0.7
        node.inputs["To Min"].default_value = -0.5
        node.inputs["To Max"].default_value = 1.5
        if "Steps" in node.inputs:
            node.inputs["Steps"].default_value = 3.0
        tree.links.new(x, node.inputs["Value"])
        return _combine(tree, node.outputs[0])

    return NodeCase(f"map_range_{kind.lower()}", build, "Map Range")


def _clamp_range(tree, uv):
    x, _ = _x(tree, uv)
    node = _node(tree, "ShaderNodeClamp", clamp_type="RANGE")
    node.inputs["Min"].default_value = 0.8
    node.inputs["Max"].default_value = 0.3
    tree.links.new(x, node.inputs["Value"])
    return _combine(tree, node.outputs[0])


def mapping_case(kind):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeMapping", vector_type=kind)
        if "Location" in node.inputs and node.inputs["Location"].enabled:
            node.inputs["Location"].default_value = (0.1, -0.2, 0.3)
        node.inputs["Rotation"].default_value = (0.3, -0.5, 0.9)
        node.inputs["Scale"].default_value = (1.5, 0.5, 2.0)
        tree.links.new(uv, node.inputs["Vector"])
        return node.outputs[0]

    return NodeCase(f"mapping_{kind.lower()}", build, "Mapping")


def _rgb_to_bw(tree, uv):
    node = _node(tree, "ShaderNodeRGBToBW")
    tree.links.new(uv, node.inputs[0])
    return _combine(tree, node.outputs[0])


def _blackbody(tree, uv):
    # Temperatures from 600 K to 12600 K along U: below the fit's 800 K, each of its spans
    # and above its 12000 K.
    x, _ = _x(tree, uv)
    node = _node(tree, "ShaderNodeBlackbody")
    tree.links.new(_spread(tree, x, 12000.0, 600.0), node.inputs["Temperature"])
    return node.outputs["Color"]


def _wavelength(tree, uv):
    # 350 nm to 800 nm along U: below the table's 380 nm, across it and past its 780 nm.
    x, _ = _x(tree, uv)
    node = _node(tree, "ShaderNodeWavelength")
    tree.links.new(_spread(tree, x, 450.0, 350.0), node.inputs["Wavelength"])
    return node.outputs["Color"]


def vector_rotate_case(rotation_type, invert=False):
    """UV moved off the origin (z too) and turned about a centre off it."""

    def build(tree, uv):
        mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
        mapping.inputs["Location"].default_value = (-0.5, -0.3, 0.2)
        mapping.inputs["Scale"].default_value = (2.0, 1.5, 1.0)
        tree.links.new(uv, mapping.inputs["Vector"])
        node = _node(tree, "ShaderNodeVectorRotate", rotation_type=rotation_type, invert=invert)
        tree.links.new(mapping.outputs[0], node.inputs["Vector"])
        # Blender 5.0 lists only the inputs the type uses.
        values = {"Center": (0.2, -0.1, 0.3), "Axis": (0.3, -0.5, 0.8), "Angle": 0.9,
                  "Rotation": (0.4, -0.7, 1.1)}  # fmt: skip
        _set_inputs(node, {k: v for k, v in values.items() if k in node.inputs})
        return node.outputs["Vector"]

    name = f"vector_rotate_{rotation_type.lower()}{'_invert' if invert else ''}"
    return NodeCase(name, build, "Vector Rotate")


def light_falloff_case(output, smooth):
    """Strength from 0 to 0.04 along U; the camera's rays are RAY_LENGTH long."""

    def build(tree, uv):
        x, _ = _x(tree, uv)
        node = _node(tree, "ShaderNodeLightFalloff")
        tree.links.new(_spread(tree, x, 0.04, 0.0), node.inputs["Strength"])
        node.inputs["Smooth"].default_value = smooth
        return _combine(tree, node.outputs[output])

    name = f"light_falloff_{output.lower()}{'_smooth' if smooth else ''}"
    return NodeCase(name, build, "Light Falloff")


def _wireframe(tree, uv):
    # Size 0.3: the band along the plane's border and its quad's diagonal; no pixel centre
    # lies within 0.03 of the band's edge (Cycles' sample stays on the same side).
    node = _node(tree, "ShaderNodeWireframe", use_pixel_size=False)
    node.inputs["Size"].default_value = 0.3
    return _combine(tree, node.outputs["Fac"])


def mix_float_case():
    def build(tree, uv):
        x, y = _x(tree, uv)
        node = _node(tree, "ShaderNodeMix", data_type="FLOAT")
        tree.links.new(x, node.inputs["Factor"])
        tree.links.new(y, node.inputs[2])
        node.inputs[3].default_value = 0.9
        return _combine(tree, node.outputs[0])

    return NodeCase("mix_float", build, "Mix")


def mix_vector_case():
    def build(tree, uv):
        node = _node(tree, "ShaderNodeMix", data_type="VECTOR", factor_mode="NON_UNIFORM")
        tree.links.new(uv, node.inputs[1])  # Factor_Vector
        node.inputs[4].default_value = (0.1, 0.9, 0.4)
        node.inputs[5].default_value = (0.8, 0.2, 0.6)
        return node.outputs[1]

    return NodeCase("mix_vector_non_uniform", build, "Mix")


def checker_case(scale=3.0):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexChecker")
        node.inputs["Color1"].default_value = (0.9, 0.3, 0.1, 1.0)
        node.inputs["Color2"].default_value = (0.1, 0.2, 0.7, 1.0)
        node.inputs["Scale"].default_value = scale
        tree.links.new(uv, node.inputs["Vector"])
        return node.outputs["Color"]

    return NodeCase("checker", build, "Checker Texture")


def gradient_case(kind):
    def build(tree, uv):
        mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
        mapping.inputs["Location"].default_value = (-0.5, -0.5, 0.0)
        mapping.inputs["Scale"].default_value = (2.0, 2.0, 2.0)
        tree.links.new(uv, mapping.inputs["Vector"])
        node = _node(tree, "ShaderNodeTexGradient", gradient_type=kind)
        tree.links.new(mapping.outputs[0], node.inputs["Vector"])
        return node.outputs["Color"]

    return NodeCase(f"gradient_{kind.lower()}", build, "Gradient Texture")


def _pixel_centres(tree, uv):
    """UV snapped to the centre of the pixel it shows: constant over each pixel, so
    Cycles' sample, a little off the centre, reads the point Whitted reads (a texture
    of hashed cells compares value for value, not within a pixel's change)."""
    snap = _node(tree, "ShaderNodeVectorMath", operation="SNAP")
    tree.links.new(uv, snap.inputs[0])
    snap.inputs[1].default_value = (1.0 / SIZE, 1.0 / SIZE, 1.0)
    centre = _node(tree, "ShaderNodeVectorMath", operation="ADD")
    tree.links.new(snap.outputs[0], centre.inputs[0])
    centre.inputs[1].default_value = (0.5 / SIZE, 0.5 / SIZE, 0.0)
    return centre.outputs[0]


def _texture_input(tree, uv, node, location=(0.13, -0.27, 0.41), scale=(1.0, 1.0, 1.0)):
    """UV at pixel centres, moved off the lattice (and z off 0), into the texture's
    Vector; the UV at pixel centres."""
    uv = _pixel_centres(tree, uv)
    mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
    mapping.inputs["Location"].default_value = location
    mapping.inputs["Scale"].default_value = scale
    tree.links.new(uv, mapping.inputs["Vector"])
    vector = node.inputs.get("Vector")
    if vector is not None and vector.enabled:
        tree.links.new(mapping.outputs[0], vector)
    return uv


def _texture_output(tree, node, output):
    """A texture's output `output`: its Color as is, a value as a grey colour."""
    socket = node.outputs[output]
    return socket if output == "Color" else _combine(tree, socket)


def _set_inputs(node, values):
    for name, value in values.items():
        node.inputs[name].default_value = value


NOISE_TYPES = "noise_type" in bpy.types.ShaderNodeTexNoise.bl_rna.properties


def noise_case(dimensions, output="Color", name=None, noise_type=None, normalize=True, **inputs):
    """A Noise Texture over UV; 1D and 4D read W from U (+ 0.37)."""

    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexNoise", noise_dimensions=dimensions)
        if noise_type is not None:
            node.noise_type = noise_type
            node.normalize = normalize
        uv = _texture_input(tree, uv, node)
        if dimensions in ("1D", "4D"):
            x, _ = _x(tree, uv)
            tree.links.new(_spread(tree, x, 1.3, 0.37), node.inputs["W"])
        _set_inputs(node, inputs)
        return _texture_output(tree, node, output)

    return NodeCase(
        name or f"noise_{dimensions.lower()}_{output.lower()}", build, "Noise Texture",
        procedural=True,
    )  # fmt: skip


def wave_case(name, wave_type, direction, profile, output="Fac", **inputs):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexWave", wave_type=wave_type, wave_profile=profile)
        if wave_type == "BANDS":
            node.bands_direction = direction
        else:
            node.rings_direction = direction
        _texture_input(tree, uv, node, location=(-0.5, -0.45, 0.1))
        _set_inputs(node, inputs)
        return _texture_output(tree, node, output)

    return NodeCase(f"wave_{name}", build, "Wave Texture", procedural=True)


def magic_case(depth, output="Color", **inputs):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexMagic", turbulence_depth=depth)
        _texture_input(tree, uv, node)
        _set_inputs(node, inputs)
        return _texture_output(tree, node, output)

    return NodeCase(
        f"magic_depth_{depth}_{output.lower()}", build, "Magic Texture", procedural=True
    )


def brick_case(name, output="Color", settings=None, **inputs):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexBrick", **(settings or {}))
        node.inputs["Color1"].default_value = (0.9, 0.3, 0.1, 1.0)
        node.inputs["Color2"].default_value = (0.1, 0.6, 0.8, 1.0)
        node.inputs["Mortar"].default_value = (0.2, 0.2, 0.25, 1.0)
        _texture_input(tree, uv, node, location=(0.013, 0.021, 0.0))
        _set_inputs(node, inputs)
        return _texture_output(tree, node, output)

    return NodeCase(f"brick_{name}", build, "Brick Texture", procedural=True)


def white_noise_case(dimensions, output):
    """A White Noise Texture over UV at pixel centres moved by an exact (dyadic) offset,
    so both renderers hash the same float bits; 1D and 4D read W from U."""

    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexWhiteNoise", noise_dimensions=dimensions)
        uv = _texture_input(tree, uv, node, location=(0.125, -0.25, 0.5))
        if dimensions in ("1D", "4D"):
            x, _ = _x(tree, uv)
            tree.links.new(x, node.inputs["W"])
        return _texture_output(tree, node, output)

    return NodeCase(
        f"white_noise_{dimensions.lower()}_{output.lower()}", build, "White Noise Texture",
        procedural=True,
    )  # fmt: skip


def musgrave_case(dimensions, musgrave_type, **inputs):
    """A Musgrave Texture (Blender 3.4 to 4.0) over UV; 1D and 4D read W from U (+ 0.37)."""

    def build(tree, uv):
        node = _node(
            tree, "ShaderNodeTexMusgrave", musgrave_dimensions=dimensions,
            musgrave_type=musgrave_type,
        )  # fmt: skip
        uv = _texture_input(tree, uv, node)
        if dimensions in ("1D", "4D"):
            x, _ = _x(tree, uv)
            tree.links.new(_spread(tree, x, 1.3, 0.37), node.inputs["W"])
        _set_inputs(node, {k: v for k, v in inputs.items() if node.inputs[k].enabled})
        return _texture_output(tree, node, "Fac")

    name = f"musgrave_{dimensions.lower()}_{musgrave_type.lower()}"
    return NodeCase(name, build, "Musgrave Texture", procedural=True)


GABOR = hasattr(bpy.types, "ShaderNodeTexGabor")  # Blender 4.3+


def gabor_case(gabor_type, output, **inputs):
    """A Gabor Texture over UV (Blender 4.3+); inputs by identifier."""

    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexGabor", gabor_type=gabor_type)
        _texture_input(tree, uv, node)
        for identifier, value in inputs.items():
            next(s for s in node.inputs if s.identifier == identifier).default_value = value
        return _texture_output(tree, node, output)

    suffix = "_".join(f"{k.lower().replace(' ', '_')}" for k in inputs)
    return NodeCase(
        f"gabor_{gabor_type.lower()}_{output.lower()}{'_' + suffix if suffix else ''}",
        build, "Gabor Texture", procedural=True,
    )  # fmt: skip


MUSGRAVE = hasattr(bpy.types, "ShaderNodeTexMusgrave")
# Values that keep each fractal within a few units (a Hybrid or Ridged of high Gain grows
# fast): Detail with a fractional octave, Dimension and Lacunarity off their defaults.
MUSGRAVE_INPUTS = {"Scale": 2.0, "Detail": 3.5, "Dimension": 1.2, "Lacunarity": 2.2,
                   "Offset": 0.8, "Gain": 1.3}  # fmt: skip


VORONOI_FRACTAL = "normalize" in bpy.types.ShaderNodeTexVoronoi.bl_rna.properties


def voronoi_case(name, dimensions, feature, metric, output, normalize=False, **inputs):
    """A Voronoi Texture over UV; 1D and 4D read W from U (+ 0.37)."""

    def build(tree, uv):
        node = _node(
            tree, "ShaderNodeTexVoronoi", voronoi_dimensions=dimensions, feature=feature,
            distance=metric,
        )  # fmt: skip
        if normalize:
            node.normalize = True
        uv = _texture_input(tree, uv, node)
        if dimensions in ("1D", "4D"):
            x, _ = _x(tree, uv)
            tree.links.new(_spread(tree, x, 1.3, 0.37), node.inputs["W"])
        _set_inputs(node, inputs)
        socket = node.outputs[output]
        return _combine(tree, socket) if socket.type == "VALUE" else socket

    return NodeCase(f"voronoi_{name}", build, "Voronoi Texture", procedural=True)


PROCEDURAL_CASES = [
    noise_case("3D", Detail=2.5, Distortion=0.4),
    noise_case("1D", "Fac", Detail=3.0, Roughness=0.7),
    noise_case("2D", "Color", Scale=3.0, Detail=0.0),
    noise_case("4D", "Color", Scale=2.0, Detail=1.3, Distortion=0.8),
    *(
        (
            noise_case("3D", "Fac", "noise_fbm_raw", "FBM", False, Detail=4.2, Lacunarity=2.5),
            noise_case("3D", "Fac", "noise_multifractal", "MULTIFRACTAL", Detail=3.5),
            noise_case("2D", "Fac", "noise_ridged", "RIDGED_MULTIFRACTAL", Detail=3.0, Offset=1.0,
                       Gain=2.0),
            noise_case("3D", "Fac", "noise_hybrid", "HYBRID_MULTIFRACTAL", Detail=2.6, Offset=0.8,
                       Gain=1.5),
            noise_case("4D", "Fac", "noise_hetero", "HETERO_TERRAIN", Detail=2.4, Offset=0.6),
        )
        if NOISE_TYPES
        else ()
    ),
    voronoi_case("3d_f1_color", "3D", "F1", "EUCLIDEAN", "Color", Scale=3.0),
    voronoi_case("3d_f1_position", "3D", "F1", "EUCLIDEAN", "Position", Scale=3.0,
                 Randomness=0.8),
    voronoi_case("2d_f2_manhattan", "2D", "F2", "MANHATTAN", "Distance", Scale=4.0),
    voronoi_case("3d_smooth_chebychev", "3D", "SMOOTH_F1", "CHEBYCHEV", "Color", Scale=3.0,
                 Smoothness=0.7),
    voronoi_case("4d_f1_minkowski", "4D", "F1", "MINKOWSKI", "Distance", Scale=2.5,
                 Exponent=1.5),
    voronoi_case("1d_f2_w", "1D", "F2", "EUCLIDEAN", "W", Scale=4.0),
    voronoi_case("2d_edge", "2D", "DISTANCE_TO_EDGE", "EUCLIDEAN", "Distance", Scale=4.0),
    voronoi_case("3d_n_sphere", "3D", "N_SPHERE_RADIUS", "EUCLIDEAN", "Radius", Scale=3.0),
    *(
        (
            voronoi_case("3d_fractal", "3D", "F1", "EUCLIDEAN", "Distance", True, Scale=2.0,
                         Detail=2.5, Roughness=0.6, Lacunarity=2.2),
            voronoi_case("2d_fractal_color", "2D", "SMOOTH_F1", "EUCLIDEAN", "Color", True,
                         Scale=2.0, Detail=1.5, Smoothness=0.5),
            voronoi_case("2d_fractal_edge", "2D", "DISTANCE_TO_EDGE", "EUCLIDEAN", "Distance",
                         True, Scale=2.0, Detail=1.7, Roughness=0.7),
        )
        if VORONOI_FRACTAL
        else ()
    ),
    wave_case("bands_x_sin", "BANDS", "X", "SIN", Scale=1.3, Distortion=2.0, Detail=2.5),
    wave_case("bands_diagonal_tri", "BANDS", "DIAGONAL", "TRI", "Color", Scale=0.9),
    wave_case("rings_spherical_saw", "RINGS", "SPHERICAL", "SAW", Scale=0.7,
              **{"Phase Offset": 1.0}),
    wave_case("rings_z_sin", "RINGS", "Z", "SIN", Scale=1.1, Distortion=1.5,
              **{"Detail Scale": 2.0, "Detail Roughness": 0.8}),
    magic_case(0, Scale=1.5),
    magic_case(2, "Fac", Scale=1.2, Distortion=1.7),
    magic_case(10, Scale=0.8, Distortion=1.3),
    *(white_noise_case(d, o) for d in ("1D", "2D", "3D", "4D") for o in ("Value", "Color")),
    *(
        (
            musgrave_case("3D", "FBM", **MUSGRAVE_INPUTS),
            musgrave_case("1D", "FBM", **MUSGRAVE_INPUTS),
            musgrave_case("2D", "MULTIFRACTAL", **MUSGRAVE_INPUTS),
            musgrave_case("4D", "HETERO_TERRAIN", **MUSGRAVE_INPUTS),
            musgrave_case("3D", "HYBRID_MULTIFRACTAL", **MUSGRAVE_INPUTS),
            musgrave_case("2D", "RIDGED_MULTIFRACTAL", **MUSGRAVE_INPUTS),
            musgrave_case("4D", "FBM", **{**MUSGRAVE_INPUTS, "Detail": 1.0}),
        )
        if MUSGRAVE
        else ()
    ),
    *(
        (
            gabor_case("2D", "Value"),
            gabor_case("2D", "Phase", Scale=3.0, Frequency=3.5),
            gabor_case("2D", "Intensity", Anisotropy=0.4, **{"Orientation 2D": 1.1}),
            gabor_case("3D", "Value", Scale=2.5),
            gabor_case("3D", "Intensity", Anisotropy=0.6, **{"Orientation 3D": (0.3, 0.8, 0.5)}),
            gabor_case("3D", "Phase", Anisotropy=0.0, Frequency=1.5),
        )
        if GABOR
        else ()
    ),
    brick_case("color", Scale=2.0, Bias=0.2, **{"Mortar Smooth": 0.5, "Mortar Size": 0.05}),
    brick_case("squash_fac", "Fac", {"offset": 0.3, "offset_frequency": 3, "squash": 0.6,
                                      "squash_frequency": 2}, Scale=2.5,
               **{"Mortar Smooth": 0.3, "Mortar Size": 0.04}),
]  # fmt: skip


def tex_coord_case(output):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeTexCoord")
        return node.outputs[output]

    return NodeCase(f"texture_coordinate_{output.lower()}", build, "Texture Coordinate")


def _other_object_coordinates(tree, uv):
    # Texture Coordinate > Object of another object: the point in that object's space
    # (an empty turned, stretched and moved, so every entry of its inverse counts).
    empty = bpy.data.objects.new("Frame", None)
    bpy.context.scene.collection.objects.link(empty)
    empty.location = (0.3, -0.2, 0.5)
    empty.rotation_euler = (0.4, -0.3, 0.7)
    empty.scale = (1.5, 0.5, 2.0)
    bpy.context.view_layer.update()
    node = _node(tree, "ShaderNodeTexCoord", object=empty)
    return node.outputs["Object"]


def light_path_case(output):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeLightPath")
        return _combine(tree, node.outputs[output])

    return NodeCase(f"light_path_{output.lower().replace(' ', '_')}", build, "Light Path")


def object_info_case(output):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeObjectInfo")
        socket = node.outputs[output]
        if socket.type == "VALUE":
            return _combine(tree, socket)
        return socket

    return NodeCase(f"object_info_{output.lower().replace(' ', '_')}", build, "Object Info")


def _color_attribute(tree, uv):
    node = _node(tree, "ShaderNodeVertexColor", layer_name="Paint")
    return node.outputs["Color"]


def _attribute(tree, uv):
    node = _node(tree, "ShaderNodeAttribute", attribute_name="height")
    return _combine(tree, node.outputs[2])


def _fresnel(tree, uv):
    node = _node(tree, "ShaderNodeFresnel")
    node.inputs["IOR"].default_value = 1.5
    return _combine(tree, node.outputs[0])


def _layer_weight(output):
    def build(tree, uv):
        node = _node(tree, "ShaderNodeLayerWeight")
        node.inputs["Blend"].default_value = 0.3
        return _combine(tree, node.outputs[output])

    return build


def image_case(projection="FLAT", interpolation="Closest", extension="REPEAT", scale=1.0):
    def build(tree, uv):
        node = _node(
            tree,
            "ShaderNodeTexImage",
            projection=projection,
            interpolation=interpolation,
            extension=extension,
        )
        node.image = test_image()
        if projection != "FLAT" or scale != 1.0:
            mapping = _node(tree, "ShaderNodeMapping", vector_type="POINT")
            mapping.inputs["Scale"].default_value = (scale, scale, scale)
            if projection != "FLAT":
                coords = _node(tree, "ShaderNodeTexCoord")
                tree.links.new(coords.outputs["Object"], mapping.inputs["Vector"])
            else:
                tree.links.new(uv, mapping.inputs["Vector"])
            tree.links.new(mapping.outputs[0], node.inputs["Vector"])
        return node.outputs["Color"]

    name = f"image_{projection.lower()}_{interpolation.lower()}_{extension.lower()}"
    return NodeCase(name, build, "Image Texture", image=True)


def test_image():
    """A 4 x 4 float image of distinct colours (linear, no colour conversion)."""
    image = bpy.data.images.get("node case texels")
    if image is not None:
        return image
    image = bpy.data.images.new("node case texels", 4, 4, float_buffer=True)
    rng = np.random.default_rng(7)
    texels = rng.uniform(0.05, 0.95, size=(4, 4, 4)).astype(np.float32)
    texels[..., 3] = 1.0
    image.pixels.foreach_set(texels.reshape(-1))
    image.pack()
    return image


MATH_OPERATIONS = [
    op
    for op in bpy.types.ShaderNodeMath.bl_rna.properties["operation"].enum_items.keys()  # noqa: SIM118
]
VECTOR_OPERATIONS = [
    op
    for op in bpy.types.ShaderNodeVectorMath.bl_rna.properties["operation"].enum_items.keys()  # noqa: SIM118
]
BLENDS = list(bpy.types.ShaderNodeMixRGB.bl_rna.properties["blend_type"].enum_items.keys())

CASES = [
    # WRAP's third input is its minimum: below every maximum, so the range never
    # passes through 0 (where any rounding flips the result).
    # TANGENT over (-1.2, 1.2): no pole, where a sample's sub-pixel place is all.
    *(
        math_case(op, c=-0.25 if op == "WRAP" else 0.25)
        if op != "TANGENT"
        else math_case(op, scale=2.4, offset=-1.2)
        for op in MATH_OPERATIONS
    ),
    *(vector_math_case(op) for op in VECTOR_OPERATIONS),
    *(mix_rgb_case(blend) for blend in BLENDS),
    mix_rgb_case("LINEAR_LIGHT", clamp=True),
    mix_float_case(),
    mix_vector_case(),
    *(ramp_case(kind) for kind in ("CONSTANT", "LINEAR", "EASE", "CARDINAL", "B_SPLINE")),
    ramp_case("LINEAR", "HSV", "NEAR"),
    ramp_case("EASE", "HSV", "FAR"),
    ramp_case("LINEAR", "HSL", "CW"),
    ramp_case("LINEAR", "HSL", "CCW"),
    ramp_case("CONSTANT", "HSV", "NEAR"),
    NodeCase("rgb_curves", _rgb_curves, "RGB Curves"),
    NodeCase("float_curve", _float_curve, "Float Curve"),
    NodeCase("vector_curves", _vector_curves, "Vector Curves"),
    NodeCase("separate_hsv", _separate_hsv, "Separate Color"),
    combine_color_case("HSV", 0.8),
    combine_color_case("HSL", 0.4),
    NodeCase("hue_saturation", _hue_saturation, "Hue/Saturation/Value"),
    NodeCase("gamma", _gamma, "Gamma"),
    NodeCase("bright_contrast", _bright_contrast, "Bright/Contrast"),
    NodeCase("invert", _invert, "Invert"),
    NodeCase("rgb_to_bw", _rgb_to_bw, "RGB to BW"),
    # Cycles 5.2's Blackbody is up to 3.6e-4 from 3.4's and 5.0's (blue 1.5659 against
    # 1.5663 near 12000 K, seen in CI); the reference is within 4e-6 of 3.4 and 5.0.
    NodeCase("blackbody", _blackbody, "Blackbody", tolerance=5e-4),
    NodeCase("wavelength", _wavelength, "Wavelength"),
    *(
        vector_rotate_case(kind)
        for kind in ("AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ")
    ),
    vector_rotate_case("AXIS_ANGLE", invert=True),
    vector_rotate_case("EULER_XYZ", invert=True),
    *(map_range_case(kind) for kind in ("LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP")),
    NodeCase("clamp_range", _clamp_range, "Clamp"),
    *(mapping_case(kind) for kind in ("POINT", "TEXTURE", "VECTOR", "NORMAL")),
    checker_case(),
    *(
        gradient_case(kind)
        for kind in (
            "LINEAR",
            "QUADRATIC",
            "EASING",
            "DIAGONAL",
            "SPHERICAL",
            "QUADRATIC_SPHERE",
            "RADIAL",
        )
    ),
    *PROCEDURAL_CASES,
    *(tex_coord_case(o) for o in ("UV", "Generated", "Object", "Normal", "Camera", "Window")),
    NodeCase("texture_coordinate_other_object", _other_object_coordinates, "Texture Coordinate"),
    *(light_path_case(o) for o in ("Is Camera Ray", "Is Shadow Ray", "Ray Depth", "Ray Length")),
    *(
        light_falloff_case(o, smooth)
        for o in ("Quadratic", "Linear", "Constant")
        for smooth in (0.0, 2.0)
    ),
    *(object_info_case(o) for o in ("Location", "Color", "Random", "Object Index")),
    NodeCase("color_attribute", _color_attribute, "Color Attribute"),
    NodeCase("attribute_float", _attribute, "Attribute"),
    NodeCase("wireframe", _wireframe, "Wireframe"),
    NodeCase("fresnel", _fresnel, "Fresnel"),
    NodeCase("layer_weight_fresnel", _layer_weight("Fresnel"), "Layer Weight"),
    NodeCase("layer_weight_facing", _layer_weight("Facing"), "Layer Weight"),
    image_case(),
    image_case(interpolation="Linear"),
    image_case(interpolation="Linear", extension="EXTEND", scale=1.5),
    image_case(interpolation="Closest", extension="CLIP", scale=1.5),
    image_case(projection="BOX", interpolation="Closest"),
    image_case(projection="SPHERE", interpolation="Closest"),
    image_case(projection="TUBE", interpolation="Closest"),
]


def build_scene(scene, case):
    """The case's plane (with a colour attribute 'Paint' and a float 'height'),
    the orthographic camera, no world, no lights."""
    plain_film(scene, SIZE, SIZE)
    top_camera(scene, 2.0)
    mesh = bpy.data.meshes.new("Plane")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    uv.data.foreach_set("uv", [0, 0, 1, 0, 1, 1, 0, 1])
    paint = mesh.color_attributes.new("Paint", "FLOAT_COLOR", "POINT")
    paint.data.foreach_set(
        "color", [0.9, 0.1, 0.1, 1, 0.1, 0.9, 0.1, 1, 0.1, 0.1, 0.9, 1, 1, 1, 1, 1]
    )
    height = mesh.attributes.new("height", "FLOAT", "POINT")
    height.data.foreach_set("value", [0.0, 0.25, 0.5, 1.0])
    plane = bpy.data.objects.new("Plane", mesh)
    plane.location = (0.0, 0.0, 0.0)
    plane.pass_index = 3
    plane.color = (0.2, 0.5, 0.7, 1.0)
    scene.collection.objects.link(plane)
    material = empty_node_material(case.name)
    tree = material.node_tree
    emission = tree.nodes.new("ShaderNodeEmission")
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    coords = tree.nodes.new("ShaderNodeTexCoord")
    tree.links.new(case.build(tree, coords.outputs["UV"]), emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    mesh.materials.append(material)
    return material


def set_cycles(scene):
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = 1
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = 0
    cycles.max_bounces = 0
    cycles.filter_width = 0.01
    cycles.pixel_filter_type = "BOX"


def render(scene, engine, directory, name):
    from whitted_tools.cycles_scenes import render_exr

    scene.whitted.aa_samples = 1
    return render_exr(scene, engine, os.path.join(directory, f"{name}_{engine.lower()}.exr"))


def uv_grid():
    """float64[SIZE, SIZE, 2]: the UV each pixel shows (rows bottom to top)."""
    centres = (np.arange(SIZE) + 0.5) / SIZE
    u, v = np.meshgrid(centres, centres)
    return np.stack([u, v], axis=-1)


def radians(x):
    return math.radians(x)
