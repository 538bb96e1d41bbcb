"""A Volume object's grids (issue 48, Volume objects), as plain data: the OpenVDB file
that holds them, which of its grids the object's material reads, where the object is,
and its Volume > Render settings (VolumeObjectData). The native module reads the grids
(native scene/vdb_file.h) and samples them (scene/volume_object.h); the sync renders
the object as Cycles' mesh around its grids' blocks of voxels (native
VolumeObject::bound_mesh, shaped by Volume > Render > Clipping) filled by its material
read with its grids (sync/scene.py, export/material.py grid_material), marched as a
heterogeneous medium.

Where the grids come from (the same in Blender 3.4 and 5.x):

- A Volume whose grids are its file's, unchanged (no modifier enabled for render): the
  file the evaluated Volume loaded for this frame, `VolumeGrids.frame_filepath`, which
  Blender resolves from `Volume.filepath` (relative to the .blend or its library), the
  image sequence's frame (`frame_start`, `frame_offset`, `frame_duration`, the
  sequence mode) and the scene's frame.
- Otherwise (a Mesh to Volume or Volume Displace modifier, geometry nodes, a packed
  file, whose `frame_filepath` still names the file it was packed from): the evaluated
  grids, written by Blender's own `VolumeGrids.save(path)` to a file in the folder the
  caller gives (a temporary one, deleted once the grids are read).

Which grids: those the material reads through Principled Volume's Density, Color and
Temperature Attribute inputs (Temperature only where Blackbody Intensity is above 0 or
linked: it scales nothing else), the Volume Info node's outputs and the Attribute nodes
naming one of those (fixed names density, color, flame, temperature). A Volume object
without a material is shaded by Cycles' default volume, a Principled Volume of the
node's defaults: its grid "density".

Units: the object's transform `matrix_world` takes object space to Blender's world,
which is Whitted's (no axis change); a grid's own transform (index space -> object
space, its voxel size) travels in the file. Step size is in Blender units of the space
Volume > Render > Space names (object or world); 0 lets Cycles pick it from the voxel
size.
"""

import os
from dataclasses import dataclass

import bpy
import numpy as np

from .nodes.graph import source
from .nodes.input_nodes import VOLUME_INFO_GRIDS

# The native VolumeObject's roles (scene/volume_object.h GridRole), in its order.
ROLES = ("density", "color", "temperature", "flame")
# Principled Volume's inputs naming a grid, by role.
PRINCIPLED_ATTRIBUTES = {
    "density": "Density Attribute",
    "color": "Color Attribute",
    "temperature": "Temperature Attribute",
}
# Where Cycles puts a voxel's value: at its cube's centre before Blender 5.0, from 5.0 at
# its integer index point, half a voxel apart. Seen on a spot-lit Mesh to Volume cube
# against Cycles (Whitted centred: summed luminance 0.9876, 0.9991, 1.0327 in 3.4,
# 4.5.15, 5.0.1, the last lopsided; at the index point in 5.0.1: 1.0001), the same with
# its grids saved to a .vdb file and read from it; and on a baked fluid domain in 3.4
# (centred SSIM 0.9993, at the index points 0.9658; 5.0's bpy module fails to bake here).
VOXELS_CENTRED = bpy.app.version < (5, 0, 0)
# Cycles' default volume: a Principled Volume of the node's defaults.
DEFAULT_GRIDS = {"density": "density"}
# Blender's grid data types (VolumeGrid.data_type) the native reader reads, and whether
# each is a vector (colour) grid.
READABLE_TYPES = {"FLOAT": False, "DOUBLE": False, "VECTOR_FLOAT": True, "VECTOR_DOUBLE": True}


@dataclass(frozen=True)
class VolumeObjectData:
    """A Volume object's grids and placement (module docstring)."""

    name: str  # the object's name
    material: str | None  # its material's name (the first slot's), None: Cycles' default
    path: str  # the OpenVDB file to read (absolute)
    written: bool  # the evaluated grids, saved by this export to `path`
    grids: tuple  # ((role, grid name), ...), roles in ROLES' order
    to_world: np.ndarray  # float64[4, 4], row-major, object space -> world
    space: str  # Volume > Render > Space: "OBJECT" | "WORLD"
    step_size: float  # Blender units of `space`; 0: automatic
    clipping: float  # values below it are empty space to Cycles' bounds
    precision: str  # "FULL" | "HALF" | "VARIABLE": read as 32-bit floats whatever it says
    centred: bool  # a voxel's value at its cube's centre, else at its index point (VOXELS_CENTRED)


class VolumeSkipped(ValueError):
    """A Volume object with nothing to read; the message says why."""


