"""The converter and colour nodes as Exprs: Math and Vector Math, separate and combine,
Mix, Color Ramp, the curves (sampled into tables), Invert, Hue/Saturation, Gamma,
Bright/Contrast, Map Range, Clamp, RGB to BW, Mapping, Vector Rotate, Blackbody and
Wavelength."""

import bpy

from . import ops
from .ir import COLOR, FLOAT, VECTOR
from .sockets import find_socket, output_index, output_name


def _math(c, out):
    node = out.node
    a, b, cc = (c.value(s, out.scope, FLOAT) for s in list(node.inputs)[:3])
    name = node.operation
    return c.b.math(
        name,
        a,
        b if _math_arity(name) > 1 else None,
        cc if _math_arity(name) > 2 else None,
        clamp=node.use_clamp,
    )


_UNARY = {
    "SQRT", "INVERSE_SQRT", "ABSOLUTE", "EXPONENT", "SIGN", "ROUND", "FLOOR", "CEIL",
    "TRUNC", "FRACT", "SINE", "COSINE", "TANGENT", "ARCSINE", "ARCCOSINE", "ARCTANGENT",
    "SINH", "COSH", "TANH", "RADIANS", "DEGREES",
}  # fmt: skip


_TERNARY = {"MULTIPLY_ADD", "COMPARE", "SMOOTH_MIN", "SMOOTH_MAX", "WRAP"}


def _math_arity(name):
    return 1 if name in _UNARY else (3 if name in _TERNARY else 2)


_VECTOR_UNARY = {
    "NORMALIZE", "LENGTH", "ABSOLUTE", "SIGN", "FLOOR", "CEIL", "FRACTION", "SINE", "COSINE",
    "TANGENT", "ROUND",
}  # fmt: skip


def _vector_math(c, out):
    node = out.node
    sockets = list(node.inputs)
    name = node.operation
    a = c.value(sockets[0], out.scope, VECTOR)
    b = c.value(sockets[1], out.scope, VECTOR)
    third = c.value(sockets[2], out.scope, VECTOR)
    scale_socket = find_socket(node.inputs, ("Scale",), enabled_only=False)
    # Blender 5.0 leaves unused operands out of `inputs`.
    scale = c.b.f(1.0) if scale_socket is None else c.value(scale_socket, out.scope, FLOAT)
    if name == "SCALE":
        args = (a, scale, None)
    elif name == "REFRACT":
        args = (a, b, scale)
    elif name in ("MULTIPLY_ADD", "FACEFORWARD", "WRAP"):
        args = (a, b, third)
    elif name in _VECTOR_UNARY:
        args = (a, None, None)
    else:
        args = (a, b, None)
    result = c.b.vmath(name, *args)
    is_value = name in ops.VECTOR_VALUE_OPS
    if output_name(out) == "Value":
        return result if is_value else c.b.f(0.0)
    return c.b.const((0.0, 0.0, 0.0), VECTOR) if is_value else result


def _separate(c, out, color_mode, input_names):
    value = c.input(out, input_names, COLOR)
    if color_mode != "RGB":
        mode = ops.pack("SEPARATE", mode=color_mode)
        value = c.b.op(ops.SEPARATE, mode, (value,), kind=COLOR)
    return c.b.swizzle(value, output_index(out))


def _separate_color(c, out):
    return _separate(c, out, out.node.mode, ("Color",))


def _combine(c, out, color_mode, kind):
    x, y, z = (c.value(s, out.scope, FLOAT) for s in list(out.node.inputs)[:3])
    return c.b.op(ops.COMBINE, ops.pack("COMBINE", mode=color_mode), (x, y, z), kind=kind)


def _combine_color(c, out):
    return _combine(c, out, out.node.mode, COLOR)


def _mix_rgb(c, out):
    node = out.node
    factor = c.b.clamp01(c.input(out, ("Fac", "Factor"), FLOAT))
    color1 = c.input(out, ("Color1",), COLOR)
    color2 = c.input(out, ("Color2",), COLOR)
    return _mix_blend(c, node.blend_type, factor, color1, color2, node.use_clamp)


def _mix_blend(c, blend, factor, color1, color2, clamp):
    if blend == "MIX" and not clamp:
        return c.b.vlerp(factor, color1, color2, COLOR)
    mode = ops.pack("MIX", blend_type=blend, clamp=clamp)
    return c.b.op(ops.MIX, mode, (factor, color1, color2), kind=COLOR)


