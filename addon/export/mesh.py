"""Mesh-like objects as shared triangle meshes plus the instances that place them.

Positions and normals stay in object space (Blender's units and axes, Z up);
each instance carries its object-to-world matrix. Arrays are filled with
foreach_get into preallocated numpy arrays of the type Blender stores (float32,
and uint32 for indices: a buffer of another type is copied item by item, several
times slower), never per vertex in Python.

A smooth mesh whose corners all take their vertex's normal exports one normal per
vertex, a mesh with sharp edges or custom normals one per triangle corner, a flat
one none: corner normals are 36 bytes a triangle, vertex normals about 6.

Bad geometry is sanitised here, before it reaches the native module (which
refuses non-finite arrays): see `_sanitise`. Its per-triangle arithmetic runs in
blocks of `_BLOCK` triangles, so its temporaries stay a few megabytes however
large the mesh.
"""

from dataclasses import dataclass

import numpy as np

from ..native import load_native
from .instance import (
    RayVisibility,
    cryptomatte_ids,
    instance_name,
    is_holdout,
    ray_visibility,
    writes_cryptomatte,
)
from .light_linking import NO_LINKS, UNLINKED

# The tracer's default material: what an empty material slot renders with.
# Blender names are never empty, so it cannot clash with a material's name.
DEFAULT_MATERIAL = ""

# Object-space coordinates beyond this magnitude are dropped with their triangles.
# The core works in float32: there the spacing of representable values at 1e7 is
# 1 unit (a metre-scale detail is gone), and the triangle normal it computes is a
# cross product of edges, |e|^2, whose squared length |e|^4 must stay below
# FLT_MAX (3.4e38): at 1e7 it is 1e28, ten orders of magnitude of margin for the
# instance's own scale. No sane model needs more than 10,000 km from its origin.
# (native/src/core/limits.h lists it with the core's own bounds.)
MAX_COORDINATE = 1.0e7

# Triangles per block of `_sanitise`'s arithmetic: about 150 bytes of temporaries a
# triangle, so 10 MB a block.
_BLOCK = 1 << 16


@dataclass(frozen=True)
class MeshData:
    name: str
    positions: np.ndarray  # float32[N,3], object space
    triangles: np.ndarray  # uint32[M,3], vertex indices
    # Shading normals, object space, at most one of `normals` and `vertex_normals`
    # (both None: every face flat); `corner_normals()` gives either per corner.
    normals: np.ndarray | None  # float32[M,3,3] corner normals
    material_slots: np.ndarray | None  # int32[M]; None: every triangle uses slot 0
    uvs: np.ndarray | None = None  # float32[M,3,2] corner UVs; None: no texture needs them
    vertex_normals: np.ndarray | None = None  # float32[N,3]: each corner takes its vertex's
    # What shader programs read (MeshNeeds), by set index; empty when none does.
    uv_sets: tuple = ()  # float32[M,3,2] per UV set
    attributes: tuple = ()  # float32[M,3,4] per corner attribute (floats in all of rgb)
    tangents: tuple = ()  # float32[M,3,4] per UV set: object-space tangent, bitangent sign

    def corner_normals(self):
        """float32[M,3,3]: the shading normal at each triangle corner; None when flat."""
        if self.vertex_normals is not None:
            return self.vertex_normals[self.triangles]
        return self.normals


@dataclass(frozen=True)
class MeshNeeds:
    """What the shader programs of a mesh's materials read from it."""

    uv_sets: tuple = ()  # UV map names by set index ("" = the active render map)
    attributes: tuple = ()  # ("COLOR" | "ATTRIBUTE", name) by attribute index
    tangents: bool = False  # tangents of every UV set (normal maps)

    def __bool__(self):
        return bool(self.uv_sets or self.attributes or self.tangents)


NO_NEEDS = MeshNeeds()


