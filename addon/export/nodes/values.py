"""Lowering the value nodes of a graph (textures, maths, colours, coordinates) to
Exprs (ir.py): `Lowering.value(socket, scope, kind)` is the value Blender would
feed `socket`, as an Expr of `kind`.

A node the program has no op for is warned once, by name, and the socket it
feeds takes its own unlinked value, as if the link were not there.
"""

from dataclasses import dataclass, field

import bpy

from ..texture import INTERPOLATIONS, ImageTextureSpec, image_texture_spec
from . import ops
from . import warn as _warn
from .graph import socket_id, socket_type, source
from .ir import COLOR, FLOAT, VECTOR, Builder
from .normals import bump as _bump

_KINDS = {"VALUE": FLOAT, "INT": FLOAT, "BOOLEAN": FLOAT, "RGBA": COLOR, "VECTOR": VECTOR}

# Procedural textures the program does not compute (named in their warning).
PROCEDURALS = {
    "ShaderNodeTexMusgrave": "Musgrave Texture",
    "ShaderNodeTexWhiteNoise": "White Noise Texture",
    "ShaderNodeTexSky": "Sky Texture",
    "ShaderNodeTexGabor": "Gabor Texture",
}


def kind_of(socket):
    return _KINDS.get(socket_type(socket), FLOAT)


@dataclass
class Needs:
    """What a material's program reads from the mesh and the instance."""

    uv_maps: list = field(default_factory=list)  # UV map names; "" = the active render map
    attributes: list = field(default_factory=list)  # ("COLOR" | "ATTRIBUTE", name)
    tangents: set = field(default_factory=set)  # UV set indices normal maps read
    object_info: bool = False

    def uv_set(self, name):
        if name not in self.uv_maps:
            self.uv_maps.append(name)
        return self.uv_maps.index(name)

    def attribute(self, key):
        if key not in self.attributes:
            self.attributes.append(key)
        return self.attributes.index(key)


class Lowering:
    """One material's (or world's) lowering: the Builder, the warnings, the textures
    and the per-hit data its program reads."""

    def __init__(self, owner, warnings, world=False):
        self.owner = owner  # "material 'Name'" or "world 'Name'"
        self.warnings = warnings
        self.world = world
        self.b = Builder()
        self.needs = Needs()
        self.textures = {}  # name -> ImageTextureSpec
        self._outputs = {}  # Output.key -> Expr
        self._active = set()

    def warn(self, node, message):
        _warn(self.warnings, f"Whitted: {self.owner}, node '{node.name}': {message}")

    # --- sockets ---------------------------------------------------------------

    def value(self, socket, scope, kind=None, consumer=None):
        """The Expr Blender feeds input `socket` (of a node inside `scope`)."""
        kind = kind or kind_of(socket)
        output, used = source(socket, scope)
        if output is not None:
            expr = self.output(output, consumer or (socket, scope))
            if expr is not None:
                return self.convert(expr, kind)
        return self.default(used, kind)

    def default(self, socket, kind):
        value = getattr(socket, "default_value", None)
        if value is None:
            return self.b.const(0.0, kind) if kind == FLOAT else self.b.const((0.0,) * 3, kind)
        if isinstance(value, (int, float, bool)):
            return self.convert(self.b.f(float(value)), kind)
        value = tuple(value)
        expr = self.b.const(value, COLOR if len(value) == 4 else VECTOR)
        return self.convert(expr, kind)

    def convert(self, expr, kind):
        """Blender's implicit conversions: colour -> float is its luminance, vector ->
        float the mean of its components; a float becomes all components."""
        if kind == FLOAT and expr.kind == COLOR:
            return self.b.luminance(expr)
        if kind == FLOAT and expr.kind == VECTOR:
            return self.b.average(expr)
        return expr

    def input(self, output, names, kind=None):
        """The value of the input of `output.node` with one of `names` (identifier
        or name, newest first); None when the node has no such input."""
        socket = find_socket(output.node.inputs, names)
        if socket is None:
            return None
        return self.value(socket, output.scope, kind)

    def inputs(self, output, kinds):
        """The node's enabled inputs in order, as Exprs of `kinds` (one per input)."""
        sockets = [s for s in output.node.inputs if getattr(s, "enabled", True)]
        return [self.value(s, output.scope, k) for s, k in zip(sockets, kinds, strict=False)]

    def output(self, output, consumer):
        """The Expr of a node output; None (with a warning) when not supported."""
        key = output.key
        if key in self._outputs:
            return self._outputs[key]
        if key in self._active:
            self.warn(output.node, "is part of a cycle; it is ignored")
            return None
        self._active.add(key)
        try:
            handler = _NODES.get(output.node.bl_idname)
            expr = self._unsupported(output, consumer) if handler is None else handler(self, output)
        finally:
            self._active.discard(key)
        self._outputs[key] = expr
        return expr

    def _unsupported(self, output, consumer):
        node = output.node
        socket, _ = consumer
        fed = getattr(socket, "node", None)
        where = f" of '{fed.name}'" if fed is not None and fed is not node else ""
        what = PROCEDURALS.get(node.bl_idname, node.bl_idname)
        self.warn(
            node,
            f"{what} is not supported; input '{socket.name}'{where} uses its unlinked value",
        )
        return None

    # --- per-hit inputs ----------------------------------------------------------

    def hit(self, mode, kind=VECTOR):
        return self.b.op(ops.INPUT, mode, (), kind=kind)

    def uv(self, name=""):
        if self.world:
            return self.hit(ops.IN_GENERATED)
        return self.hit(ops.IN_UV + self.needs.uv_set(name))

    def texture(self, spec):
        self.textures[spec.name] = spec
        return spec.name