def _mix(c, out):
    node = out.node
    data_type = node.data_type
    if data_type == "FLOAT":
        factor = c.input(out, ("Factor_Float",), FLOAT)
        if node.clamp_factor:
            factor = c.b.clamp01(factor)
        a = c.input(out, ("A_Float",), FLOAT)
        b = c.input(out, ("B_Float",), FLOAT)
        return c.b.lerp(factor, a, b)
    if data_type == "VECTOR":
        a = c.input(out, ("A_Vector",), VECTOR)
        b = c.input(out, ("B_Vector",), VECTOR)
        if node.factor_mode == "NON_UNIFORM":
            factor = c.input(out, ("Factor_Vector",), VECTOR)
            if node.clamp_factor:
                zero = c.b.const((0.0, 0.0, 0.0), VECTOR)
                one = c.b.const((1.0, 1.0, 1.0), VECTOR)
                factor = c.b.vmath("MINIMUM", c.b.vmath("MAXIMUM", factor, zero), one)
            mode = ops.pack("MIX_VALUE", factor_mode="NON_UNIFORM")
            return c.b.op(ops.MIX_VALUE, mode, (factor, a, b), kind=VECTOR)
        factor = c.input(out, ("Factor_Float",), FLOAT)
        if node.clamp_factor:
            factor = c.b.clamp01(factor)
        return c.b.vlerp(factor, a, b, VECTOR)
    if data_type == "RGBA":
        factor = c.input(out, ("Factor_Float",), FLOAT)
        if node.clamp_factor:
            factor = c.b.clamp01(factor)
        a = c.input(out, ("A_Color",), COLOR)
        b = c.input(out, ("B_Color",), COLOR)
        return _mix_blend(c, node.blend_type, factor, a, b, node.clamp_result)
    c.warn(node, f"{data_type} mixing is not supported; the input it feeds uses its unlinked value")
    return None


# Cycles reads a Color Ramp from a table of colours Blender evaluates at evenly spaced
# positions, interpolated linearly between them (or the one below, for Constant): 256
# of them at i / 255 in Blender 3.4, 257 at i / 256 in 5.0 (measured against each one's
# Cycles; 4.x is read as 5.0, not measured).
_RAMP_STEPS = 255 if bpy.app.version < (4, 0, 0) else 256


def _ramp(c, out):
    node = out.node
    ramp = node.color_ramp
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    interpolation = ramp.interpolation
    if ramp.color_mode != "RGB":
        # HSV and HSL blends (with their hue direction) are Blender's own: Blender's table,
        # as Cycles takes it, becomes a ramp of its entries.
        table = [float(_RAMP_STEPS + 1)]
        for i in range(_RAMP_STEPS + 1):
            position = i / _RAMP_STEPS
            table += [position, *map(float, ramp.evaluate(position))]
        interpolation = "CONSTANT" if interpolation == "CONSTANT" else "LINEAR"
    else:
        table = [float(len(ramp.elements))]
        for element in ramp.elements:
            table += [float(element.position), *map(float, element.color)]
    mode = ops.pack("COLOR_RAMP", interpolation=interpolation)
    color = c.b.op(ops.COLOR_RAMP, mode, (factor,), e=tuple(table), kind=COLOR)
    if output_name(out) == "Alpha":
        return c.b.swizzle(color, 3)
    return color


def curve_table(mapping, columns, low=0.0, high=1.0):
    """A CURVE constants block: for each of the 4 columns, 256 samples over [low, high]
    of `mapping.curves[columns[k]]` (None: zeros), with the curve's own `evaluate`."""
    if hasattr(mapping, "initialize"):
        mapping.initialize()
    size = ops.CURVE_TABLE_SIZE
    table = []
    for index in columns:
        if index is None:
            table += [0.0] * size
            continue
        curve = mapping.curves[index]
        table += [
            float(mapping.evaluate(curve, low + (high - low) * i / (size - 1))) for i in range(size)
        ]
    return tuple(table)


def _vector_curves(c, out):
    node = out.node
    mapping = node.mapping
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    vector = c.input(out, ("Vector",), VECTOR)
    # Cycles tabulates the three curves over the span of their points (the first
    # point's x to the last's) and looks each axis up at its place in that span.
    low = min(curve.points[0].location[0] for curve in mapping.curves[:3])
    high = max(curve.points[-1].location[0] for curve in mapping.curves[:3])
    if not high > low:
        low, high = 0.0, 1.0
    table = curve_table(mapping, (0, 1, 2, None), low, high)
    span = c.b.const((high - low,) * 3, VECTOR)
    place = c.b.vmath("DIVIDE", c.b.vmath("SUBTRACT", vector, c.b.const((low,) * 3, VECTOR)), span)
    mapped = c.b.op(
        ops.CURVE, _curve_mode(node, "VECTOR"), (c.b.f(1.0), place), e=table, kind=VECTOR
    )
    return c.b.vlerp(factor, vector, mapped, kind=VECTOR)


