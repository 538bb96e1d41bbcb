"""Mesh-like objects as shared triangle meshes plus the instances that place them.

Positions and normals stay in object space (Blender's units and axes, Z up);
each instance carries its object-to-world matrix. Arrays are filled with
foreach_get, never per vertex in Python.

Bad geometry is sanitised here, before it reaches the native module (which
refuses non-finite arrays): see `_sanitise`.
"""

from dataclasses import dataclass, field

import numpy as np

from .instance import RayVisibility, instance_name, is_holdout, ray_visibility

# The tracer's default material: what an empty material slot renders with.
# Blender names are never empty, so it cannot clash with a material's name.
DEFAULT_MATERIAL = ""

# Object-space coordinates beyond this magnitude are dropped with their triangles.
# The core works in float32: there the spacing of representable values at 1e7 is
# 1 unit (a metre-scale detail is gone), and the triangle normal it computes is a
# cross product of edges, |e|^2, whose squared length |e|^4 must stay below
# FLT_MAX (3.4e38): at 1e7 it is 1e28, ten orders of magnitude of margin for the
# instance's own scale. No sane model needs more than 10,000 km from its origin.
MAX_COORDINATE = 1.0e7


@dataclass(frozen=True)
class MeshData:
    name: str
    positions: np.ndarray  # float32[N,3], object space
    triangles: np.ndarray  # uint32[M,3], vertex indices
    normals: np.ndarray | None  # float32[M,3,3] corner normals; None: all faces flat
    material_slots: np.ndarray | None  # int32[M]; None: every triangle uses slot 0
    uvs: np.ndarray | None = None  # float32[M,3,2] corner UVs; None: no texture needs them


@dataclass(frozen=True)
class InstanceData:
    name: str
    mesh: str  # MeshData.name
    transform: np.ndarray  # float64[4,4], row-major, object to world
    materials: tuple[str, ...]  # material name per slot, DEFAULT_MATERIAL if empty
    visibility: RayVisibility  # which rays see it
    holdout: bool  # camera rays that hit it give colour 0 and alpha 0


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


@dataclass(frozen=True)
class MeshExport:
    meshes: list[MeshData]
    instances: list[InstanceData]
    sanitised: Sanitised = field(default_factory=Sanitised)  # totals over all meshes


def convert_meshes(depsgraph, warnings, uv_maps=None):
    """Every renderable mesh-like object of the evaluated depsgraph, each distinct
    geometry once, placed by one instance per object or instance.

    Curves, text, surfaces and metaballs need no case of their own: the
    depsgraph evaluates them to a mesh, which it yields as a MESH instance of
    the object (besides the object itself, whose to_mesh() is that same mesh
    again). So only MESH objects and instances are exported, as Cycles does.

    `uv_maps` maps a material name to the UV map its textures read ("" for the
    active render map); a mesh exports corner UVs when one of its materials is there.
    """
    uv_maps = uv_maps or {}
    meshes = []
    instances = []
    # Evaluated mesh address -> the name of its mesh, or None when it has no triangles.
    mesh_names = {}
    taken_names = set()
    sanitised = Sanitised()
    view_layer = depsgraph.view_layer_eval  # holdout is per view layer
    for object_instance in depsgraph.object_instances:
        obj = object_instance.object
        if (
            obj.type != "MESH"
            or obj.original.hide_render
            # An instancer can hide its own geometry (particles' "Show Emitter").
            or not object_instance.show_self
        ):
            continue
        # The depsgraph hands every unmodified user of a mesh (collection instances
        # too), and every geometry-nodes instance of one geometry, the same evaluated
        # mesh; an object with modifiers owns its evaluated mesh. So the address of
        # the evaluated mesh tells which instances can share one exported mesh.
        key = obj.data.as_pointer()
        if key not in mesh_names:
            name = _unique_name(f"{obj.original.name_full}/{obj.data.name_full}", taken_names)
            taken_names.add(name)
            mesh, repaired = _convert_geometry(obj, name, _uv_map(obj, uv_maps), warnings)
            if repaired:
                sanitised += repaired
                warnings.append(f"Whitted: object '{obj.name}': {repaired.describe()}")
            mesh_names[key] = None if mesh is None else mesh.name
            if mesh is not None:
                meshes.append(mesh)
        if mesh_names[key] is None:
            continue
        instances.append(
            InstanceData(
                name=instance_name(object_instance),
                mesh=mesh_names[key],
                # Valid only while iterating: copy it now.
                transform=np.array(object_instance.matrix_world, dtype=np.float64),
                materials=_slot_materials(obj),
                visibility=ray_visibility(object_instance),
                holdout=is_holdout(object_instance, view_layer),
            )
        )
    return MeshExport(meshes=meshes, instances=instances, sanitised=sanitised)


def _unique_name(name, taken):
    # Two geometries of one object (geometry nodes) can share a data name.
    suffix = 1
    unique = name
    while unique in taken:
        unique = f"{name}.{suffix}"
        suffix += 1
    return unique


def _convert_geometry(obj, name, uv_map, warnings):
    # `obj` comes from depsgraph.object_instances and is already evaluated (with
    # modifiers); a geometry-nodes instance is a temporary object that
    # evaluated_get() would not find, so it is converted directly.
    try:
        mesh = obj.to_mesh()
    except RuntimeError as error:
        warnings.append(f"Whitted: object '{obj.name}' could not be made a mesh ({error}); skipped")
        return None, Sanitised()
    try:
        return _triangulate(mesh, name, uv_map, warnings)
    finally:
        obj.to_mesh_clear()