def find_socket(sockets, names, enabled_only=True):
    """The first socket whose identifier or name is one of `names`, in order (only
    enabled ones unless `enabled_only` is False: Blender hides the operands an
    operation does not use)."""
    for name in names:
        for socket in sockets:
            if (not enabled_only or getattr(socket, "enabled", True)) and (
                socket_id(socket) == name or socket.name == name
            ):
                return socket
    return None


def _output_name(output):
    return output.socket.name


def _output_index(output):
    identifier = socket_id(output.socket)
    return next(i for i, s in enumerate(output.node.outputs) if socket_id(s) == identifier)


# --- node handlers: (Lowering, Output) -> Expr or None --------------------------


def _value(c, out):
    return c.b.f(out.socket.default_value)


def _rgb(c, out):
    return c.b.const(tuple(out.socket.default_value), COLOR)


def _image(c, out):
    node = out.node
    spec = image_texture_spec(node, c.owner, c.warnings)
    if spec is None:
        c.warn(node, "no image; the input it feeds uses its unlinked value")
        return None
    # The program gives the coordinates; one native texture per image and sampling.
    vector = _vector_input(c, out, default=None)
    if vector is None:
        vector = c.uv("")
    projection = ops.IMAGE_PROJECTIONS.index(node.projection)
    blend = c.b.f(getattr(node, "projection_blend", 0.0))
    image = c.b.op(ops.IMAGE, projection, (vector, blend), e=c.texture(spec), kind=COLOR)
    if _output_name(out) == "Alpha":
        return c.b.swizzle(image, 3)
    return image


def _vector_input(c, out, default):
    socket = find_socket(out.node.inputs, ("Vector",))
    if socket is None:
        return default
    output, _ = source(socket, out.scope)
    if output is None:
        return default
    return c.value(socket, out.scope, VECTOR)


def _environment(c, out):
    node = out.node
    if node.image is None:
        c.warn(node, "no image; the input it feeds uses its unlinked value")
        return None
    interpolation = INTERPOLATIONS.get(node.interpolation, "LINEAR")
    spec = ImageTextureSpec(node.image.original, interpolation, "REPEAT", "UV", "")
    vector = _vector_input(c, out, default=None)
    if vector is None:
        vector = c.hit(ops.IN_POSITION)
    projection = ops.ENVIRONMENT_PROJECTIONS.index(node.projection)
    return c.b.op(ops.ENVIRONMENT, projection, (vector,), e=c.texture(spec), kind=COLOR)


