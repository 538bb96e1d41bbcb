"""The memory guard: a render that would not fit is refused before it allocates.

A scene that does not fit (a huge subdivision, a giant resolution, millions of
unique meshes) would otherwise run until the operating system kills Blender,
and the artist's unsaved work with it. Before anything large is allocated, the
memory a render needs is estimated from counts Blender already has (triangles
of each distinct evaluated mesh, instances, texels of the images the materials
use, every tile of a UDIM image, pixels, curve keys and points) and compared
with the memory available (MemAvailable) or the budget set in the environment
variable WHITTED_MEMORY_BUDGET (MiB, for farms that share machines).

The costs are what Whitted adds beyond Blender's own memory, measured by
whitted_tools bench-memory on the performance scenes (docs/MEMORY.md states how
close the estimate comes).
"""

import os
from dataclasses import dataclass, replace

import bpy

from .export import ExportError
from .export.curves import STRAND_TYPES, hair_keys, hair_systems
from .export.world import map_size
from .preferences import memory_budget_mib

MIB = 1024 * 1024
# The native module and the libraries it loads (Embree, TBB), its threads and
# Embree's device (docs/MEMORY.md: the demo at 480x270 takes 18 MiB in all).
BASE_BYTES = 12 * MIB
# A triangle's share of the mesh arrays, its BVH and the export's temporaries
# (docs/PERFORMANCE.md: 105-121 B beyond Blender's own).
TRIANGLE_BYTES = 120
# An instance: its native record, its Embree instance and the exporter's data
# (docs/MEMORY.md: about 750 B on the 10,000-instance scene).
INSTANCE_BYTES = 800
# A pixel: the film (RGBA, the ray cost, sums and counts) and the render result's
# passes that Blender allocates for Whitted.
PIXEL_BYTES = 40
# A texel: float RGBA read from Blender, then the native texture's copy.
TEXEL_BYTES = 32
# A curve key or a point: 16 B of keys (x, y, z, radius), Embree's curve BVH and the
# export's temporaries (co_hair's keys as float64 before they are packed).
# whitted_tools bench-memory's fur scene (900,000 keys) measured about 140-175 B a key
# beyond the rest of its estimate (docs/MEMORY.md).
KEY_BYTES = 160
# A texel of the world light's importance map (native scene/world_light.h): its
# conditional CDF and density as floats, and its weight as a double while it is built.
MAP_TEXEL_BYTES = 16


@dataclass(frozen=True)
class MemoryEstimate:
    triangles: int  # of the distinct meshes exported (an instanced mesh once)
    instances: int
    texels: int
    pixels: int
    keys: int = 0  # curve keys and points: hair, Curves objects, point clouds
    map_texels: int = 0  # the world light's importance map
    # The Volume objects' grids as the native module holds them (VolumeObject.bytes):
    # known only once the sync has read them (check_volumes).
    volume_bytes: int = 0

    @property
    def parts(self):
        """(what, bytes) of the estimate, largest first."""
        parts = [
            (f"{self.triangles:,} triangles", self.triangles * TRIANGLE_BYTES),
            (f"{self.instances:,} instances", self.instances * INSTANCE_BYTES),
            (f"{self.texels:,} texels of textures", self.texels * TEXEL_BYTES),
            (f"{self.pixels:,} pixels", self.pixels * PIXEL_BYTES),
            (f"{self.keys:,} curve keys and points", self.keys * KEY_BYTES),
            (
                f"{self.map_texels:,} texels of the world's light map",
                self.map_texels * MAP_TEXEL_BYTES,
            ),
            ("the Volume objects' grids", self.volume_bytes),
        ]
        return sorted(parts, key=lambda part: -part[1])

    @property
    def bytes(self):
        return BASE_BYTES + sum(size for _, size in self.parts)


def estimate(depsgraph, pixels):
    """The MemoryEstimate of rendering evaluated `depsgraph` at `pixels` pixels.

    Reads only counts: the triangles of a polygon mesh are its loops less twice
    its faces (an n-gon makes n - 2 triangles); nothing is triangulated or copied.
    """
    triangles = 0
    instances = 0
    keys = 0
    seen = set()
    render = depsgraph.mode == "RENDER"
    for object_instance in depsgraph.object_instances:
        obj = object_instance.object
        if obj.type in STRAND_TYPES and obj.data.as_pointer() not in seen:
            seen.add(obj.data.as_pointer())
            keys += len(obj.data.points)
        if object_instance.show_particles and obj.type == "MESH" and obj.name not in seen:
            seen.add(obj.name)
            keys += sum(hair_keys(system, render) for system in hair_systems(obj, render))
        if obj.type != "MESH" or not object_instance.show_self:
            continue
        instances += 1
        mesh = obj.data
        address = mesh.as_pointer()
        if address not in seen:
            seen.add(address)
            triangles += max(0, len(mesh.loops) - 2 * len(mesh.polygons))
    texels = sum(
        image_texels(block) for block in depsgraph.ids if isinstance(block, bpy.types.Image)
    )
    width, height = map_size(depsgraph.scene.world)
    return MemoryEstimate(triangles, instances, texels, pixels, keys, width * height)


def image_texels(image):
    """The texels of an image: of every tile of a UDIM image (each is read)."""
    if image.source == "TILED":
        return sum(tile.size[0] * tile.size[1] for tile in image.tiles)
    return image.size[0] * image.size[1]


def budget():
    """(bytes, where the figure comes from): WHITTED_MEMORY_BUDGET (MiB) when set,
    else the add-on preference's budget when set, else the memory the system says
    is available now; (None, ...) when none is known (no /proc/meminfo)."""
    setting = os.environ.get("WHITTED_MEMORY_BUDGET")
    if setting:
        try:
            return int(float(setting) * MIB), f"the budget WHITTED_MEMORY_BUDGET={setting} MiB"
        except ValueError:
            raise ExportError(
                f"Whitted: WHITTED_MEMORY_BUDGET={setting!r} is not a number of MiB"
            ) from None
    preference = memory_budget_mib()
    if preference > 0:
        return preference * MIB, "the memory budget in the add-on's preferences"
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024, "the memory available"
    except OSError:
        pass  # not Linux: no guard rather than a wrong one
    return None, "unknown"


def check(depsgraph, pixels):
    """Raise ExportError, saying what is too big and by how much, when the render
    of `depsgraph` at `pixels` pixels would need more than the budget; else return
    its MemoryEstimate."""
    needed = estimate(depsgraph, pixels)
    _refuse_over_budget(needed)
    return needed


def check_volumes(needed, volume_bytes):
    """`needed` (a MemoryEstimate) with the grids the sync read; raises ExportError as
    check() does when the render would no longer fit. The grids are read by then: the
    render, not the read, is refused."""
    if not volume_bytes:
        return needed
    needed = replace(needed, volume_bytes=volume_bytes)
    _refuse_over_budget(needed)
    return needed


def _refuse_over_budget(needed):
    limit, source = budget()
    if limit is not None and needed.bytes > limit:
        parts = ", ".join(f"{what} {size / MIB:,.0f} MiB" for what, size in needed.parts)
        raise ExportError(
            f"Whitted: this render needs about {needed.bytes / MIB:,.0f} MiB, "
            f"{(needed.bytes - limit) / MIB:,.0f} MiB more than {source} "
            f"({limit / MIB:,.0f} MiB): {parts}. Nothing was rendered; lower the "
            "resolution or the geometry (subdivision levels, instance counts)."
        )
