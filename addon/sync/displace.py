"""True displacement: the vertices of a mesh whose material's Displacement method is
Displacement Only or Displacement and Bump, moved as Cycles moves them without adaptive
subdivision (its GeometryManager::displace).

The material's exporter gives the program that computes the world displacement
(export/material.py Displacement, the output's Displacement lowered once for the bump
and for this); the native `Scene.displace` runs it once per vertex, at the vertex of the
first triangle that uses it and displaces (that triangle's UVs and attributes there),
with the vertex's normal as the shading normal, adds it to the vertex in object space
and, for Displacement Only, gives the displaced faces' vertices new normals. Called on
the main thread while a geometry is exported (sync/scene.py), before its BVH is built.
"""

from ..export.geometry_key import key_owner
from ..export.instance import slot_materials
from ..export.nodes import warn


def slot_displacements(obj, displacements):
    """The export.material.Displacement of each material slot of evaluated `obj` (None for
    a slot whose material moves no vertex), from {material name: Displacement}; () when
    no slot moves any."""
    found = tuple(displacements.get(name) for name in slot_materials(obj))
    return found if any(d is not None for d in found) else ()


def displace(native, scene, mesh, displacement, object_instance):
    """Move the vertices of native `mesh` (object space) by `displacement` (per slot, as
    slot_displacements gives it), evaluated with the object-to-world matrix of
    `object_instance` (the first instance of the geometry, as Cycles takes the first
    object that uses a mesh); how many vertices moved. The images the programs sample are
    the native scene's, set with the materials before the geometries."""
    slots = [
        None
        if d is None
        # Displacement Only: the vertex normals of its faces are made again from the
        # moved faces; Displacement and Bump keeps them (its bump bends them).
        else (d.program.native(native), d.output, d.method == "DISPLACEMENT")
        for d in displacement
    ]
    return scene.displace(mesh, slots, object_instance.matrix_world)


def adaptive_warning(obj, experimental, warnings):
    """Say that evaluated `obj`, whose material moves vertices, asks for Cycles' adaptive
    subdivision (microdisplacement), which Whitted does not do: its vertices move at the
    mesh's own resolution. Blender 3.x-4.x: Object > Subdivision > Adaptive Subdivision
    (object.cycles.use_adaptive_subdivision) with the Experimental feature set
    (`experimental`); 4.5+: a Subdivision Surface modifier's Adaptive Subdivision, the
    last modifier."""
    settings = getattr(obj.original, "cycles", None)
    asked = experimental and getattr(settings, "use_adaptive_subdivision", False)
    modifiers = obj.original.modifiers
    if modifiers and modifiers[-1].type == "SUBSURF":
        asked = asked or getattr(modifiers[-1], "use_adaptive_subdivision", False)
    if not asked:
        return
    message = (
        f"Whitted: object '{obj.name}': adaptive subdivision (microdisplacement) is not "
        "rendered; its vertices are displaced at the mesh's own resolution"
    )
    warn(warnings, message)


def displacement_effect(displaced):
    """The report's entry ({name, on, why}) for the vertices moved, from {geometry key:
    vertices moved}; None where none moved."""
    if not displaced:
        return None
    parts = (f"{n:,} vertices of '{key_owner(key)}'" for key, n in sorted(displaced.items()))
    return {"name": "displacement", "on": True, "why": "displaced " + ", ".join(parts)}
