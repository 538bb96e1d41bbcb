"""The texture nodes as Exprs: images and environments (native textures the program
samples), and the procedural textures the program computes (Checker, Gradient, Noise,
Voronoi, Wave, Magic, Brick, Sky, White Noise, Musgrave), each at the coordinates its
Vector input gives."""

import math

import bpy

from ...native import load_native
from .. import ies
from ..texture import INTERPOLATIONS, ImageTextureSpec, image_texture_spec
from . import ops
from .graph import source
from .input_nodes import texture_normal
from .ir import COLOR, FLOAT, VECTOR
from .sockets import find_socket, output_name


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
    projection = ops.pack("IMAGE", projection=node.projection)
    blend = c.b.f(getattr(node, "projection_blend", 0.0))
    image = c.b.op(ops.IMAGE, projection, (vector, blend), e=c.texture(spec), kind=COLOR)
    if output_name(out) == "Alpha":
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
    projection = ops.pack("ENVIRONMENT", projection=node.projection)
    return c.b.op(ops.ENVIRONMENT, projection, (vector,), e=c.texture(spec), kind=COLOR)


def _checker(c, out):
    vector = _vector_input(c, out, default=None) or c.hit(ops.IN_GENERATED)
    color1 = c.input(out, ("Color1",), COLOR)
    color2 = c.input(out, ("Color2",), COLOR)
    scale = c.input(out, ("Scale",), FLOAT)
    checker = c.b.op(ops.CHECKER, 0, (vector, color1, color2, scale), kind=COLOR)
    if output_name(out) in ("Fac", "Factor"):
        return c.b.swizzle(checker, 3)
    return checker


def _gradient(c, out):
    vector = _vector_input(c, out, default=None) or c.hit(ops.IN_GENERATED)
    mode = ops.pack("GRADIENT", gradient_type=out.node.gradient_type)
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
    color = output_name(out) == "Color"
    mode = ops.pack(
        "NOISE",
        dimensions=node.noise_dimensions,
        noise_type=getattr(node, "noise_type", "FBM"),
        normalize=getattr(node, "normalize", True),
        color=color,
    )
    first = c.b.pack(w, scale, detail, roughness)
    second = c.b.pack(lacunarity, offset, gain, distortion)
    noise = c.b.op(ops.NOISE, mode, (vector, first, second), kind=COLOR)
    return noise if color else c.b.swizzle(noise, 3)