@dataclass(frozen=True)
class InstanceData:
    name: str
    mesh: str  # MeshData.name
    transform: np.ndarray  # float64[4,4], row-major, object to world
    materials: tuple[str, ...]  # material name per slot, DEFAULT_MATERIAL if empty
    visibility: RayVisibility  # which rays see it
    holdout: bool  # camera rays that hit it give colour 0 and alpha 0
    # (location xyz, random, pass index, colour rgba) for Object Info; None when no
    # material of the instance reads it.
    info: tuple | None = None
    # (object id, asset id, (material id per slot)): its Cryptomatte ids (cryptomatte.py);
    # None when the view layer writes no Cryptomatte.
    cryptomatte: tuple | None = None
    # Its transforms over the shutter (export/motion.py MotionData), () when still.
    motion: tuple = ()
    # Light linking: (light set, shadow set, light sets it lights, shadow sets that
    # block it), export/light_linking.py.
    links: tuple = UNLINKED


@dataclass(frozen=True)
class Sanitised:
    """What `_sanitise` removed or repaired in one mesh."""

    nonfinite: int = 0  # triangles dropped: a vertex is NaN or infinite
    distant: int = 0  # triangles dropped: a vertex is beyond MAX_COORDINATE
    zero_area: int = 0  # triangles dropped: their edges' cross product is 0 (float64)
    normals: int = 0  # corner normals of zero length or non-finite, set to the face normal

    def __add__(self, other):
        return Sanitised(
            self.nonfinite + other.nonfinite,
            self.distant + other.distant,
            self.zero_area + other.zero_area,
            self.normals + other.normals,
        )

    def __bool__(self):
        return any((self.nonfinite, self.distant, self.zero_area, self.normals))

    def describe(self):
        """The counts as a phrase, e.g. '3 triangles with NaN/Inf vertices skipped'."""
        dropped = [
            f"{count} {what if count == 1 else what.replace('triangle', 'triangles')}"
            for count, what in (
                (self.nonfinite, "triangle with NaN/Inf vertices"),
                (self.distant, f"triangle with vertices beyond {MAX_COORDINATE:g}"),
                (self.zero_area, "zero-area triangle"),
            )
            if count
        ]
        parts = [f"{', '.join(dropped)} skipped"] if dropped else []
        if self.normals:
            parts.append(f"{self.normals} zero-length or NaN normal(s) set to the face normal")
        return "; ".join(parts)


def mesh_instances(depsgraph):
    """(object instance, geometry key) of every renderable mesh instance of the
    evaluated depsgraph, in the depsgraph's order. Valid only while iterating."""
    keys = GeometryKeys(depsgraph.mode == "RENDER")
    for object_instance in depsgraph.object_instances:
        if is_renderable_mesh(object_instance):
            yield object_instance, keys.key(object_instance)


def is_renderable_mesh(object_instance):
    """Whether a depsgraph object instance is a mesh that renders.

    Curves, text, surfaces and metaballs need no case of their own: the
    depsgraph evaluates them to a mesh, which it yields as a MESH instance of
    the object (besides the object itself, whose to_mesh() is that same mesh
    again). So only MESH objects and instances are exported, as Cycles does.
    """
    obj = object_instance.object
    return (
        obj.type == "MESH"
        and not obj.original.hide_render
        # An instancer can hide its own geometry (particles' "Show Emitter").
        and object_instance.show_self
    )


class GeometryKeys:
    """The geometry keys of one evaluation of a depsgraph (`geometry_key`): every
    user of one evaluated mesh gets one key, and two different evaluated meshes
    never share one (the second of them is numbered, in the depsgraph's order:
    several geometries of one instancer, or a mesh whose users evaluate
    differently)."""

    def __init__(self, render):
        self._render = render
        self._by_address = {}  # evaluated mesh address -> key
        self._taken = set()

    def key(self, object_instance):
        address = object_instance.object.data.as_pointer()
        key = self._by_address.get(address)
        if key is None:
            base = key = geometry_key(object_instance, self._render)
            count = 1
            while key in self._taken:
                key = f"{base}#{count}"
                count += 1
            self._by_address[address] = key
            self._taken.add(key)
        return key