def _checker(c, out):
    vector = _vector_input(c, out, default=None) or c.hit(ops.IN_GENERATED)
    color1 = c.input(out, ("Color1",), COLOR)
    color2 = c.input(out, ("Color2",), COLOR)
    scale = c.input(out, ("Scale",), FLOAT)
    checker = c.b.op(ops.CHECKER, 0, (vector, color1, color2, scale), kind=COLOR)
    if _output_name(out) in ("Fac", "Factor"):
        return c.b.swizzle(checker, 3)
    return checker


def _gradient(c, out):
    vector = _vector_input(c, out, default=None) or c.hit(ops.IN_GENERATED)
    mode = ops.GRADIENT_TYPES.index(out.node.gradient_type)
    return c.b.op(ops.GRADIENT, mode, (vector,), kind=FLOAT)


def _texture_vector(c, out):
    """A texture's Vector: its link, else the Generated coordinates (as Cycles)."""
    return _vector_input(c, out, default=None) or c.hit(ops.IN_GENERATED)


# Blender before 4.0 has one fractal of its own for the Noise Texture and the Wave's
# detail: fBM of lacunarity 2, normalised, its roughness clamped to [0, 1]. Its Noise
# node has no Lacunarity socket; the Wave node has nothing to tell, hence the version.
_LEGACY_FRACTAL = bpy.app.version < (4, 0, 0)
# Blender 5.0 hashes the 2D-4D Voronoi cells by their integer coordinates (PCG), 3.4 by
# their float bits; nothing on the node tells (4.x is read as 3.4: not measured).
_INTEGER_VORONOI_HASH = bpy.app.version >= (5, 0, 0)


def _float_inputs(c, out, defaults):
    """The node's FLOAT inputs by name; a disabled or missing one is its default."""
    values = []
    for name, default in defaults:
        value = c.input(out, (name,), FLOAT)
        values.append(c.b.f(default) if value is None else value)
    return values


def _noise(c, out):
    node = out.node
    vector = _texture_vector(c, out)
    w, scale, detail, roughness, offset, gain, distortion = _float_inputs(
        c,
        out,
        (("W", 0.0), ("Scale", 5.0), ("Detail", 2.0), ("Roughness", 0.5), ("Offset", 0.0),
         ("Gain", 1.0), ("Distortion", 0.0)),
    )  # fmt: skip
    lacunarity = c.input(out, ("Lacunarity",), FLOAT)
    if lacunarity is None:  # Blender 3.x: the legacy fractal
        lacunarity = c.b.f(2.0)
        roughness = c.b.clamp01(roughness)
    mode = ops.DIMENSIONS.index(node.noise_dimensions)
    mode |= ops.NOISE_TYPES.index(getattr(node, "noise_type", "FBM")) << 2
    mode |= ops.NOISE_NORMALIZE if getattr(node, "normalize", True) else 0
    color = _output_name(out) == "Color"
    mode |= ops.NOISE_COLOR if color else 0
    first = c.b.pack(w, scale, detail, roughness)
    second = c.b.pack(lacunarity, offset, gain, distortion)
    noise = c.b.op(ops.NOISE, mode, (vector, first, second), kind=COLOR)
    return noise if color else c.b.swizzle(noise, 3)


def _voronoi(c, out):
    node = out.node
    vector = _texture_vector(c, out)
    w, scale, detail, roughness, lacunarity, smoothness, exponent, randomness = _float_inputs(
        c,
        out,
        (("W", 0.0), ("Scale", 5.0), ("Detail", 0.0), ("Roughness", 0.5), ("Lacunarity", 2.0),
         ("Smoothness", 1.0), ("Exponent", 0.5), ("Randomness", 1.0)),
    )  # fmt: skip
    feature = node.feature
    name = _output_name(out)
    # Each feature has its outputs: Distance and Radius a value, Position and W the
    # feature point, Color its cell's; an output the feature lacks is 0 in Cycles.
    wanted = {"Distance": "DISTANCE", "Color": "COLOR", "Position": "POSITION", "W": "POSITION"}
    output = wanted.get(name, "DISTANCE")
    has = {"DISTANCE_TO_EDGE": ("Distance",), "N_SPHERE_RADIUS": ("Radius",)}
    if name not in has.get(feature, ("Distance", "Color", "Position", "W")):
        return c.b.f(0.0)
    mode = ops.DIMENSIONS.index(node.voronoi_dimensions)
    mode |= ops.VORONOI_FEATURES.index(feature) << 2
    mode |= ops.VORONOI_METRICS.index(node.distance) << 5
    mode |= ops.NOISE_NORMALIZE if getattr(node, "normalize", False) else 0
    mode |= ops.VORONOI_INTEGER_HASH if _INTEGER_VORONOI_HASH else 0
    mode |= ops.VORONOI_OUTPUTS.index(output) << 9
    first = c.b.pack(w, scale, detail, roughness)
    second = c.b.pack(lacunarity, smoothness, exponent, randomness)
    kind = {"COLOR": COLOR, "POSITION": VECTOR}.get(output, FLOAT)
    voronoi = c.b.op(ops.VORONOI, mode, (vector, first, second), kind=kind)
    return c.b.swizzle(voronoi, 3) if name == "W" else voronoi