def volume_object_data(object_instance, folder):
    """The VolumeObjectData of a Volume object instance of an evaluated depsgraph;
    evaluated grids are written into `folder`. Raises VolumeSkipped."""
    obj = object_instance.object
    volume = obj.data
    grids = volume.grids
    if not grids.is_loaded:
        # A render's depsgraph loads a file's grids only when asked (seen in Blender 3.4:
        # a .vdb read by no earlier evaluation listed none), as Cycles' sync asks.
        grids.load()
    if grids.error_message:
        original = obj.original.data
        path = bpy.path.abspath(original.filepath, library=original.library)
        raise VolumeSkipped(f"Blender could not load its grids from {path}: {grids.error_message}")
    available = {grid.name: grid.data_type for grid in grids}
    modified = any(modifier.show_render for modifier in obj.original.modifiers)
    if not available:
        raise VolumeSkipped(_why_empty(obj.original.data, grids, modified))
    material = grid_object_material(obj)
    roles = []
    for role, name in material_grids(material).items():
        kind = available.get(name)
        if kind in READABLE_TYPES and READABLE_TYPES[kind] == (role == "color"):
            roles.append((role, name))
    if not roles:
        readable = sorted(name for name, kind in available.items() if kind in READABLE_TYPES)
        raise VolumeSkipped(
            f"its material reads none of its grids ({', '.join(sorted(available))}; readable: "
            f"{', '.join(readable) or 'none'})"
        )
    path, written = _grid_file(obj, folder, modified)
    render = volume.render
    return VolumeObjectData(
        name=obj.original.name,
        material=None if material is None else material.original.name_full,
        path=path,
        written=written,
        grids=tuple(roles),
        to_world=np.array(object_instance.matrix_world, dtype=np.float64),
        space=render.space,
        step_size=float(render.step_size),
        clipping=float(render.clipping),
        precision=render.precision,
        centred=VOXELS_CENTRED,
    )


def grid_material_name(material, grids):
    """The native material a Volume object (or a fluid domain) renders with: `material`
    (a name, or None) read with its `grids` (((role, grid name), ...): export/material.py
    grid_material), one per material and set of grids; the unit separator keeps it apart
    from any material's own name."""
    named = ",".join(f"{role}={name}" for role, name in grids)
    return f"{material or ''}\x1fgrids:{named}"


# A fluid domain's grids as Cycles names them (its smoke attributes), and the
# FluidDomainSettings array and channels of each.
FLUID_GRIDS = {
    "density": ("density_grid", 1),
    "color": ("color_grid", 3),
    "flame": ("flame_grid", 1),
    "heat": ("heat_grid", 1),
    "temperature": ("temperature_grid", 1),
}


@dataclass(frozen=True)
class FluidGrids:
    """A baked gas domain's grids the material reads, as dense arrays (export/volume_object.py
    FLUID_GRIDS), and where they lie."""

    material: str | None  # its material's name (the first slot's), None: Cycles' default
    grids: tuple  # ((role, grid name), ...), roles in ROLES' order
    arrays: tuple  # float32 arrays, one per grid, `channels` a voxel, x fastest
    channels: tuple  # by grid
    resolution: tuple  # voxels a side (x, y, z)
    index_to_object: np.ndarray  # float64[4, 4], row-major: voxel (i, j, k) -> object space
    clipping: float  # the domain's Clipping: as VolumeObjectData's
    centred: bool  # as VolumeObjectData's


def fluid_domain(obj):
    """The settings of `obj`'s gas fluid domain shown in renders (a Fluid modifier of type
    DOMAIN, gas), or None."""
    for modifier in obj.modifiers:
        if modifier.type == "FLUID" and modifier.fluid_type == "DOMAIN" and modifier.show_render:
            settings = modifier.domain_settings
            return settings if settings.domain_type == "GAS" else None
    return None