def _musgrave(c, out):
    """Blender 3.4-4.0's Musgrave Texture as the NOISE op: Cycles' Musgrave fractals are
    the Noise Texture's types, unnormalised, with roughness = Lacunarity^-Dimension and
    one octave fewer (Musgrave's Detail counts its octaves from 1, Noise's from 0), once
    Cycles' clamps are applied (Dimension and Lacunarity at least 1e-5, Detail in
    [0, 15]). A Detail below 1 is read as 1 (warned where it is the node's own value):
    Cycles scales the single octave by it there."""
    node = out.node
    vector = _texture_vector(c, out)
    w, scale, detail, dimension, lacunarity, offset, gain = _float_inputs(
        c,
        out,
        (("W", 0.0), ("Scale", 5.0), ("Detail", 2.0), ("Dimension", 2.0), ("Lacunarity", 2.0),
         ("Offset", 0.0), ("Gain", 1.0)),
    )  # fmt: skip
    if detail.is_const and detail.value[0] < 1.0:
        c.warn(node, "a Detail below 1 is read as 1")
    floor = c.b.f(1e-5)
    dimension = c.b.maximum(dimension, floor)
    lacunarity = c.b.maximum(lacunarity, floor)
    roughness = c.b.math("POWER", lacunarity, c.b.math("MULTIPLY", dimension, c.b.f(-1.0)))
    octaves = c.b.math("SUBTRACT", c.b.minimum(detail, c.b.f(15.0)), c.b.f(1.0))
    mode = ops.pack(
        "NOISE",
        dimensions=node.musgrave_dimensions,
        noise_type=node.musgrave_type,
        normalize=False,
        color=False,
    )
    first = c.b.pack(w, scale, octaves, roughness)
    second = c.b.pack(lacunarity, offset, gain, c.b.f(0.0))
    return c.b.swizzle(c.b.op(ops.NOISE, mode, (vector, first, second), kind=COLOR), 3)


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
    name = output_name(out)
    # Each feature has its outputs: Distance and Radius a value, Position and W the
    # feature point, Color its cell's; an output the feature lacks is 0 in Cycles.
    wanted = {"Distance": "DISTANCE", "Color": "COLOR", "Position": "POSITION", "W": "POSITION"}
    output = wanted.get(name, "DISTANCE")
    has = {"DISTANCE_TO_EDGE": ("Distance",), "N_SPHERE_RADIUS": ("Radius",)}
    if name not in has.get(feature, ("Distance", "Color", "Position", "W")):
        return c.b.f(0.0)
    mode = ops.pack(
        "VORONOI",
        dimensions=node.voronoi_dimensions,
        feature=feature,
        metric=node.distance,
        integer_hash=_INTEGER_VORONOI_HASH,
        normalize=getattr(node, "normalize", False),
        output=output,
    )
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
    if node.wave_type == "BANDS":
        direction = {"bands_direction": node.bands_direction}
    else:
        direction = {"rings_direction": node.rings_direction}
    mode = ops.pack("WAVE", wave_type=node.wave_type, wave_profile=node.wave_profile, **direction)
    first = c.b.pack(scale, distortion, detail, detail_scale)
    second = c.b.pack(roughness, phase, c.b.f(0.0))
    wave = c.b.op(ops.WAVE, mode, (vector, first, second), kind=FLOAT)
    if output_name(out) == "Color":
        return c.b.pack(wave, wave, wave, c.b.f(1.0), kind=COLOR)
    return wave


def _magic(c, out):
    vector = _texture_vector(c, out)
    scale, distortion = _float_inputs(c, out, (("Scale", 5.0), ("Distortion", 1.0)))
    depth = ops.pack("MAGIC", turbulence_depth=min(max(int(out.node.turbulence_depth), 0), 10))
    magic = c.b.op(ops.MAGIC, depth, (vector, scale, distortion), kind=COLOR)
    if output_name(out) == "Color":
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
    frequencies = ops.pack(
        "BRICK",
        offset_frequency=min(max(node.offset_frequency, 0), 255),
        squash_frequency=min(max(node.squash_frequency, 0), 255),
    )
    first = c.b.pack(scale, size, smooth, bias)
    second = c.b.pack(width, height, c.b.f(node.offset), c.b.f(node.squash))
    brick = c.b.op(ops.BRICK, frequencies, (vector, first, second), kind=VECTOR)
    mortar = c.b.swizzle(brick, 1)
    if output_name(out) != "Color":
        return mortar
    # Color1 to Color2 by the brick's tint, then to the mortar colour by the mortar.
    bricks = c.b.vlerp(c.b.swizzle(brick, 0), color1, color2)
    return c.b.vlerp(mortar, bricks, mortar_color)


def _white_noise(c, out):
    # Cycles' node: hashes of the input's float bits. Its Vector has no default link
    # (unlike the other textures): unlinked, it is the socket's own value.
    node = out.node
    vector = c.input(out, ("Vector",), VECTOR) or c.b.const((0.0, 0.0, 0.0), VECTOR)
    w = c.input(out, ("W",), FLOAT) or c.b.f(0.0)
    color = output_name(out) == "Color"
    mode = ops.pack("WHITE_NOISE", dimensions=node.noise_dimensions, color=color)
    noise = c.b.op(ops.WHITE_NOISE, mode, (vector, w), kind=COLOR if color else FLOAT)
    return noise if color else c.b.swizzle(noise, 3)