def _wave(c, out):
    node = out.node
    vector = _texture_vector(c, out)
    scale, distortion, detail, detail_scale, roughness, phase = _float_inputs(
        c,
        out,
        (("Scale", 5.0), ("Distortion", 0.0), ("Detail", 2.0), ("Detail Scale", 1.0),
         ("Detail Roughness", 0.5), ("Phase Offset", 0.0)),
    )  # fmt: skip
    if _LEGACY_FRACTAL:
        roughness = c.b.clamp01(roughness)
    kind = ops.WAVE_TYPES.index(node.wave_type)
    if kind == 0:
        direction = ops.WAVE_BANDS_DIRECTIONS.index(node.bands_direction)
    else:
        direction = ops.WAVE_RINGS_DIRECTIONS.index(node.rings_direction)
    mode = kind | direction << 1 | ops.WAVE_PROFILES.index(node.wave_profile) << 3
    first = c.b.pack(scale, distortion, detail, detail_scale)
    second = c.b.pack(roughness, phase, c.b.f(0.0))
    wave = c.b.op(ops.WAVE, mode, (vector, first, second), kind=FLOAT)
    if _output_name(out) == "Color":
        return c.b.pack(wave, wave, wave, c.b.f(1.0), kind=COLOR)
    return wave


def _magic(c, out):
    vector = _texture_vector(c, out)
    scale, distortion = _float_inputs(c, out, (("Scale", 5.0), ("Distortion", 1.0)))
    depth = min(max(int(out.node.turbulence_depth), 0), 10)
    magic = c.b.op(ops.MAGIC, depth, (vector, scale, distortion), kind=COLOR)
    if _output_name(out) == "Color":
        return magic
    return c.b.swizzle(magic, 3)


def _brick(c, out):
    node = out.node
    vector = _texture_vector(c, out)
    color1 = c.input(out, ("Color1",), COLOR)
    color2 = c.input(out, ("Color2",), COLOR)
    mortar_color = c.input(out, ("Mortar",), COLOR)
    scale, size, smooth, bias, width, height = _float_inputs(
        c,
        out,
        (("Scale", 5.0), ("Mortar Size", 0.02), ("Mortar Smooth", 0.1), ("Bias", 0.0),
         ("Brick Width", 0.5), ("Row Height", 0.25)),
    )  # fmt: skip
    frequencies = (
        min(max(node.offset_frequency, 0), 255) | min(max(node.squash_frequency, 0), 255) << 8
    )
    first = c.b.pack(scale, size, smooth, bias)
    second = c.b.pack(width, height, c.b.f(node.offset), c.b.f(node.squash))
    brick = c.b.op(ops.BRICK, frequencies, (vector, first, second), kind=VECTOR)
    mortar = c.b.swizzle(brick, 1)
    if _output_name(out) != "Color":
        return mortar
    # Color1 to Color2 by the brick's tint, then to the mortar colour by the mortar.
    bricks = c.b.vlerp(c.b.swizzle(brick, 0), color1, color2)
    return c.b.vlerp(mortar, bricks, mortar_color)


def _uv_map(c, out):
    return c.uv(out.node.uv_map)


_TEX_COORD = {
    "Generated": ops.IN_GENERATED,
    "Normal": ops.IN_NORMAL,
    "Object": ops.IN_OBJECT,
    "Camera": ops.IN_CAMERA,
    "Window": ops.IN_WINDOW,
    "Reflection": ops.IN_REFLECTION,
}


