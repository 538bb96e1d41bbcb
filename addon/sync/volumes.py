"""The Volume objects of a sync's walk: each exported (export/volume_object.py) and its
grids read by the native module at once, so that a file of evaluated grids, written to
a temporary folder, is deleted as soon as it is read. Grids read from a file that has
not changed since the last walk (same path, size and time, same grids) are kept.

The walk (sync/scene.py) renders each one read as an instance of its mesh (the blocks of
voxels that reach its Clipping, as Cycles builds a Volume's mesh) filled by its
material read with its grids; the report says why any other was skipped (a missing or
empty file, grids the material does not read, an unreadable grid).
"""

import os
import tempfile
from dataclasses import dataclass

from ..export.volume_object import (
    VolumeObjectData,
    VolumeSkipped,
    volume_object_data,
)


@dataclass(frozen=True)
class VolumeRead:
    """A Volume object's grids as the native module holds them."""

    label: str  # the object's name, as the report names it
    key: tuple  # the file they were read from (None for written grids: read each time)
    grids: tuple  # whitted_native.VolumeGrid by export.volume_object.VolumeObjectData.grids
    native: object  # whitted_native.VolumeObject: the grids placed in the world
    data: VolumeObjectData  # what was exported
    # Its bound_mesh (rays enter its medium through it), built by this walk where its
    # grids were read anew or its Clipping, which shapes the mesh, changed; else None: the
    # last walk's mesh, the same, stands.
    mesh: object


class VolumeReads:
    """The Volume objects met by one walk, given the last walk's ({name: VolumeRead})."""

    def __init__(self, native, previous):
        self._native = native
        self._previous = previous
        # Made at the first evaluated grids to write; removed by close(), or when
        # collected if an exception ends the walk first.
        self._folder = None
        self.read = {}  # instance name -> VolumeRead
        self.skipped = {}  # instance name -> (the object's name, why)

    def add(self, name, object_instance):
        """Export and read the Volume object `object_instance` (an evaluated depsgraph's,
        iterated now) under `name` (an instance's: a geometry-nodes volume is an instance of
        the object whose modifier makes it). Its VolumeRead, or None where it is skipped."""
        label = object_instance.object.original.name
        try:
            data = volume_object_data(object_instance, self._temporary_folder())
        except VolumeSkipped as why:
            self.skipped[name] = (label, str(why))
            return None
        key = None if data.written else _file_key(data)
        kept = self._previous.get(name)
        fresh = not (key is not None and kept is not None and kept.key == key)
        if not fresh:
            grids = kept.grids  # the same file: only the placement may have changed
        else:
            try:
                grids = tuple(
                    self._native.read_volume_grids(data.path, [grid for _, grid in data.grids])
                )
            except self._native.VolumeFileError as error:
                self.skipped[name] = (label, str(error))
                return None
            finally:
                if data.written:
                    os.remove(data.path)
        by_role = {role: grid for (role, _), grid in zip(data.grids, grids, strict=True)}
        try:
            volume = self._native.VolumeObject(
                data.to_world,
                space=data.space,
                step_size=data.step_size,
                centred=data.centred,
                clipping=data.clipping,
                **by_role,
            )
        except ValueError as error:
            self.skipped[name] = (label, str(error))
            return None
        names = ", ".join(grid for _, grid in data.grids)
        if volume.world_bounds is None:
            self.skipped[name] = (label, f"its grids ({names}) have no active voxels")
            return None
        mesh = None
        if fresh or kept.data.clipping != data.clipping:
            mesh = volume.bound_mesh()
            if mesh.triangle_count == 0:
                why = f"no voxel of its grids ({names}) reaches its Clipping ({data.clipping:g})"
                self.skipped[name] = (label, why)
                return None
        read = VolumeRead(label, key, grids, volume, data, mesh)
        self.read[name] = read
        return read

    def close(self):
        """Delete the temporary folder (if one was made)."""
        if self._folder is not None:
            self._folder.cleanup()
            self._folder = None

    def _temporary_folder(self):
        if self._folder is None:
            self._folder = tempfile.TemporaryDirectory(prefix="whitted-volumes-")
        return self._folder.name

    def warnings(self):
        """The report's lines: the Volume objects skipped, and why (those read are in the
        volumes' reason, native integrator/analysis.cpp)."""
        return [
            f"Whitted: Volume object '{self.skipped[name][0]}' skipped: {self.skipped[name][1]}"
            for name in sorted(self.skipped)
        ]

    @property
    def bytes(self):
        """Bytes the grids read hold natively."""
        return sum(read.native.bytes for read in self.read.values())


def _file_key(data):
    # A file's grids are the same while its path, size, time and the grids asked are;
    # None for a file that is not there (the native read says so).
    try:
        status = os.stat(data.path)
    except FileNotFoundError:
        return None
    return (data.path, status.st_size, status.st_mtime_ns, data.grids)