def _gabor(c, out):
    # Blender 4.3's Gabor Texture (native shader/gabor.cpp): Orientation is an angle in
    # 2D, a direction in 3D (identifiers "Orientation 2D" and "Orientation 3D").
    node = out.node
    vector = _texture_vector(c, out)
    scale, frequency, anisotropy = _float_inputs(
        c, out, (("Scale", 5.0), ("Frequency", 2.0), ("Anisotropy", 1.0))
    )
    if node.gabor_type == "2D":
        orientation = c.input(out, ("Orientation 2D",), FLOAT) or c.b.f(math.pi / 4.0)
    else:
        default = c.b.const((math.sqrt(2.0), math.sqrt(2.0), 0.0), VECTOR)
        orientation = c.input(out, ("Orientation 3D",), VECTOR) or default
    mode = ops.pack("GABOR", gabor_type=node.gabor_type, output=output_name(out).upper())
    return c.b.op(ops.GABOR, mode, (vector, scale, frequency, anisotropy, orientation))


# Cycles 4.0+ looks an IES profile up along the incoming direction (from the lamp to the
# lit point), 3.x along the Texture Coordinate's Normal: the same for a point or spot lamp,
# the lamp's own normal for an area lamp. Both in the lamp's object space, as a normal.
# And 4.0+ treats the table's edges otherwise (native shader/ies.h); 4.x is read as 5.0
# (not measured).
_IES_ALONG_INCOMING = bpy.app.version >= (4, 0, 0)
_IES_EDGES = "BOUNDS" if _IES_ALONG_INCOMING else "LEGACY"

# What Cycles' IES node gives per unit Strength where it has no profile (a missing or
# unreadable file): its lookup's fallback.
IES_WITHOUT_PROFILE = 100.0


def _ies(c, out):
    node = out.node
    strength = c.input(out, ("Strength",), FLOAT) or c.b.f(1.0)
    profile, why = _ies_profile(node)
    if profile is None:
        c.warn(node, f"{why}; it gives {IES_WITHOUT_PROFILE:g} x Strength, as in Cycles")
        return c.b.mul(strength, c.b.f(IES_WITHOUT_PROFILE))
    vector = _vector_input(c, out, default=None)
    if vector is None and _IES_ALONG_INCOMING and c.lamp_matrix is not None:
        vector = c.in_lamp_space(c.hit(ops.IN_INCOMING))
    elif vector is None:
        # The Texture Coordinate's Normal (Cycles 3.x's default); outside a lamp Cycles
        # 4.0+ takes the object-space incoming direction, which no surface program reads.
        if _IES_ALONG_INCOMING:
            c.warn(node, "outside a lamp its Vector is the Texture Coordinate's Normal")
        vector = texture_normal(c)
    if profile.type_b and _IES_ALONG_INCOMING:
        c.warn(node, "a type B profile is read as Cycles 3.x reads it; Cycles 4.0+ turns it "
               "otherwise (not followed)")  # fmt: skip
    mode = ops.pack("IES", edges=_IES_EDGES)
    return c.b.op(ops.IES, mode, (vector, strength), e=tuple(profile.table), kind=FLOAT)


def _ies_profile(node):
    """(its ies.Profile, None) of an IES Texture node (its Text block, or its file,
    relative to the blend file or its library), or (None, why not)."""
    if node.mode == "INTERNAL":
        if node.ies is None:
            return None, "no IES text"
        text, where = node.ies.as_string(), f"text '{node.ies.name}'"
    else:
        path = bpy.path.abspath(node.filepath, library=node.id_data.library)
        try:
            with open(path, encoding="latin-1") as f:
                text = f.read()
        except OSError as error:
            return None, f"IES file '{node.filepath}' cannot be read ({error.strerror})"
        where = f"file '{node.filepath}'"
    profile = ies.parse(text)
    if profile is None:
        return None, f"IES {where} holds no type B or C profile Cycles reads"
    return profile, None


