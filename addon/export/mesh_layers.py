"""The layers a mesh carries besides positions and normals, only where its materials
read them: the UV map its textures read, and what its shader programs read (UV sets,
corner attributes, tangents), each per triangle corner."""

from dataclasses import dataclass

import numpy as np

from .instance import slot_materials


@dataclass(frozen=True)
class MeshNeeds:
    """What the shader programs of a mesh's materials read from it."""

    uv_sets: tuple = ()  # UV map names by set index ("" = the active render map)
    attributes: tuple = ()  # ("COLOR" | "ATTRIBUTE", name) by attribute index
    tangents: bool = False  # tangents of every UV set (normal maps)

    def __bool__(self):
        return bool(self.uv_sets or self.attributes or self.tangents)


NO_NEEDS = MeshNeeds()


def object_uv_map(obj, uv_maps):
    """The UV map the first textured material of evaluated `obj` asks for, or None;
    `uv_maps` maps a material name to its UV map."""
    return next((uv_maps[m] for m in slot_materials(obj) if m in uv_maps), None)


def _uv_layer(mesh, uv_map, owner, warnings):
    """The UV layer named `uv_map` or, for "" or a map the mesh lacks, the active
    render one; None (with a warning) when the mesh has none."""
    layers = mesh.uv_layers
    if len(layers) == 0:
        warn(warnings, f"Whitted: object '{owner}' has no UV map; its textures read UV (0, 0)")
        return None
    layer = layers.get(uv_map) if uv_map else None
    if layer is None:
        if uv_map:
            warn(
                warnings,
                f"Whitted: object '{owner}' has no UV map '{uv_map}'; using the active render one",
            )
        layer = next((candidate for candidate in layers if candidate.active_render), layers[0])
    return layer


def corner_uvs(mesh, uv_map, owner, warnings):
    """float32[M,3,2]: the UV of each loop triangle's corners, from the UV map
    named `uv_map` or, for "" or a map the mesh lacks, the active render one."""
    layer = _uv_layer(mesh, uv_map, owner, warnings)
    if layer is None:
        return None
    loop_uvs = np.empty((len(mesh.loops), 2), dtype=np.float32)
    if hasattr(layer, "uv"):  # Blender 3.5+: the plain float2 array, a block copy
        layer.uv.foreach_get("vector", loop_uvs.reshape(-1))
    else:
        layer.data.foreach_get("uv", loop_uvs.reshape(-1))
    triangles = mesh.loop_triangles
    loops = np.empty((len(triangles), 3), dtype=np.uint32)  # Blender's type: a block copy
    triangles.foreach_get("loops", loops.reshape(-1))
    return np.take(loop_uvs, loops, axis=0)


def object_needs(obj, needs_by_material, warnings):
    """The MeshNeeds of evaluated `obj`: its materials' needs merged in slot order.

    A set index means the same UV map (or attribute) for every material of the mesh;
    when two materials disagree, the first one's wins and the other is warned about."""
    uv_sets, attributes, tangents = [], [], False
    for material in slot_materials(obj):
        needs = needs_by_material.get(material)
        if needs is None:
            continue
        _merge(uv_sets, needs.uv_sets, obj, material, "UV maps", warnings)
        _merge(attributes, needs.attributes, obj, material, "attributes", warnings)
        tangents = tangents or needs.tangents
    return MeshNeeds(tuple(uv_sets), tuple(attributes), tangents)


def attribute_keys(obj, keys_by_material, warnings):
    """The Object and Instancer attributes (("OBJECT" | "INSTANCER", name) by index) the
    materials of evaluated `obj` read, merged in slot order as object_needs merges the
    mesh's layers; `keys_by_material` maps a material name to its keys."""
    keys = []
    for material in slot_materials(obj):
        wanted = keys_by_material.get(material)
        if wanted:
            _merge(keys, wanted, obj, material, "Object and Instancer attributes", warnings)
    return tuple(keys)


def _merge(merged, wanted, obj, material, what, warnings):
    # An index means one item for every material of the object: the first one's wins.
    for index, item in enumerate(wanted):
        if index == len(merged):
            merged.append(item)
        elif merged[index] != item:
            warn(
                warnings,
                f"Whitted: object '{obj.name}': material '{material}' reads its {what} "
                "in another order than the object's first material; it reads theirs",
            )


def warn(warnings, message):
    if message not in warnings:
        warnings.append(message)


def program_arrays(mesh, needs, owner, warnings):
    """The per-corner arrays of `needs` for a mesh whose loop triangles exist."""
    triangles = mesh.loop_triangles
    count = len(triangles)
    loops = np.empty((count, 3), dtype=np.uint32)
    triangles.foreach_get("loops", loops.reshape(-1))
    uv_sets = []
    layer_names = []
    for uv_map in needs.uv_sets:
        layer = _uv_layer(mesh, uv_map, owner, warnings)
        layer_names.append(None if layer is None else layer.name)
        uvs = corner_uvs(mesh, uv_map, owner, []) if layer is not None else None
        uv_sets.append(np.zeros((count, 3, 2), np.float32) if uvs is None else uvs)
    attributes = [_corner_attribute(mesh, key, loops, owner, warnings) for key in needs.attributes]
    tangents = []
    if needs.tangents:
        for name in layer_names:
            tangents.append(_corner_tangents(mesh, name, loops, owner, warnings))
    return {
        "uv_sets": tuple(uv_sets),
        "attributes": tuple(attributes),
        "tangents": tuple(tangents),
    }


