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
refuses non-finite arrays): see `sanitise`. Its per-triangle arithmetic runs in
blocks of `_BLOCK` triangles, so its temporaries stay a few megabytes however
large the mesh.
"""

from dataclasses import dataclass

import numpy as np

from ..native import load_native
from .geometry_key import GeometryKeys
from .mesh_layers import NO_NEEDS, corner_uvs, program_arrays
from .sanitise import Sanitised, compact, sanitise, usable


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
        vertex_normals = _vertex_normals(mesh, positions)
    elif domain == "CORNER":
        normals = np.empty((count, 3, 3), dtype=np.float32)
        triangles.foreach_get("split_normals", normals.reshape(-1))
    slots = _material_slots(mesh, count)
    uvs = None if uv_map is None else corner_uvs(mesh, uv_map, owner, warnings)
    extra = program_arrays(mesh, needs, owner, warnings) if needs else {}
    return positions, corners, normals, vertex_normals, slots, uvs, extra


def _vertex_normals(mesh, positions):
    """float32[N,3]: Blender's vertex normals (the face normals around each vertex
    weighted by the face's corner angle there, normalised), computed here.

    Blender sums them in floats in the order of the faces (before 4.1 on several
    threads, in no fixed order), and one mesh can come in several face orders: its UV
    sphere operator gives the same faces in a new order each call, and one to two
    vertex normals in twenty then differ in the last bit, which moved pixels of the
    gallery scenes by up to 1e-4 (bpy 5.0). The native core sums them in fixed point,
    which no order changes (whitted_native.vertex_normals: 0.1 s for 1M quads in bpy 5.0,
    reads included, against 0.001 s for a copy of Blender's).
    """
    polygons = len(mesh.polygons)
    starts = np.empty(polygons, dtype=np.uint32)
    mesh.polygons.foreach_get("loop_start", starts)
    face_normals = np.empty((polygons, 3), dtype=np.float32)
    if hasattr(mesh, "normals_domain"):
        # Blender 4.1+: block copies of plain arrays (MeshLoop.vertex_index is read item
        # by item: 0.14 s for 1M quads against 0.002 s), the faces' loops consecutive, and
        # the face normals Blender's own vertex normals sum (MeshPolygon.normal is
        # computed again, differently: up to 2e-5 apart on a UV sphere).
        vertex = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.attributes[".corner_vert"].data.foreach_get("value", vertex)
        vertex = vertex.view(np.uint32)
        sizes = np.diff(starts, append=np.uint32(len(mesh.loops)))
        mesh.polygon_normals.foreach_get("vector", face_normals.reshape(-1))
    else:
        # uint32, the type Blender stores the indices in: int32 is copied item by item,
        # 10x slower (a million triangles: 0.19 s against 0.02 s in 3.4).
        vertex = np.empty(len(mesh.loops), dtype=np.uint32)
        mesh.loops.foreach_get("vertex_index", vertex)
        sizes = np.empty(polygons, dtype=np.uint32)
        mesh.polygons.foreach_get("loop_total", sizes)
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
    keep, sanitised = sanitise(positions, corners, normals)
    # A loose NaN vertex no triangle uses must go too: the native module refuses it.
    if not keep.all() or not np.isfinite(positions).all():
        if not keep.any():
            return None, sanitised
        positions, corners, used = compact(positions, corners[keep])
        slots = None if slots is None else slots[keep]
        normals = None if normals is None else normals[keep]
        uvs = None if uvs is None else uvs[keep]
        extra = {key: tuple(a[keep] for a in arrays) for key, arrays in extra.items()}
        vertex_normals = None if vertex_normals is None else vertex_normals[used]
    del keep
    if vertex_normals is not None and not usable(vertex_normals).all():
        # Rare (a vertex of zero-area faces only): each corner of a bad vertex normal
        # takes its face's normal, so the mesh needs corner normals.
        normals = vertex_normals[corners]
        vertex_normals = None
        _, repaired = sanitise(positions, corners, normals)
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