def _triangulate(mesh, name, uv_map, warnings):
    """(MeshData or None when no triangle is left, Sanitised)."""
    mesh.calc_loop_triangles()
    triangles = mesh.loop_triangles
    count = len(triangles)
    if count == 0:
        return None, Sanitised()
    positions = np.empty((len(mesh.vertices), 3), dtype=np.float32)
    mesh.vertices.foreach_get("co", positions.reshape(-1))
    corners = np.empty((count, 3), dtype=np.int32)
    triangles.foreach_get("vertices", corners.reshape(-1))
    slots = np.empty(count, dtype=np.int32)
    triangles.foreach_get("material_index", slots)
    # Blender renders an index past the last slot with the last slot.
    np.clip(slots, 0, max(len(mesh.materials), 1) - 1, out=slots)
    smooth = np.empty(count, dtype=bool)
    triangles.foreach_get("use_smooth", smooth)
    normals = None
    if smooth.any() or mesh.has_custom_normals:
        # Corner ("split") normals: smooth faces interpolate, flat faces and sharp
        # edges keep the face normal. Blender < 4.1 computes them only on request.
        if hasattr(mesh, "calc_normals_split"):
            mesh.calc_normals_split()
        normals = np.empty((count, 3, 3), dtype=np.float32)
        triangles.foreach_get("split_normals", normals.reshape(-1))
    uvs = None if uv_map is None else _corner_uvs(mesh, uv_map, name, warnings)
    keep, sanitised = _sanitise(positions, corners, normals)
    # A loose NaN vertex no triangle uses must go too: the native module refuses it.
    if not keep.all() or not np.isfinite(positions).all():
        if not keep.any():
            return None, sanitised
        positions, corners = _compact(positions, corners[keep])
        slots = slots[keep]
        normals = None if normals is None else normals[keep]
        uvs = None if uvs is None else uvs[keep]
    mesh_data = MeshData(
        name=name,
        positions=positions,
        # Indices are never negative: reinterpret the bits, no copy.
        triangles=corners.view(np.uint32),
        normals=normals,
        material_slots=slots if slots.any() else None,
        uvs=uvs,
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
    nonfinite_vertex = ~np.isfinite(positions).all(axis=1)
    # NaN compares False, so a NaN vertex is only "non-finite", never "distant".
    distant_vertex = (np.abs(positions) > MAX_COORDINATE).any(axis=1) & ~nonfinite_vertex
    nonfinite = nonfinite_vertex[corners].any(axis=1)
    distant = distant_vertex[corners].any(axis=1) & ~nonfinite
    bad = nonfinite | distant
    # Non-finite points would give NaN crosses (and overflow warnings): use 0.
    points = np.where(bad[:, None, None], 0.0, positions[corners].astype(np.float64))
    cross = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    length = np.linalg.norm(cross, axis=1)
    zero_area = (length == 0.0) & ~bad
    keep = ~(bad | zero_area)
    repaired = 0
    if normals is not None:
        corner_length = np.linalg.norm(normals, axis=2)
        broken = ~(np.isfinite(corner_length) & (corner_length > 0.0)) & keep[:, None]
        repaired = int(broken.sum())
        if repaired:
            face = cross / np.where(length > 0.0, length, 1.0)[:, None]
            rows, columns = np.nonzero(broken)
            normals[rows, columns] = face[rows]
    sanitised = Sanitised(
        nonfinite=int(nonfinite.sum()),
        distant=int(distant.sum()),
        zero_area=int(zero_area.sum()),
        normals=repaired,
    )
    return keep, sanitised


def _compact(positions, corners):
    """Only the vertices `corners` uses (so no NaN vertex stays), renumbered."""
    used = np.zeros(len(positions), dtype=bool)
    used[corners] = True
    renumber = np.cumsum(used, dtype=np.int32) - 1
    return np.ascontiguousarray(positions[used]), np.ascontiguousarray(renumber[corners])


def _uv_map(obj, uv_maps):
    # The UV map the first textured material of the object asks for, or None.
    return next((uv_maps[m] for m in _slot_materials(obj) if m in uv_maps), None)


def _corner_uvs(mesh, uv_map, name, warnings):
    """float32[M,3,2]: the UV of each loop triangle's corners, from the UV map
    named `uv_map` or, for "" or a map the mesh lacks, the active render one."""
    layers = mesh.uv_layers
    if len(layers) == 0:
        warnings.append(f"Whitted: mesh '{name}' has no UV map; its textures read UV (0, 0)")
        return None
    layer = layers.get(uv_map) if uv_map else None
    if layer is None:
        if uv_map:
            warnings.append(
                f"Whitted: mesh '{name}' has no UV map '{uv_map}'; using the active render one"
            )
        layer = next((candidate for candidate in layers if candidate.active_render), layers[0])
    loop_uvs = np.empty((len(mesh.loops), 2), dtype=np.float32)
    layer.data.foreach_get("uv", loop_uvs.reshape(-1))
    triangles = mesh.loop_triangles
    loops = np.empty((len(triangles), 3), dtype=np.int32)
    triangles.foreach_get("loops", loops.reshape(-1))
    return loop_uvs[loops]


def _slot_materials(obj):
    # The evaluated object's slots already resolve object- versus data-linked materials.
    names = tuple(
        slot.material.name_full if slot.material is not None else DEFAULT_MATERIAL
        for slot in obj.material_slots
    )
    return names or (DEFAULT_MATERIAL,)