def geometry_key(object_instance, render):
    """A name for the geometry of a mesh instance that survives re-evaluation, as
    Cycles keys its geometry: the original mesh data-block when the object shows it
    as it is (every user shares it), the original object where modifiers or
    geometry nodes make the geometry its own, and the instancer for geometry an
    instancer generates (geometry nodes, curves made into meshes)."""
    original = object_instance.object.original
    if object_instance.is_instance:
        owner = object_instance.parent.original
        # A generated geometry's temporary object reports its instancer as original.
        if original == owner or original.type != "MESH":
            return f"object:{owner.name_full}"
    if original.type != "MESH" or _own_geometry(original, render):
        return f"object:{original.name_full}"
    return f"mesh:{original.data.name_full}"


def _own_geometry(obj, render):
    # Modifiers (geometry nodes among them) or edit mode make an object's evaluated
    # mesh its own: no other user of the data-block shares it.
    enabled = "show_render" if render else "show_viewport"
    return obj.mode == "EDIT" or any(getattr(m, enabled) for m in obj.modifiers)


def instance_data(object_instance, mesh, view_layer, info=(), links=NO_LINKS):
    """InstanceData of a mesh instance placing geometry `mesh` (its key).

    `view_layer` is the depsgraph's evaluated view layer (holdout is per layer);
    `info` the names of the materials that read Object Info. An object with a pass
    index sends its Object Info too, for the IndexOB pass. `links`: the scene's
    light_linking.LightLinks."""
    materials = _slot_materials(object_instance.object)
    reads_info = any(m in info for m in materials) or object_instance.object.pass_index != 0
    return InstanceData(
        name=instance_name(object_instance),
        mesh=mesh,
        # Valid only while iterating: copy it now.
        transform=np.array(object_instance.matrix_world, dtype=np.float64),
        materials=materials,
        visibility=ray_visibility(object_instance),
        holdout=is_holdout(object_instance, view_layer),
        info=object_info(object_instance) if reads_info else None,
        cryptomatte=cryptomatte_ids(object_instance.object)
        if writes_cryptomatte(view_layer)
        else None,
        links=links.of_object(
            object_instance.object, object_instance.parent if object_instance.is_instance else None
        ),
    )


def object_info(object_instance):
    """(location xyz, random, pass index, colour rgba): what Object Info gives, as
    Cycles computes it: the instance's world location; its random id (an unsigned
    32-bit hash) times 1 / 0xFFFFFFFF in float32, in [0, 1]; the object's pass index
    and its colour (Object Properties > Viewport Display).

    The depsgraph gives instances their `random_id` and real objects 0; Cycles then
    hashes the object's name (hash_uint2(hash_string(name), 0), util/hash.h)."""
    obj = object_instance.object
    location = tuple(float(x) for x in object_instance.matrix_world.translation)
    random_id = getattr(object_instance, "random_id", 0) & 0xFFFFFFFF
    if random_id == 0:
        random_id = _hash_uint2(_hash_string(obj.name), 0)
    random = float(np.float32(np.float32(random_id) * np.float32(1.0 / 0xFFFFFFFF)))
    return (*location, random, float(obj.pass_index), *(float(c) for c in obj.color))


def _hash_string(text):
    # Cycles' hash_string: i = i * 37 + c over the bytes, in uint32.
    value = 0
    for byte in text.encode():
        value = (value * 37 + byte) & 0xFFFFFFFF
    return value


def _rot(x, k):
    return ((x << k) | (x >> (32 - k))) & 0xFFFFFFFF


def _hash_uint2(kx, ky):
    # Bob Jenkins' lookup3 final mix of two words (Cycles' hash_uint2).
    a = b = c = (0xDEADBEEF + (2 << 2) + 13) & 0xFFFFFFFF
    b = (b + ky) & 0xFFFFFFFF
    a = (a + kx) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 14)) & 0xFFFFFFFF
    a ^= c
    a = (a - _rot(c, 11)) & 0xFFFFFFFF
    b ^= a
    b = (b - _rot(a, 25)) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 16)) & 0xFFFFFFFF
    a ^= c
    a = (a - _rot(c, 4)) & 0xFFFFFFFF
    b ^= a
    b = (b - _rot(a, 14)) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 24)) & 0xFFFFFFFF
    return c


