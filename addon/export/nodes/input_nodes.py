"""The input nodes as Exprs: constants (Value, RGB), what a hit gives (Texture
Coordinate, UV Map, Geometry, Light Path, Light Falloff, Wireframe, Object Info,
attributes and colour attributes), the view-dependent factors (Fresnel, Layer
Weight), Normal Map, Tangent, and Ambient Occlusion and Bevel (rays from and near the
hit)."""

import bpy

from ..properties import view_layer_attribute
from . import ops
from .graph import source
from .ir import COLOR, FLOAT, VECTOR
from .normals import linked_normal
from .sockets import find_socket, output_name


def _value(c, out):
    return c.b.f(out.socket.default_value)


def _rgb(c, out):
    return c.b.const(tuple(out.socket.default_value), COLOR)


def _uv_map(c, out):
    return c.uv(out.node.uv_map)


# The tables below name INPUT modes; ops gives their numbers once the native module is
# loaded (the add-on imports before it: native.py).
_TEX_COORD = {
    "Generated": "IN_GENERATED",
    "Normal": "IN_NORMAL",
    "Object": "IN_OBJECT",
    "Camera": "IN_CAMERA",
    "Window": "IN_WINDOW",
    "Reflection": "IN_REFLECTION",
}


# Whether a lamp's Texture Coordinate Object output is in the lamp's space (4.0+; 4.x is
# read as 5.0, not measured) or the world (3.x).
_LAMP_OBJECT_SPACE = bpy.app.version >= (4, 0, 0)


def _tex_coord(c, out):
    name = output_name(out)
    if name == "UV":
        return c.uv("")
    other = getattr(out.node, "object", None)
    if other is not None and name == "Object":
        return _in_object_space(c, other.matrix_world.inverted_safe())
    if name == "Normal":
        return texture_normal(c)
    if c.lamp_matrix is not None and name == "Object":
        # A lamp's tree: the point on the lamp in the lamp's object space from 4.0 (where
        # Cycles gives lamps an object), in the world before (3.x's lamp has none to carry
        # the point into: measured, tests/blender/test_ies.py).
        if _LAMP_OBJECT_SPACE:
            return _in_object_space(c, c.lamp_matrix.inverted_safe())
        return c.hit(ops.IN_POSITION)
    if name == "Camera" and not c.world:
        # INPUT 6 is Blender's camera space (looking down -Z); Cycles' Camera output
        # looks down +Z.
        flip = c.b.const((1.0, 1.0, -1.0), VECTOR)
        return c.b.vmul(c.hit(ops.IN_CAMERA), flip, VECTOR)
    return c.hit(getattr(ops, _TEX_COORD[name]))


def texture_normal(c):
    """What a Texture Coordinate's Normal output gives (and what Cycles 3.x's IES Texture
    reads by default): a lamp's normal in its object space, a surface's shading normal in
    its object's, the world's direction as it is."""
    if c.lamp_matrix is not None:
        return c.in_lamp_space(c.hit(ops.IN_NORMAL))
    if not c.world:
        return c.hit(ops.IN_OBJECT_NORMAL)
    return c.hit(ops.IN_NORMAL)


def _in_object_space(c, inverse):
    """The hit's world position in an object's space, as Cycles' Object output of a
    Texture Coordinate node naming another object (its matrix at the frame: no motion
    blur of it) or of a lamp's tree: the object's `inverse` transform (a mathutils
    Matrix) times the point, its rows dotted with the point."""
    point = c.hit(ops.IN_POSITION)
    b = c.b
    rows = [
        b.add(b.vmath("DOT_PRODUCT", point, b.const(tuple(inverse[i][:3]), VECTOR)),
              b.f(inverse[i][3]))
        for i in range(3)
    ]  # fmt: skip
    return b.pack(*rows)


_GEOMETRY = {
    "Position": ("IN_POSITION", VECTOR),
    "Normal": ("IN_NORMAL", VECTOR),
    "True Normal": ("IN_TRUE_NORMAL", VECTOR),
    "Incoming": ("IN_INCOMING", VECTOR),
    "Backfacing": ("IN_BACKFACING", FLOAT),
}