def _texture_mapping(c, node, vector):
    """`vector` through the node's own Texture Mapping (its sidebar's Location, Rotation
    and Scale, as a Mapping node of its Vector Type); min/max clipping and axis remaps
    are not applied (warned)."""
    mapping = node.texture_mapping
    axes = (mapping.mapping_x, mapping.mapping_y, mapping.mapping_z)
    if mapping.use_min or mapping.use_max or axes != ("X", "Y", "Z"):
        c.warn(node, "its Texture Mapping's clipping and axis remapping are not applied")
    identity = (tuple(mapping.translation), tuple(mapping.rotation), tuple(mapping.scale)) == (
        (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0))  # fmt: skip
    if identity:
        return vector
    mode = ops.pack("MAPPING", vector_type=mapping.vector_type)
    location = c.b.const(tuple(mapping.translation), VECTOR)
    rotation = c.b.const(tuple(mapping.rotation), VECTOR)
    scale = c.b.const(tuple(mapping.scale), VECTOR)
    return c.b.op(ops.MAPPING, mode, (vector, location, rotation, scale), kind=VECTOR)


def _sky(c, out):
    """Blender's Sky Texture (native shader/sky.h). Perez/Preetham and Hosek/Wilkie
    analytic from Sun Direction and Turbidity (and Ground Albedo); Nishita (3.x/4.x) and
    5.x's Single and Multiple Scattering a table built natively here."""
    node = out.node
    native = load_native()
    vector = _texture_mapping(c, node, _texture_vector(c, out))
    model = node.sky_type
    if model in ("PREETHAM", "HOSEK_WILKIE"):
        sun = tuple(node.sun_direction)
        norm = math.sqrt(sum(x * x for x in sun)) or 1.0
        sun = tuple(x / norm for x in sun)
        if model == "PREETHAM":
            table = native.preetham_table(sun, node.turbidity)
        else:
            table = native.hosek_wilkie_table(sun, node.turbidity, node.ground_albedo)
        mode = ops.pack("SKY", model=model)
    else:
        dust = getattr(node, "aerosol_density", None)
        if dust is None:
            dust = node.dust_density
        elevation, rotation = _sun_position(node.sun_elevation, node.sun_rotation)
        table = native.scattering_table(
            elevation, rotation, node.sun_disc, node.sun_size, node.sun_intensity,
            node.altitude, node.air_density, dust, node.ozone_density, model,
        )  # fmt: skip
        mode = ops.pack("SKY", model="SINGLE_SCATTERING")
        half = node.sun_size / 2.0
        if node.sun_disc and node.sun_intensity > 0.0 and elevation + half > 0.0:
            c.suns.append((vector, native.sun_direction(elevation, rotation), node.sun_size))
    table = tuple(float(x) for x in table)
    return c.b.op(ops.SKY, mode, (vector,), e=table, kind=COLOR)


def _sun_position(elevation, rotation):
    """Sun Elevation and Rotation as the sky draws them: an elevation past the zenith
    (or below the nadir) is the same position seen from the other side, as Cycles
    folds it into [-pi/2, pi/2] with the rotation turned half way."""
    elevation = math.remainder(elevation, 2.0 * math.pi)
    if abs(elevation) > math.pi / 2.0:
        elevation = math.copysign(math.pi, elevation) - elevation
        rotation += math.pi
    return elevation, rotation


TEXTURE_NODES = {
    "ShaderNodeTexImage": _image,
    "ShaderNodeTexEnvironment": _environment,
    "ShaderNodeTexChecker": _checker,
    "ShaderNodeTexGradient": _gradient,
    "ShaderNodeTexNoise": _noise,
    "ShaderNodeTexVoronoi": _voronoi,
    "ShaderNodeTexWave": _wave,
    "ShaderNodeTexMagic": _magic,
    "ShaderNodeTexBrick": _brick,
    "ShaderNodeTexSky": _sky,
    "ShaderNodeTexWhiteNoise": _white_noise,
    "ShaderNodeTexMusgrave": _musgrave,
    "ShaderNodeTexGabor": _gabor,
    "ShaderNodeTexIES": _ies,
}