def export_geometry(obj, name, uv_map, warnings, convert=None, in_place=False, needs=NO_NEEDS):
    """The geometry of evaluated mesh object `obj` as MeshData named `name` (or what
    `convert` made of it), or None when no triangle is left; and its Sanitised,
    which is also described in `warnings`. The MeshData lives only in this frame,
    so its arrays are freed on return when `convert` keeps none of them. `needs`:
    the UV sets, corner attributes and tangents its materials' programs read."""
    mesh, sanitised = _convert_geometry(obj, name, uv_map, warnings, in_place, needs)
    if sanitised:
        warnings.append(f"Whitted: object '{obj.name}': {sanitised.describe()}")
    if mesh is None or convert is None:
        return mesh, sanitised
    return convert(mesh), sanitised


def _convert_geometry(obj, name, uv_map, warnings, in_place, needs):
    # `obj` comes from depsgraph.object_instances and is already evaluated (with
    # modifiers); a geometry-nodes instance is a temporary object that
    # evaluated_get() would not find, so it is converted directly.
    # Tangents are computed into the mesh: never into the depsgraph's own.
    if (
        in_place
        and not needs.tangents
        and _corner_normals_ready(obj.data)
        and _normals_domain(obj.data) == "CORNER"
    ):
        arrays = _read(obj.data, "CORNER", obj.name, uv_map, warnings, needs)
    else:
        try:
            mesh = obj.to_mesh()
        except RuntimeError as error:
            warnings.append(
                f"Whitted: object '{obj.name}' could not be made a mesh ({error}); skipped"
            )
            return None, Sanitised()
        try:
            domain = _normals_domain(mesh)
            if domain == "CORNER" and hasattr(mesh, "calc_normals_split"):
                mesh.calc_normals_split()  # Blender < 4.1 computes them only on request
            arrays = _read(mesh, domain, obj.name, uv_map, warnings, needs)
        finally:
            # Blender's copy goes before the arrays are checked: it is the larger.
            obj.to_mesh_clear()
    if arrays is None:
        return None, Sanitised()
    *arrays, extra = arrays
    return _finish(name, *arrays, extra)


def _corner_normals_ready(mesh):
    """Whether the evaluated `mesh` holds corner normals that Blender < 4.1's depsgraph
    computed (for auto smooth and custom normals), so that it is read in place, as
    Cycles does: to_mesh() would copy every array but drop them, and
    calc_normals_split() take 0.3 s a million triangles to compute them again.
    Loop 0's normal is (0, 0, 0) when they are missing (a computed one has length 1).
    """
    return _computes_corner_normals(mesh) and any(mesh.loops[0].normal)


def _computes_corner_normals(mesh):
    """Whether a render depsgraph of Blender < 4.1 computes the evaluated `mesh`'s
    corner normals (auto smooth or custom normals): the meshes F12 reads in place.

    Not in edit mode: the geometry is in a BMesh that only to_mesh() turns into
    arrays. Other meshes are copied: read in place, they would keep the caches the
    export computes (loop triangles: 16 bytes a triangle) for the whole render, for
    little gain; and from 4.1 to_mesh() shares the arrays and normals anyway.
    """
    return (
        hasattr(mesh, "calc_normals_split")
        and not mesh.is_editmode
        and (mesh.use_auto_smooth or mesh.has_custom_normals)
        and len(mesh.loops) > 0
    )