def _tex_coord(c, out):
    name = _output_name(out)
    if name == "UV":
        return c.uv("")
    if getattr(out.node, "object", None) is not None and name == "Object":
        c.warn(out.node, "Object coordinates of another object are not supported; its own")
    if name == "Normal" and not c.world:
        # Cycles' Normal output is the shading normal in object space.
        return c.hit(ops.IN_OBJECT_NORMAL)
    if name == "Camera" and not c.world:
        # INPUT 6 is Blender's camera space (looking down -Z); Cycles' Camera output
        # looks down +Z.
        flip = c.b.const((1.0, 1.0, -1.0), VECTOR)
        return c.b.vmul(c.hit(ops.IN_CAMERA), flip, VECTOR)
    return c.hit(_TEX_COORD[name])


_GEOMETRY = {
    "Position": (ops.IN_POSITION, VECTOR),
    "Normal": (ops.IN_NORMAL, VECTOR),
    "True Normal": (ops.IN_TRUE_NORMAL, VECTOR),
    "Incoming": (ops.IN_INCOMING, VECTOR),
    "Backfacing": (ops.IN_BACKFACING, FLOAT),
}


def _geometry(c, out):
    entry = _GEOMETRY.get(_output_name(out))
    if entry is None:
        c.warn(out.node, f"output '{_output_name(out)}' is not supported; it gives 0")
        return c.b.f(0.0)
    return c.hit(entry[0], entry[1])


_LIGHT_PATH = {
    "Is Camera Ray": ops.IN_IS_CAMERA_RAY,
    "Is Shadow Ray": ops.IN_IS_SHADOW_RAY,
    "Is Diffuse Ray": ops.IN_IS_DIFFUSE_RAY,
    "Is Glossy Ray": ops.IN_IS_REFLECTION_RAY,
    "Is Singular Ray": ops.IN_IS_SINGULAR_RAY,
    "Is Reflection Ray": ops.IN_IS_REFLECTION_RAY,
    "Is Transmission Ray": ops.IN_IS_TRANSMISSION_RAY,
    "Ray Depth": ops.IN_RAY_DEPTH,
    # Every bounce of a Whitted tracer is singular: glossy and transmission depths
    # are the ray depth, and no ray is diffuse or transparent.
    "Glossy Depth": ops.IN_RAY_DEPTH,
    "Transmission Depth": ops.IN_RAY_DEPTH,
}


def _light_path(c, out):
    name = _output_name(out)
    mode = _LIGHT_PATH.get(name)
    if mode is None:
        if name not in ("Diffuse Depth", "Transparent Depth", "Is Volume Scatter Ray"):
            c.warn(out.node, f"output '{name}' is not supported; it gives 0")
        return c.b.f(0.0)
    if name in ("Glossy Depth", "Transmission Depth"):
        c.warn(out.node, f"'{name}' is approximated by the ray depth")
    return c.hit(mode, FLOAT)


def _object_info(c, out):
    name = _output_name(out)
    c.needs.object_info = True
    if name == "Location":
        return c.hit(ops.IN_OBJECT_LOCATION)
    if name == "Random":
        return c.hit(ops.IN_OBJECT_RANDOM, FLOAT)
    if name in ("Object Index", "Pass Index"):
        return c.hit(ops.IN_OBJECT_INDEX, FLOAT)
    if name == "Color":
        return c.hit(ops.IN_OBJECT_COLOR, COLOR)
    if name == "Alpha":
        return c.b.swizzle(c.hit(ops.IN_OBJECT_COLOR, COLOR), 3)
    c.warn(out.node, f"output '{name}' is not supported; it gives 0")
    return c.b.f(0.0)


def _attribute_value(c, out, key):
    if c.world:
        c.warn(out.node, "attributes are not available in the world; 0")
        return c.b.f(0.0)
    value = c.hit(ops.IN_ATTRIBUTE + c.needs.attribute(key), COLOR)
    name = _output_name(out)
    if name == "Alpha":
        return c.b.swizzle(value, 3)
    if name in ("Fac", "Factor"):
        # Float attributes are exported in all of rgb, so the mean is the value.
        return c.b.average(value)
    return value