def _geometry(c, out):
    if output_name(out) == "Tangent":
        # Cycles' default tangent: radial about the object's Z axis.
        return c.hit(ops.IN_RADIAL_TANGENT + 2)
    entry = _GEOMETRY.get(output_name(out))
    if entry is None:
        c.warn(out.node, f"output '{output_name(out)}' is not supported; it gives 0")
        return c.b.f(0.0)
    return c.hit(getattr(ops, entry[0]), entry[1])


_LIGHT_PATH = {
    "Is Camera Ray": "IN_IS_CAMERA_RAY",
    "Is Shadow Ray": "IN_IS_SHADOW_RAY",
    "Is Diffuse Ray": "IN_IS_DIFFUSE_RAY",
    "Is Glossy Ray": "IN_IS_REFLECTION_RAY",
    "Is Singular Ray": "IN_IS_SINGULAR_RAY",
    "Is Reflection Ray": "IN_IS_REFLECTION_RAY",
    "Is Transmission Ray": "IN_IS_TRANSMISSION_RAY",
    "Ray Depth": "IN_RAY_DEPTH",
    # From where the ray starts (a camera ray at its near clip distance) to the hit; 0
    # in the world (Cycles' background).
    "Ray Length": "IN_RAY_LENGTH",
    # Every bounce of a Whitted tracer is singular: glossy and transmission depths
    # are the ray depth, and no ray is diffuse or transparent.
    "Glossy Depth": "IN_RAY_DEPTH",
    "Transmission Depth": "IN_RAY_DEPTH",
}


def _light_path(c, out):
    name = output_name(out)
    mode = _LIGHT_PATH.get(name)
    if mode is None:
        if name not in ("Diffuse Depth", "Transparent Depth", "Is Volume Scatter Ray"):
            c.warn(out.node, f"output '{name}' is not supported; it gives 0")
        return c.b.f(0.0)
    if name in ("Glossy Depth", "Transmission Depth"):
        c.warn(out.node, f"'{name}' is approximated by the ray depth")
    return c.hit(getattr(ops, mode), FLOAT)


def _light_falloff(c, out):
    # Cycles' node at a surface: the Strength scaled by the ray's length to the hit (the
    # camera's, a reflected or refracted ray's, or a shadow feeler's to an emitting mesh),
    # so that a mesh light's inverse-square falloff leaves the named one. In the world the
    # length is 0 (Cycles' background): Linear and Constant give 0. A lamp runs it per
    # feeler with the distance to the lit point (export/light.py light_shader).
    strength = c.input(out, ("Strength",), FLOAT)
    smooth = c.input(out, ("Smooth",), FLOAT)
    falloff = output_name(out).upper()
    if falloff == "QUADRATIC" and smooth.is_const and smooth.value[0] <= 0.0:
        return strength  # the op's identity, folded: no length read
    mode = ops.pack("LIGHT_FALLOFF", falloff=falloff)
    length = c.hit(ops.IN_RAY_LENGTH, FLOAT)
    return c.b.op(ops.LIGHT_FALLOFF, mode, (strength, smooth, length), kind=FLOAT)


def _wireframe(c, out):
    # Cycles' node: 1 within Size / 2 of an edge of the hit's triangle (world units; each
    # edge's line, every edge of the triangulation), else 0. The world has no triangle: 0.
    node = out.node
    if c.world:
        return c.b.f(0.0)
    if node.use_pixel_size:
        c.warn(node, "Pixel Size is not supported; Size is read in world units")
    size = c.input(out, ("Size",), FLOAT)
    corners = tuple(c.hit(ops.IN_TRIANGLE + k) for k in range(3))
    point = c.hit(ops.IN_POSITION)
    return c.b.op(ops.WIREFRAME, 0, (size, point, *corners), kind=FLOAT)


def _object_info(c, out):
    name = output_name(out)
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
    return _attribute_outputs(c, out, c.hit(ops.IN_ATTRIBUTE + c.needs.attribute(key), COLOR))