def copied_for_normals(obj):
    """Whether exporting evaluated mesh object `obj` from a viewport depsgraph copies it
    (to_mesh()) and computes its corner normals where a render (F12) reads it in place
    (_convert_geometry): work done before a render's engine starts, which the Estimate
    leaves out of its fixed costs. A mesh whose materials need tangents is copied
    either way; that is not considered here."""
    return _computes_corner_normals(obj.data) and _normals_domain(obj.data) == "CORNER"


def _read(mesh, domain, owner, uv_map, warnings, needs=NO_NEEDS):
    """The mesh's arrays as Blender stores them: (positions, corners, corner normals,
    vertex normals, material slots, uvs, {uv_sets, attributes, tangents}), or None
    when it has no triangles. `domain` is `_normals_domain(mesh)`; `owner` names
    the object in warnings."""
    mesh.calc_loop_triangles()
    triangles = mesh.loop_triangles
    count = len(triangles)
    if count == 0:
        return None
    positions = np.empty((len(mesh.vertices), 3), dtype=np.float32)
    mesh.vertices.foreach_get("co", positions.reshape(-1))
    corners = np.empty((count, 3), dtype=np.uint32)
    triangles.foreach_get("vertices", corners.reshape(-1))
    normals = vertex_normals = None
    if domain == "POINT":
        vertex_normals = np.empty_like(positions)
        if hasattr(mesh, "normals_domain"):  # Blender 4.1+: a plain array, a block copy
            mesh.vertex_normals.foreach_get("vector", vertex_normals.reshape(-1))
        else:
            vertex_normals = _vertex_normals(mesh, positions)
    elif domain == "CORNER":
        normals = np.empty((count, 3, 3), dtype=np.float32)
        triangles.foreach_get("split_normals", normals.reshape(-1))
    slots = _material_slots(mesh, count)
    uvs = None if uv_map is None else _corner_uvs(mesh, uv_map, owner, warnings)
    extra = _program_arrays(mesh, needs, owner, warnings) if needs else {}
    return positions, corners, normals, vertex_normals, slots, uvs, extra


def _vertex_normals(mesh, positions):
    """float32[N,3]: Blender's vertex normals (the face normals around each vertex
    weighted by the face's corner angle there, normalised), computed here.

    Blender before 4.1 sums them on several threads in no fixed order, so two reads
    of one unchanged mesh can differ in the last bit, and a render would not be a
    pure function of the scene. The native core sums them in a fixed order, in double
    (whitted_native.vertex_normals: 0.12 s for 1M quads; the numpy code it replaced,
    with the same operations and so the same bits, took 1.1 s on the million scene).
    """
    # uint32, the type Blender stores the indices in: int32 is copied item by item, 10x
    # slower (a million triangles: 0.19 s against 0.02 s in 3.4).
    vertex = np.empty(len(mesh.loops), dtype=np.uint32)
    mesh.loops.foreach_get("vertex_index", vertex)
    starts = np.empty(len(mesh.polygons), dtype=np.uint32)
    sizes = np.empty(len(mesh.polygons), dtype=np.uint32)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", sizes)
    face_normals = np.empty((len(mesh.polygons), 3), dtype=np.float32)
    mesh.polygons.foreach_get("normal", face_normals.reshape(-1))  # one face each: exact
    # A vertex of no face (or of zero-area faces only) keeps a zero normal, which
    # `_finish` repairs.
    return load_native().vertex_normals(positions, vertex, starts, sizes, face_normals)