def _corner_tangents(mesh, uv_layer, loops, owner, warnings):
    """float32[M,3,4]: Blender's own tangent space (`calc_tangents`, MikkTSpace) of UV
    layer `uv_layer`: object-space tangent and bitangent sign per triangle corner;
    zeros (no normal mapping) when Blender cannot compute it."""
    count = len(loops)
    if uv_layer is None:
        return np.zeros((count, 3, 4), np.float32)
    try:
        mesh.calc_tangents(uvmap=uv_layer)
    except RuntimeError as error:
        warn(warnings, f"Whitted: object '{owner}': no tangents ({error}); normal maps ignored")
        return np.zeros((count, 3, 4), np.float32)
    loop_count = len(mesh.loops)
    tangent = np.empty((loop_count, 4), dtype=np.float32)
    flat = np.empty(loop_count * 3, dtype=np.float32)
    mesh.loops.foreach_get("tangent", flat)
    tangent[:, :3] = flat.reshape(-1, 3)
    sign = np.empty(loop_count, dtype=np.float32)
    mesh.loops.foreach_get("bitangent_sign", sign)
    tangent[:, 3] = sign
    if hasattr(mesh, "free_tangents"):
        mesh.free_tangents()
    return np.take(tangent, loops, axis=0)


_ATTRIBUTE_VALUES = {
    "FLOAT_COLOR": ("color", 4),
    "BYTE_COLOR": ("color", 4),  # `color` is scene linear for byte colours too
    "FLOAT_VECTOR": ("vector", 3),
    "FLOAT2": ("vector", 2),
    "FLOAT": ("value", 1),
    "INT": ("value", 1),
    "INT8": ("value", 1),
    "BOOLEAN": ("value", 1),
}


def _corner_attribute(mesh, key, loops, owner, warnings):
    """float32[M,3,4]: attribute `key` ("COLOR" or "ATTRIBUTE", name) at each corner;
    a float in all of rgb, alpha 1 but for colours; zeros (with a warning) when the
    mesh lacks it, as Cycles renders a missing attribute black."""
    kind, name = key
    count = len(loops)
    attribute = None
    if kind == "COLOR":
        colors = getattr(mesh, "color_attributes", None)
        if colors is not None and len(colors):
            if name:
                attribute = colors.get(name)
            else:
                index = getattr(colors, "render_color_index", -1)
                attribute = colors[index] if 0 <= index < len(colors) else colors.active_color
    if attribute is None and name:
        attribute = mesh.attributes.get(name)
    if attribute is None:
        what = f"colour attribute '{name}'" if name else "colour attribute"
        if kind == "ATTRIBUTE":
            what = f"attribute '{name}'"
        warn(warnings, f"Whitted: object '{owner}' has no {what}; it reads 0")
        return np.zeros((count, 3, 4), np.float32)
    entry = _ATTRIBUTE_VALUES.get(attribute.data_type)
    if entry is None or attribute.domain not in ("POINT", "CORNER", "FACE"):
        warn(
            warnings,
            f"Whitted: object '{owner}': attribute '{attribute.name}' "
            f"({attribute.data_type} on {attribute.domain}) is not supported; it reads 0",
        )
        return np.zeros((count, 3, 4), np.float32)
    field, width = entry
    size = len(attribute.data)
    flat = np.empty(size * width, dtype=np.float32)
    if attribute.data_type in ("INT", "INT8", "BOOLEAN"):
        raw = np.empty(size, dtype=np.int32 if attribute.data_type != "BOOLEAN" else bool)
        attribute.data.foreach_get(field, raw)
        flat[:] = raw
    else:
        attribute.data.foreach_get(field, flat)
    values = np.ones((size, 4), dtype=np.float32)
    stored = flat.reshape(size, width)
    if width == 1:
        values[:, :3] = stored
    else:
        values[:, : min(width, 4)] = stored[:, :4]
        if width == 2:
            values[:, 2] = 0.0
    if attribute.domain == "CORNER":
        index = loops
    elif attribute.domain == "POINT":
        vertex = np.empty(len(mesh.loops), dtype=np.uint32)  # Blender's type: a block copy
        mesh.loops.foreach_get("vertex_index", vertex)
        index = vertex[loops]
    else:
        faces = np.empty(count, dtype=np.uint32)
        mesh.loop_triangles.foreach_get("polygon_index", faces)
        index = np.repeat(faces[:, None], 3, axis=1)
    return np.take(values, index, axis=0)