def _vertex_color(c, out):
    return _attribute_value(c, out, ("COLOR", out.node.layer_name))


def _attribute(c, out):
    node = out.node
    if node.attribute_type != "GEOMETRY":
        c.warn(node, f"{node.attribute_type} attributes are not supported; 0")
        return c.b.f(0.0)
    return _attribute_value(c, out, ("ATTRIBUTE", node.attribute_name))


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
    if _output_name(out) == "Value":
        return result if is_value else c.b.f(0.0)
    return c.b.const((0.0, 0.0, 0.0), VECTOR) if is_value else result


def _separate(c, out, mode, input_names):
    value = c.input(out, input_names, COLOR)
    if mode:
        value = c.b.op(ops.SEPARATE, mode, (value,), kind=COLOR)
    return c.b.swizzle(value, _output_index(out))


def _separate_color(c, out):
    mode = {"RGB": 0, "HSV": 1, "HSL": 2}[out.node.mode]
    return _separate(c, out, mode, ("Color",))


def _combine(c, out, mode, kind):
    x, y, z = (c.value(s, out.scope, FLOAT) for s in list(out.node.inputs)[:3])
    return c.b.op(ops.COMBINE, mode, (x, y, z), kind=kind)


def _combine_color(c, out):
    return _combine(c, out, {"RGB": 0, "HSV": 1, "HSL": 2}[out.node.mode], COLOR)


def _mix_rgb(c, out):
    node = out.node
    factor = c.b.clamp01(c.input(out, ("Fac", "Factor"), FLOAT))
    color1 = c.input(out, ("Color1",), COLOR)
    color2 = c.input(out, ("Color2",), COLOR)
    return _mix_blend(c, node.blend_type, factor, color1, color2, node.use_clamp)


def _mix_blend(c, blend, factor, color1, color2, clamp):
    if blend == "MIX" and not clamp:
        return c.b.vlerp(factor, color1, color2, COLOR)
    mode = ops.mix_blend(blend) | (ops.CLAMP_BIT if clamp else 0)
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
            return c.b.op(ops.MIX_VALUE, 2, (factor, a, b), kind=VECTOR)
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


def _ramp(c, out):
    node = out.node
    ramp = node.color_ramp
    if ramp.color_mode != "RGB":
        c.warn(node, f"{ramp.color_mode} colour ramp interpolation is approximated in RGB")
    factor = c.input(out, ("Fac", "Factor"), FLOAT)
    table = [float(len(ramp.elements))]
    for element in ramp.elements:
        table += [float(element.position), *map(float, element.color)]
    mode = ops.RAMP_MODES.index(ramp.interpolation)
    color = c.b.op(ops.COLOR_RAMP, mode, (factor,), e=tuple(table), kind=COLOR)
    if _output_name(out) == "Alpha":
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
    mapped = c.b.op(ops.CURVE, _curve_mode(node, 2), (c.b.f(1.0), place), e=table, kind=VECTOR)
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
    return c.b.op(ops.CURVE, _curve_mode(node, 0), (factor, color), e=table, kind=COLOR)


def _curve_mode(node, kind):
    # CURVE's bit 8: extend the curves along their end slopes (Extend: Extrapolated).
    extrapolated = getattr(node.mapping, "extend", "HORIZONTAL") == "EXTRAPOLATED"
    return kind | (ops.CLAMP_BIT if extrapolated else 0)


def _float_curve(c, out):
    factor = c.input(out, ("Factor", "Fac"), FLOAT)
    value = c.input(out, ("Value",), FLOAT)
    table = curve_table(out.node.mapping, (0, None, None, None))
    return c.b.op(ops.CURVE, _curve_mode(out.node, 1), (factor, value), e=table, kind=FLOAT)


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
    mode = ops.MAP_RANGE_MODES.index(node.interpolation_type)
    mode |= ops.CLAMP_BIT if node.clamp else 0
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
    mode = 1 if node.clamp_type == "RANGE" else 0
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
    mode = ops.MAPPING_TYPES.index(node.vector_type)
    return c.b.op(ops.MAPPING, mode, (vector, location, rotation, scale), kind=VECTOR)