def _normals_domain(mesh):
    """Where the mesh's shading normals vary: "FACE" (every face flat), "POINT" (each
    corner takes its vertex's normal) or "CORNER" (sharp edges, flat faces among
    smooth ones, custom normals)."""
    domain = getattr(mesh, "normals_domain", None)  # Blender 4.1+ says it
    if domain is not None:
        return domain
    # Before 4.1: custom normals vary per corner; auto smooth makes edges sharp by
    # angle (and honours edges marked sharp); otherwise smooth faces take the vertex
    # normal and flat ones the face normal.
    if mesh.has_custom_normals:
        return "CORNER"
    smooth = np.empty(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    if not smooth.any():
        return "FACE"
    if smooth.all() and not mesh.use_auto_smooth:
        return "POINT"
    return "CORNER"


def _material_slots(mesh, count):
    """int32[M] material slot of each loop triangle, or None when all use slot 0."""
    # Blender renders an index past the last slot with the last slot: with one slot
    # (or none) every triangle uses slot 0.
    last = len(mesh.materials) - 1
    if last <= 0:
        return None
    # Blender 3.4+ keeps the indices in a built-in face attribute (int32), absent when
    # all are 0. A block copy of it and of each triangle's face, then a gather, is
    # several times faster than loop_triangles' material_index, read item by item.
    attribute = mesh.attributes.get("material_index")
    if attribute is None:
        return None
    face_slots = np.empty(len(mesh.polygons), dtype=np.int32)
    attribute.data.foreach_get("value", face_slots)
    faces = np.empty(count, dtype=np.uint32)
    mesh.loop_triangles.foreach_get("polygon_index", faces)
    slots = face_slots[faces]
    np.clip(slots, 0, last, out=slots)
    return slots if slots.any() else None


def _finish(name, positions, corners, normals, vertex_normals, slots, uvs, extra=None):
    """(MeshData or None when no triangle is left, Sanitised): bad triangles dropped,
    unused vertices with them, bad normals repaired. `extra`: the per-corner arrays
    programs read ({"uv_sets" | "attributes" | "tangents": tuple of [M,3,k]})."""
    extra = dict(extra or {})
    keep, sanitised = _sanitise(positions, corners, normals)
    # A loose NaN vertex no triangle uses must go too: the native module refuses it.
    if not keep.all() or not np.isfinite(positions).all():
        if not keep.any():
            return None, sanitised
        positions, corners, used = _compact(positions, corners[keep])
        slots = None if slots is None else slots[keep]
        normals = None if normals is None else normals[keep]
        uvs = None if uvs is None else uvs[keep]
        extra = {key: tuple(a[keep] for a in arrays) for key, arrays in extra.items()}
        vertex_normals = None if vertex_normals is None else vertex_normals[used]
    del keep
    if vertex_normals is not None and not _usable(vertex_normals).all():
        # Rare (a vertex of zero-area faces only): each corner of a bad vertex normal
        # takes its face's normal, so the mesh needs corner normals.
        normals = vertex_normals[corners]
        vertex_normals = None
        _, repaired = _sanitise(positions, corners, normals)
        sanitised += Sanitised(normals=repaired.normals)
    mesh_data = MeshData(
        name=name,
        positions=positions,
        triangles=corners,
        normals=normals,
        material_slots=slots,
        uvs=uvs,
        vertex_normals=vertex_normals,
        uv_sets=extra.get("uv_sets", ()),
        attributes=extra.get("attributes", ()),
        tangents=extra.get("tangents", ()),
    )
    return mesh_data, sanitised


def _sanitise(positions, corners, normals):
    """Which triangles to keep, and what was wrong; repairs `normals` in place.

    Dropped: triangles with a vertex that is NaN/Inf or beyond MAX_COORDINATE, and
    those of zero area (the cross product of two edges, in float64, is exactly 0:
    collinear or repeated corners; they cannot be hit, and have no normal). Slivers
    of non-zero area are kept: the core's watertight intersection handles them.
    A corner normal of zero length or with NaN/Inf is replaced by the face normal.
    """
    count = len(corners)
    nonfinite_vertex = ~np.isfinite(positions).all(axis=1)
    # NaN compares False, so a NaN vertex is only "non-finite", never "distant".
    distant_vertex = (np.abs(positions) > MAX_COORDINATE).any(axis=1)
    if nonfinite_vertex.any() or distant_vertex.any():  # rare: per triangle only then
        nonfinite = nonfinite_vertex[corners].any(axis=1)
        distant = distant_vertex[corners].any(axis=1) & ~nonfinite
        keep = ~(nonfinite | distant)
    else:
        nonfinite = distant = np.zeros(0, dtype=bool)
        keep = np.ones(count, dtype=bool)
    del nonfinite_vertex, distant_vertex
    zero_area = repaired = 0
    # Triangles with a NaN/Inf vertex (already dropped) give NaN products: not zero.
    with np.errstate(invalid="ignore", over="ignore"):
        for start in range(0, count, _BLOCK):
            block = slice(start, start + _BLOCK)
            zero = _zero_area(positions, corners[block]) & keep[block]
            zero_area += int(np.count_nonzero(zero))
            keep[block] &= ~zero
            if normals is not None:
                repaired += _repair(normals[block], positions, corners[block], keep[block])
    sanitised = Sanitised(
        nonfinite=int(np.count_nonzero(nonfinite)),
        distant=int(np.count_nonzero(distant)),
        zero_area=zero_area,
        normals=repaired,
    )
    return keep, sanitised


def _zero_area(positions, corners):
    """bool[k]: whether the cross product of each triangle's edges (p1 - p0, p2 - p0),
    in float64, is exactly 0 (in the native core: numpy's temporaries took 0.12 s a
    million triangles)."""
    return load_native().zero_area_triangles(positions, corners)


def _usable(normals):
    """bool[...]: which normals (last axis xyz) have a finite, non-zero float32 length."""
    squared = np.einsum("...k,...k->...", normals, normals)
    # NaN fails both comparisons; an infinite component (or overflow) the second.
    return (squared > 0.0) & (squared < np.inf)


def _repair(normals, positions, corners, keep):
    """Set the unusable corner normals of kept triangles (which have non-zero area) to
    their face normal; how many."""
    rows, columns = np.nonzero(~_usable(normals) & keep[:, None])
    if len(rows) == 0:
        return 0
    points = positions[corners[rows]].astype(np.float64)
    face = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    normals[rows, columns] = face / np.linalg.norm(face, axis=1)[:, None]
    return len(rows)


def _compact(positions, corners):
    """Only the vertices `corners` uses (so no NaN vertex stays), renumbered, and the
    mask of the vertices kept."""
    used = np.zeros(len(positions), dtype=bool)
    used[corners] = True
    # Unused vertices get -1, never read: every corner's vertex is used.
    renumber = np.cumsum(used, dtype=np.int64) - 1
    return (
        np.ascontiguousarray(positions[used]),
        np.ascontiguousarray(renumber[corners], dtype=np.uint32),
        used,
    )


def object_uv_map(obj, uv_maps):
    """The UV map the first textured material of evaluated `obj` asks for, or None;
    `uv_maps` maps a material name to its UV map."""
    return next((uv_maps[m] for m in _slot_materials(obj) if m in uv_maps), None)


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


def _corner_uvs(mesh, uv_map, owner, warnings):
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
    for material in _slot_materials(obj):
        needs = needs_by_material.get(material)
        if needs is None:
            continue
        for merged, wanted, what in (
            (uv_sets, needs.uv_sets, "UV maps"),
            (attributes, needs.attributes, "attributes"),
        ):
            for index, item in enumerate(wanted):
                if index == len(merged):
                    merged.append(item)
                elif merged[index] != item:
                    warn(
                        warnings,
                        f"Whitted: object '{obj.name}': material '{material}' reads its {what} "
                        "in another order than the object's first material; it reads theirs",
                    )
        tangents = tangents or needs.tangents
    return MeshNeeds(tuple(uv_sets), tuple(attributes), tangents)


def warn(warnings, message):
    if message not in warnings:
        warnings.append(message)


def _program_arrays(mesh, needs, owner, warnings):
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
        uvs = _corner_uvs(mesh, uv_map, owner, []) if layer is not None else None
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


def _slot_materials(obj):
    # The evaluated object's slots already resolve object- versus data-linked materials.
    names = tuple(
        slot.material.name_full if slot.material is not None else DEFAULT_MATERIAL
        for slot in obj.material_slots
    )
    return names or (DEFAULT_MATERIAL,)