def _attribute_outputs(c, out, value):
    # An attribute as Cycles' node reads an RGBA one: Color and Vector its rgb, Fac their
    # mean, Alpha its a.
    name = output_name(out)
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
    kind = node.attribute_type
    if kind == "VIEW_LAYER":
        return _layer_attribute(c, out, node.attribute_name)
    if kind in ("OBJECT", "INSTANCER"):
        return _instance_attribute(c, out, (kind, node.attribute_name))
    if c.grids is not None:
        return _grid_attribute(c, out, node.attribute_name)
    return _attribute_value(c, out, ("ATTRIBUTE", node.attribute_name))


def _layer_attribute(c, out, name):
    # A constant of the render (the view layer's, scene's or world's property), folded
    # into the program as Cycles folds it; what was read is kept so that an edit of the
    # property exports the material again (sync/scene.py).
    if c.view_layer is None:
        c.warn(out.node, "View Layer attributes are read by materials only; 0")
        return c.b.f(0.0)
    value = view_layer_attribute(c.view_layer, name)
    c.needs.layer_attributes[name] = value
    return _attribute_outputs(c, out, c.b.const(value, COLOR))


def _instance_attribute(c, out, key):
    # Each instance carries the values of its materials' Object and Instancer attributes
    # (export/instance.py instance_attributes), read by IN_OBJECT_ATTRIBUTE + index.
    if c.world:
        c.warn(out.node, f"{key[0]} attributes are not available in the world; 0")
        return c.b.f(0.0)
    index = c.needs.instance_attribute(key)
    if index is None:
        c.warn(
            out.node,
            f"more than {ops.OBJECT_ATTRIBUTES} Object and Instancer attributes; "
            f"'{key[1]}' reads 0",
        )
        return c.b.f(0.0)
    return _attribute_outputs(c, out, c.hit(ops.IN_OBJECT_ATTRIBUTE + index, COLOR))


def _grid_attribute(c, out, name):
    # Inside a Volume object an attribute is a grid (export/volume_object.py reads those
    # named as its roles are); Fac is a colour grid's mean, Alpha 1.
    role = next((r for r, grid in c.grids.items() if grid == name), None)
    value = None if role is None else c.grid(role, name)
    if value is None:
        c.warn(
            out.node,
            f"grid '{name}' is not read (only density, color, temperature and flame are); 0",
        )
        return c.b.f(0.0)
    kind = output_name(out)
    if kind == "Alpha":
        return c.b.f(1.0)
    if kind in ("Fac", "Factor") and role == "color":
        return c.b.average(value)
    return value


# The Volume Info node's outputs and the grid each reads, by its fixed name.
VOLUME_INFO_GRIDS = {
    "Color": "color",
    "Density": "density",
    "Flame": "flame",
    "Temperature": "temperature",
}


def _volume_info(c, out):
    # A grid of the Volume object, or 0 where there is none (a mesh's volume, the world).
    grid = VOLUME_INFO_GRIDS.get(output_name(out))
    value = None if grid is None else c.grid(grid, grid)
    return c.b.f(0.0) if value is None else value


def _fresnel(c, out):
    ior = c.input(out, ("IOR",), FLOAT)
    _warn_linked_normal(c, out)
    return c.b.op(ops.FRESNEL, 0, (ior,), kind=FLOAT)


def _layer_weight(c, out):
    blend = c.input(out, ("Blend",), FLOAT)
    _warn_linked_normal(c, out)
    output = "FRESNEL" if output_name(out) == "Fresnel" else "FACING"
    mode = ops.pack("LAYER_WEIGHT", output=output)
    return c.b.op(ops.LAYER_WEIGHT, mode, (blend,), kind=FLOAT)


def _warn_linked_normal(c, out):
    socket = find_socket(out.node.inputs, ("Normal",))
    if socket is not None and source(socket, out.scope)[0] is not None:
        c.warn(out.node, "a linked Normal is not supported; the shading normal is used")