def fluid_grids(obj, settings):
    """FluidGrids of evaluated mesh object `obj`, whose gas domain is `settings`, or None
    where its material reads none of its grids or nothing is baked for this frame.

    Where they lie: Cycles fills the domain mesh's texture space with the grid (its
    Generated coordinates [0, 1]^3 across the domain's resolution), voxel (i, j, k) the
    cube from texspace_location - texspace_size + (i, j, k) * 2 texspace_size / resolution."""
    material = grid_object_material(obj)
    resolution = tuple(int(n) for n in settings.domain_resolution)
    voxels = resolution[0] * resolution[1] * resolution[2]
    roles, arrays, channels = [], [], []
    for role, name in material_grids(material).items():
        if name not in FLUID_GRIDS or (name == "color") != (role == "color"):
            continue
        attribute, width = FLUID_GRIDS[name]
        values = getattr(settings, attribute)
        if len(values) != voxels * width:
            continue  # not baked for this frame
        array = np.empty(len(values), dtype=np.float32)
        values.foreach_get(array)
        roles.append((role, name))
        arrays.append(array)
        channels.append(width)
    if not roles:
        return None
    mesh = obj.data
    size = 2.0 * np.array(mesh.texspace_size, dtype=np.float64)
    lower = np.array(mesh.texspace_location, dtype=np.float64) - 0.5 * size
    index_to_object = np.diag([*(size / np.array(resolution)), 1.0])
    index_to_object[:3, 3] = lower
    return FluidGrids(
        material=None if material is None else material.original.name_full,
        grids=tuple(roles),
        arrays=tuple(arrays),
        channels=tuple(channels),
        resolution=resolution,
        index_to_object=index_to_object,
        clipping=float(settings.clipping),
        centred=VOXELS_CENTRED,
    )


def material_grids(material):
    """{role: grid name} that `material` reads (module docstring), roles in ROLES' order."""
    if material is None or material.node_tree is None:
        return dict(DEFAULT_GRIDS)
    output = material.node_tree.get_output_node("CYCLES")
    socket = None if output is None else output.inputs.get("Volume")
    found = {}
    for node in _volume_nodes(socket):
        if node.bl_idname == "ShaderNodeVolumePrincipled":
            for role, input_name in PRINCIPLED_ATTRIBUTES.items():
                if role == "temperature" and not _blackbody(node):
                    continue
                name = node.inputs[input_name].default_value
                if name:
                    found.setdefault(role, name)
        elif node.bl_idname == "ShaderNodeVolumeInfo":
            for output_name, grid in VOLUME_INFO_GRIDS.items():
                if node.outputs[output_name].is_linked:
                    found.setdefault(grid, grid)
        elif node.bl_idname == "ShaderNodeAttribute" and node.attribute_type == "GEOMETRY":
            # An Attribute node reads a grid by name: one of the roles' fixed names.
            name = node.attribute_name
            if name in ROLES:
                found.setdefault(name, name)
    return {role: found[role] for role in ROLES if role in found}


def _volume_nodes(socket):
    """The nodes upstream of `socket` (inside node groups too)."""
    if socket is None:
        return []
    nodes = []
    seen = set()
    pending = [(socket, ())]
    while pending:
        current, scope = pending.pop()
        found, _ = source(current, scope)
        if found is None:
            continue
        key = (found.node.as_pointer(), tuple(group.as_pointer() for group in found.scope))
        if key in seen:
            continue
        seen.add(key)
        nodes.append(found.node)
        pending.extend((given, found.scope) for given in found.node.inputs)
    return nodes


def _blackbody(node):
    # Whether Principled Volume's Temperature reaches its output: blackbody emission on.
    socket = node.inputs["Blackbody Intensity"]
    return socket.is_linked or socket.default_value > 0.0


def grid_object_material(obj):
    # A Volume object is shaded by its first material (Cycles: one shader a volume).
    return next((slot.material for slot in obj.material_slots if slot.material), None)


def _grid_file(obj, folder, modified):
    """(path, written): the file holding the evaluated grids (module docstring)."""
    volume = obj.data
    original = obj.original
    path = volume.grids.frame_filepath
    # Packing is the original Volume's (an evaluated copy has no packed_file); its
    # frame_filepath still names the file it was packed from, which may be gone.
    packed = getattr(original.data, "packed_file", None) is not None
    if not modified and path and not packed:
        return bpy.path.abspath(path, library=original.data.library), False
    target = os.path.join(folder, f"{_file_name(original.name)}.vdb")
    if not volume.grids.save(target):
        raise VolumeSkipped(f"Blender could not write its evaluated grids to {target}")
    return target, True


def _file_name(name):
    # An object's name as a file name: letters, digits and -_. kept, the rest '_'.
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name) or "volume"


def _why_empty(volume, grids, modified):
    """Why the evaluated grids `grids` of original Volume `volume` are none."""
    if modified:
        return "its modifiers make no grids"
    if not volume.filepath:
        return "it has no grids (no OpenVDB file, no modifier)"
    if volume.is_sequence and not grids.frame_filepath:
        return f"its sequence has no file for frame {grids.frame}"
    path = bpy.path.abspath(volume.filepath, library=volume.library)
    if not os.path.exists(path):
        return f"its file {path} does not exist"
    return f"its file {path} holds no grids"