def _fresnel(c, out):
    ior = c.input(out, ("IOR",), FLOAT)
    _warn_linked_normal(c, out)
    return c.b.op(ops.FRESNEL, 0, (ior,), kind=FLOAT)


def _layer_weight(c, out):
    blend = c.input(out, ("Blend",), FLOAT)
    _warn_linked_normal(c, out)
    mode = 0 if _output_name(out) == "Fresnel" else 1
    return c.b.op(ops.LAYER_WEIGHT, mode, (blend,), kind=FLOAT)


def _warn_linked_normal(c, out):
    socket = find_socket(out.node.inputs, ("Normal",))
    if socket is not None and source(socket, out.scope)[0] is not None:
        c.warn(out.node, "a linked Normal is not supported; the shading normal is used")


def _normal_map(c, out):
    node = out.node
    strength = c.input(out, ("Strength",), FLOAT)
    color = c.input(out, ("Color",), COLOR)
    space = node.space
    if space in ("BLENDER_OBJECT", "BLENDER_WORLD"):
        # Blender's own spaces are object/world with y and z negated (2c - 1 -> its
        # negative: c -> 1 - c), as Cycles does.
        one = c.b.const((0.0, 1.0, 1.0), COLOR)
        sign = c.b.const((1.0, -1.0, -1.0), COLOR)
        color = c.b.vadd(c.b.vmul(color, sign), one)
        space = space.removeprefix("BLENDER_")
    if space not in ops.NORMAL_MAP_SPACES:
        c.warn(node, f"{space} normal maps are not supported; the shading normal is used")
        return c.hit(ops.IN_NORMAL)
    uv_set = 0
    if space == "TANGENT":
        uv_set = c.needs.uv_set(node.uv_map)
        c.needs.tangents.add(uv_set)
    return c.b.op(
        ops.NORMAL_MAP, ops.NORMAL_MAP_SPACES.index(space), (strength, color), e=("set", uv_set),
        kind=VECTOR,
    )  # fmt: skip


def _separate_rgb(c, out):
    return _separate(c, out, 0, ("Image", "Color"))


def _separate_xyz(c, out):
    value = c.input(out, ("Vector",), VECTOR)
    return c.b.swizzle(value, _output_index(out))


def _separate_hsv(c, out):
    return _separate(c, out, 1, ("Color",))


_NODES = {
    "ShaderNodeValue": _value,
    "ShaderNodeRGB": _rgb,
    "ShaderNodeTexImage": _image,
    "ShaderNodeTexEnvironment": _environment,
    "ShaderNodeTexChecker": _checker,
    "ShaderNodeTexGradient": _gradient,
    "ShaderNodeTexNoise": _noise,
    "ShaderNodeTexVoronoi": _voronoi,
    "ShaderNodeTexWave": _wave,
    "ShaderNodeTexMagic": _magic,
    "ShaderNodeTexBrick": _brick,
    "ShaderNodeUVMap": _uv_map,
    "ShaderNodeTexCoord": _tex_coord,
    "ShaderNodeNewGeometry": _geometry,
    "ShaderNodeLightPath": _light_path,
    "ShaderNodeObjectInfo": _object_info,
    "ShaderNodeVertexColor": _vertex_color,
    "ShaderNodeAttribute": _attribute,
    "ShaderNodeMath": _math,
    "ShaderNodeVectorMath": _vector_math,
    "ShaderNodeSeparateColor": _separate_color,
    "ShaderNodeSeparateRGB": _separate_rgb,
    "ShaderNodeSeparateXYZ": _separate_xyz,
    "ShaderNodeSeparateHSV": _separate_hsv,
    "ShaderNodeCombineColor": _combine_color,
    "ShaderNodeCombineRGB": lambda c, out: _combine(c, out, 0, COLOR),
    "ShaderNodeCombineXYZ": lambda c, out: _combine(c, out, 0, VECTOR),
    "ShaderNodeCombineHSV": lambda c, out: _combine(c, out, 1, COLOR),
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
    "ShaderNodeFresnel": _fresnel,
    "ShaderNodeLayerWeight": _layer_weight,
    "ShaderNodeNormalMap": _normal_map,
    "ShaderNodeBump": _bump,
}

SUPPORTED_NODES = frozenset(_NODES)