def _tangent(c, out):
    # Cycles' Tangent node: radial about the object's X, Y or Z axis (IN_RADIAL_TANGENT),
    # or the UV map's tangent (the one a tangent-space normal map reads: its MikkTSpace
    # tangent), carried to the world and made perpendicular to the normal (UV_TANGENT).
    node = out.node
    if node.direction_type == "UV_MAP":
        uv_set = c.needs.uv_set(node.uv_map)
        c.needs.tangents.add(uv_set)
        return c.b.op(ops.UV_TANGENT, 0, (), e=("set", uv_set), kind=VECTOR)
    return c.hit(ops.IN_RADIAL_TANGENT + "XYZ".index(node.axis))


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
    try:
        mode = ops.pack("NORMAL_MAP", space=space)
    except ValueError:
        c.warn(node, f"{space} normal maps are not supported; the shading normal is used")
        return c.hit(ops.IN_NORMAL)
    uv_set = 0
    if space == "TANGENT":
        uv_set = c.needs.uv_set(node.uv_map)
        c.needs.tangents.add(uv_set)
    return c.b.op(
        ops.NORMAL_MAP, mode, (strength, color), e=("set", uv_set),
        kind=VECTOR,
    )  # fmt: skip


def _ambient_occlusion(c, out):
    # Cycles' node (svm_ao): AO is the share of Samples directions drawn about the Normal
    # (unlinked: the shading normal; with Inside, its opposite) with density cos/pi along
    # which nothing lies within Distance of the hit (with Only Local, nothing of the hit's
    # own object); Color is AO times the Color input. Where nothing can be traced (the
    # world, a shadow feeler's or a medium's evaluation) Cycles gives 1, as the op does.
    # An unlinked Distance of 0 reads the World's AO distance (Cycles' Fast GI Distance;
    # unbounded without a world).
    node = out.node
    color = c.input(out, ("Color",), COLOR)
    if c.world:
        ao = c.b.f(1.0)
    else:
        socket = find_socket(node.inputs, ("Distance",))
        distance = c.value(socket, out.scope, FLOAT)
        if distance.is_const and distance.value[0] == 0.0:
            # Cycles folds constants into the socket before it looks (a linked Value 0 too).
            distance = c.b.f(c.ao_distance)
        normal = linked_normal(c, out)
        normal = normal if normal is not None else c.shading_normal
        # Blender's Samples go from 1 to 128; the op takes up to 255.
        samples = max(0, min(int(node.samples), 255))
        mode = ops.pack(
            "AMBIENT_OCCLUSION", samples=samples, inside=node.inside, only_local=node.only_local
        )
        ao = c.b.op(ops.AMBIENT_OCCLUSION, mode, (distance, normal), kind=FLOAT)
    if output_name(out) == "AO":
        return ao
    return c.b.vmul(color, ao, COLOR)


def _bevel(c, out):
    # Cycles' node (svm_bevel): the shading normals of the hit's own object within Radius
    # of the hit, averaged by a falloff of their distance (Samples probes near the hit); a
    # linked Normal keeps its bend with the bevel's change added. In the world, or where
    # nothing can be traced, the normal as it is, as in Cycles.
    node = out.node
    normal = linked_normal(c, out)
    unbent = c.hit(ops.IN_NORMAL) if normal is None else normal
    if c.world:
        return unbent
    radius = c.input(out, ("Radius",), FLOAT)
    samples = max(0, min(int(node.samples), 255))
    mode = ops.pack("BEVEL", samples=samples)
    point = c.hit(ops.IN_POSITION)
    true_normal = c.hit(ops.IN_TRUE_NORMAL)
    return c.b.op(ops.BEVEL, mode, (radius, point, true_normal, normal), kind=VECTOR)


INPUT_NODES = {
    "ShaderNodeValue": _value,
    "ShaderNodeRGB": _rgb,
    "ShaderNodeUVMap": _uv_map,
    "ShaderNodeTexCoord": _tex_coord,
    "ShaderNodeNewGeometry": _geometry,
    "ShaderNodeLightPath": _light_path,
    "ShaderNodeObjectInfo": _object_info,
    "ShaderNodeLightFalloff": _light_falloff,
    "ShaderNodeWireframe": _wireframe,
    "ShaderNodeVertexColor": _vertex_color,
    "ShaderNodeAttribute": _attribute,
    "ShaderNodeVolumeInfo": _volume_info,
    "ShaderNodeFresnel": _fresnel,
    "ShaderNodeLayerWeight": _layer_weight,
    "ShaderNodeNormalMap": _normal_map,
    "ShaderNodeTangent": _tangent,
    "ShaderNodeAmbientOcclusion": _ambient_occlusion,
    "ShaderNodeBevel": _bevel,
}