def _rgb_curves(c, out):
    node = out.node
    if tuple(node.mapping.black_level) != (0.0, 0.0, 0.0) or tuple(node.mapping.white_level) != (
        1.0,
        1.0,
        1.0,
    ):
        c.warn(node, "black and white levels are ignored")
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    color = c.input(out, ("Color",), COLOR)
    table = curve_table(node.mapping, (3, 0, 1, 2))
    return c.b.op(ops.CURVE, _curve_mode(node, "RGB"), (factor, color), e=table, kind=COLOR)


def _curve_mode(node, kind):
    # Extrapolate: extend the curves along their end slopes (Extend: Extrapolated).
    extrapolated = getattr(node.mapping, "extend", "HORIZONTAL") == "EXTRAPOLATED"
    return ops.pack("CURVE", kind=kind, extrapolate=extrapolated)


def _float_curve(c, out):
    factor = c.input(out, ("Factor", "Fac"), FLOAT)
    value = c.input(out, ("Value",), FLOAT)
    table = curve_table(out.node.mapping, (0, None, None, None))
    return c.b.op(ops.CURVE, _curve_mode(out.node, "FLOAT"), (factor, value), e=table, kind=FLOAT)


def _invert(c, out):
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    color = c.input(out, ("Color",), COLOR)
    return c.b.op(ops.INVERT, 0, (factor, color), kind=COLOR)


def _hue_sat(c, out):
    hue = c.input(out, ("Hue",), FLOAT)
    saturation = c.input(out, ("Saturation",), FLOAT)
    value = c.input(out, ("Value",), FLOAT)
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    color = c.input(out, ("Color",), COLOR)
    return c.b.op(ops.HUE_SAT, 0, (hue, saturation, value, factor, color), kind=COLOR)


def _gamma(c, out):
    color = c.input(out, ("Color",), COLOR)
    gamma = c.input(out, ("Gamma",), FLOAT)
    return c.b.op(ops.GAMMA, 0, (color, gamma), kind=COLOR)


def _bright_contrast(c, out):
    color, bright, contrast = c.inputs(out, (COLOR, FLOAT, FLOAT))
    return c.b.op(ops.BRIGHT_CONTRAST, 0, (color, bright, contrast), kind=COLOR)


def _map_range(c, out):
    node = out.node
    mode = ops.pack("MAP_RANGE", interpolation_type=node.interpolation_type, clamp=node.clamp)
    if node.data_type == "FLOAT":
        value = c.input(out, ("Value",), FLOAT)
        bounds = [
            c.input(out, (name,), FLOAT) for name in ("From Min", "From Max", "To Min", "To Max")
        ]
        steps = c.input(out, ("Steps",), FLOAT)
        packed = c.b.pack(*bounds)
        return c.b.op(ops.MAP_RANGE, mode, (value, packed, steps), kind=FLOAT)
    if node.data_type == "FLOAT_VECTOR":
        value = c.input(out, ("Vector",), VECTOR)
        names = ("From_Min_FLOAT3", "From_Max_FLOAT3", "To_Min_FLOAT3", "To_Max_FLOAT3")
        bounds = [c.input(out, (name,), VECTOR) for name in names]
        steps = c.input(out, ("Steps_FLOAT3",), VECTOR)
        parts = []
        for k in range(3):
            packed = c.b.pack(*(c.b.swizzle(bound, k) for bound in bounds))
            component = c.b.swizzle(value, k)
            parts.append(c.b.op(ops.MAP_RANGE, mode, (component, packed, c.b.swizzle(steps, k))))
        return c.b.pack(*parts)
    c.warn(node, f"{node.data_type} map range is not supported")
    return None


def _clamp(c, out):
    node = out.node
    value = c.input(out, ("Value",), FLOAT)
    low = c.input(out, ("Min",), FLOAT)
    high = c.input(out, ("Max",), FLOAT)
    mode = ops.pack("CLAMP", clamp_type=node.clamp_type)
    return c.b.op(ops.CLAMP, mode, (value, low, high), kind=FLOAT)


def _rgb_to_bw(c, out):
    return c.b.luminance(c.input(out, ("Color",), COLOR))


def _mapping(c, out):
    node = out.node
    vector = c.input(out, ("Vector",), VECTOR)
    zero = c.b.const((0.0, 0.0, 0.0), VECTOR)
    location = c.input(out, ("Location",), VECTOR) or zero
    rotation = c.input(out, ("Rotation",), VECTOR) or zero
    scale = c.input(out, ("Scale",), VECTOR) or c.b.const((1.0, 1.0, 1.0), VECTOR)
    mode = ops.pack("MAPPING", vector_type=node.vector_type)
    return c.b.op(ops.MAPPING, mode, (vector, location, rotation, scale), kind=VECTOR)


def _blackbody(c, out):
    # Cycles' node (svm_node_blackbody): the fit's colour (op BLACKBODY, shader/blackbody.h)
    # with each channel clamped at 0; scene linear is Rec.709, so Cycles' rec709_to_rgb is
    # the identity.
    temperature = c.input(out, ("Temperature",), FLOAT)
    colour = c.b.op(ops.BLACKBODY, 0, (temperature,), kind=COLOR)
    return c.b.vmath("MAXIMUM", colour, c.b.const((0.0, 0.0, 0.0), COLOR), kind=COLOR)


def _wavelength(c, out):
    # Cycles' node: the CIE matching functions at the wavelength (nm) to Rec.709, scaled by
    # 1 / 2.52 and clamped at 0 (op WAVELENGTH, shader/wavelength.h).
    nanometres = c.input(out, ("Wavelength",), FLOAT)
    return c.b.op(ops.WAVELENGTH, 0, (nanometres,), kind=COLOR)


def _vector_rotate(c, out):
    node = out.node
    vector = c.input(out, ("Vector",), VECTOR)
    center = c.input(out, ("Center",), VECTOR)
    # The Euler type turns by Rotation; the others by Angle, Axis Angle about Axis.
    if node.rotation_type == "EULER_XYZ":
        rotation = c.input(out, ("Rotation",), VECTOR)
        angle = c.b.f(0.0)
    else:
        rotation = c.input(out, ("Axis",), VECTOR) or c.b.const((0.0, 0.0, 1.0), VECTOR)
        angle = c.input(out, ("Angle",), FLOAT)
    mode = ops.pack("VECTOR_ROTATE", rotation_type=node.rotation_type, invert=node.invert)
    return c.b.op(ops.VECTOR_ROTATE, mode, (vector, center, rotation, angle), kind=VECTOR)


def _separate_rgb(c, out):
    return _separate(c, out, "RGB", ("Image", "Color"))


def _separate_xyz(c, out):
    value = c.input(out, ("Vector",), VECTOR)
    return c.b.swizzle(value, output_index(out))


def _separate_hsv(c, out):
    return _separate(c, out, "HSV", ("Color",))


CONVERTER_NODES = {
    "ShaderNodeMath": _math,
    "ShaderNodeVectorMath": _vector_math,
    "ShaderNodeSeparateColor": _separate_color,
    "ShaderNodeSeparateRGB": _separate_rgb,
    "ShaderNodeSeparateXYZ": _separate_xyz,
    "ShaderNodeSeparateHSV": _separate_hsv,
    "ShaderNodeCombineColor": _combine_color,
    "ShaderNodeCombineRGB": lambda c, out: _combine(c, out, "RGB", COLOR),
    "ShaderNodeCombineXYZ": lambda c, out: _combine(c, out, "RGB", VECTOR),
    "ShaderNodeCombineHSV": lambda c, out: _combine(c, out, "HSV", COLOR),
    "ShaderNodeMixRGB": _mix_rgb,
    "ShaderNodeMix": _mix,
    "ShaderNodeValToRGB": _ramp,
    "ShaderNodeRGBCurve": _rgb_curves,
    "ShaderNodeFloatCurve": _float_curve,
    "ShaderNodeVectorCurve": _vector_curves,
    "ShaderNodeInvert": _invert,
    "ShaderNodeHueSaturation": _hue_sat,
    "ShaderNodeGamma": _gamma,
    "ShaderNodeBrightContrast": _bright_contrast,
    "ShaderNodeMapRange": _map_range,
    "ShaderNodeClamp": _clamp,
    "ShaderNodeRGBToBW": _rgb_to_bw,
    "ShaderNodeMapping": _mapping,
    "ShaderNodeBlackbody": _blackbody,
    "ShaderNodeWavelength": _wavelength,
    "ShaderNodeVectorRotate": _vector_rotate,
}
