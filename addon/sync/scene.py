"""The live native scene, brought up to date from the depsgraph (as Cycles' sync).

A `SceneSync` keeps one `whitted_native.Scene` and what was exported into it.
Its first `sync` exports everything; each later one reads `depsgraph.updates`
(sync/changes.py) and changes only what changed:

- an object moved: its instance's transform (no mesh export, no mesh BVH);
- a geometry changed: that geometry, once for all its instances;
- a material or node tree: that material, and its textures only when an image
  or the texture filter changed (a material that starts reading UVs re-exports
  the meshes that use it, which then carry UVs);
- a light, the world, the sync's parameters: those alone;
- objects added, removed or hidden, an instancer, anything else it cannot
  place: every instance of the depsgraph is compared with what was exported
  (removals are never listed in the updates), and only the differences change.

Every key survives re-evaluation (export/mesh.py `geometry_key`,
export/instance.py `instance_name`), and the native scene orders everything by
name, so after any sequence of edits the synced scene renders the same pixels
as a full export of the edited scene (tests/blender/test_sync.py).

Only the main thread may call `sync`: it reads bpy data. A running job keeps
its own compiled snapshot, so the native scene may change under it.
"""

import time
from dataclasses import asdict, dataclass, field, fields, replace
from types import SimpleNamespace

import bpy
import numpy as np

from ..export.curves import STRAND_TYPES, hair_systems, particle_hair_data, strands_data
from ..export.geometry_key import GeometryKeys
from ..export.instance import DEFAULT_MATERIAL, instance_data, instance_name
from ..export.light import instance_light
from ..export.light_linking import NO_LINKS, light_links
from ..export.material import (
    convert_material,
    default_material,
    grid_material,
    medium_material,
)
from ..export.mesh import export_geometry, is_renderable_mesh
from ..export.mesh_layers import (
    NO_NEEDS,
    MeshNeeds,
    attribute_keys,
    object_needs,
    object_uv_map,
)
from ..export.nodes.values import UNBOUNDED_AO_DISTANCE
from ..export.properties import view_layer_attribute
from ..export.sanitise import Sanitised
from ..export.texture import convert_textures
from ..export.volume import Medium, volume_bounces_warning
from ..export.volume_object import (
    fluid_domain,
    fluid_grids,
    grid_material_name,
    grid_object_material,
)
from ..export.world import ao_distance, convert_world
from . import native_data
from .changes import classify
from .displace import adaptive_warning, displace, displacement_effect, slot_displacements
from .volumes import VolumeReads

# What an original object contributes, as the last walk over the instances saw it.
_MESH = "mesh"  # a mesh object shown as itself
_LIGHT = "light"
_INSTANCER = "instancer"  # its instances (or generated geometry) come from it
_VOLUME = "volume"  # a Volume object (sync/volumes.py), read again by a walk when it changes
_OTHER = "other"  # cameras, empties without instances, ...


@dataclass(frozen=True)
class SyncParams:
    """The settings besides the depsgraph that change what is exported."""

    light_samples: int  # feelers per axis of a sized light whose own setting is 0
    texture_filter: str  # AUTHORED | CLOSEST
    ambient_strength: float  # scales the world's ambient light
    local_model: str = "BLENDER"  # scene.whitted.local_model: how materials are mapped
    # A view layer's UV pass is on: every mesh sends its active render UV map, not only
    # those whose textures read one.
    uv_pass: bool = False
    # The World's AO distance (export/world.py ao_distance), read by Ambient Occlusion
    # nodes of Distance 0.
    ao_distance: float = UNBOUNDED_AO_DISTANCE
    # Cycles' Feature Set is Experimental (3.x-4.x: where an object's Adaptive
    # Subdivision applies; sync/displace.py adaptive_warning).
    experimental: bool = False
    # What moves within the shutter (export/motion.py MotionData; F12 with motion blur
    # on), None otherwise: the instances it names carry their transforms over it.
    motion: object = field(default=None, compare=False)

    @classmethod
    def of(cls, scene, quality):
        """The parameters of Blender `scene` rendered at properties.presets.Quality."""
        return cls(
            light_samples=quality.light_samples,
            texture_filter=quality.texture_filter,
            ambient_strength=scene.whitted.ambient_strength,
            local_model=scene.whitted.local_model,
            uv_pass=any(layer.use_pass_uv for layer in scene.view_layers),
            ao_distance=ao_distance(scene.world),
            experimental=getattr(getattr(scene, "cycles", None), "feature_set", "")
            == "EXPERIMENTAL",
        )


@dataclass
class SyncReport:
    """What one sync did: counts of what it (re-)exported, and its time."""

    full: bool = False  # the first sync: everything exported
    walked: bool = False  # every depsgraph instance compared with the exported ones
    meshes: int = 0  # geometries exported (mesh BVHs built)
    instances: int = 0  # instances added or changed
    materials: int = 0
    textures: int = 0
    lights: int = 0
    world: bool = False
    removed: int = 0  # meshes, instances, materials, textures and lights removed
    seconds: float = 0.0

    @property
    def changed(self):
        """Whether the native scene changed (and so the image may have)."""
        counts = (self.meshes, self.instances, self.materials, self.textures, self.lights)
        return any(counts) or self.world or bool(self.removed)

    def as_dict(self):
        return asdict(self)

    def describe(self):
        """A short line for the status bar, e.g. 'sync 1.2 ms: 1 instance'."""
        parts = [
            f"{count} {name if count == 1 else name + 's'}"
            for name, count in (
                ("mesh", self.meshes),
                ("instance", self.instances),
                ("material", self.materials),
                ("texture", self.textures),
                ("light", self.lights),
            )
            if count
        ]
        if self.world:
            parts.append("world")
        if self.removed:
            parts.append(f"{self.removed} removed")
        what = ", ".join(parts) or "nothing changed"
        return f"sync {1000.0 * self.seconds:.1f} ms: {what}"


@dataclass(frozen=True)
class _Geometry:
    has_primitives: bool  # triangles, curves or points: something a ray can hit
    uv_map: str | None  # the UV map it was exported with
    sanitised: Sanitised
    needs: MeshNeeds = NO_NEEDS  # the UV sets, attributes and tangents it carries
    # What moved its vertices: its slots' export.material.Displacement (None for a slot
    # that moves none), () when none does (sync/displace.py slot_displacements).
    displacement: tuple = ()
    displaced: int = 0  # how many vertices its displacement moved


class SceneSync:
    """One native scene and the rules that keep it equal to the depsgraph's."""

    def __init__(self, native):
        self._native = native
        self.scene = native.Scene()
        self._params = None  # SyncParams of the last sync; None before the first
        self._materials = {}  # name -> export.material.MaterialExport
        self._uv_maps = {}  # material name -> the UV map its textures read
        self._walked_uv_maps = {}  # the UV maps the meshes were last exported for
        self._needs = {}  # material name -> MeshNeeds its program reads
        self._info = frozenset()  # materials that read Object Info
        # Material name -> the Object and Instancer attributes it reads (by index).
        self._attributes = {}
        self._walked_needs = ({}, frozenset(), {})  # (needs, info, attributes) of the last walk
        # Material name -> the export.material.Displacement that moves its vertices, now
        # and at the last walk (a change exports the meshes that use it again).
        self._displacements = {}
        self._walked_displacements = {}
        self._textures = {}  # name -> texture spec (export.texture)
        self._geometry = {}  # geometry key -> _Geometry
        self._instances = {}  # instance name -> export.mesh.InstanceData
        self._lights = {}  # instance name -> export.light.LightData
        self._roles = {}  # original object name -> _MESH | _LIGHT | _INSTANCER | _OTHER
        self._instanced_light_data = set()  # light data-blocks shown by instances
        self._world = None  # export.world.WorldData
        self._links = NO_LINKS  # export.light_linking.LightLinks of the last sync
        self._volumes = {}  # instance name -> sync.volumes.VolumeRead (Volume objects)
        self._fluids = {}  # instance name -> VolumeObject of a gas domain's grids
        # Their materials read with their grids: native name -> (material name or None, grids).
        self._grid_materials = {}
        self._volume_warnings = []  # the last walk's report lines for Volume objects
        self.warnings = []  # of the last sync: what could not be exported as authored

    @property
    def sanitised(self):
        """Bad geometry dropped or repaired in the meshes exported now, totals."""
        total = Sanitised()
        for geometry in self._geometry.values():
            total += geometry.sanitised
        return total

    def _shown_changed(self, depsgraph):
        # Hiding or showing an object in the view layer updates only the Scene: the
        # objects the depsgraph evaluates tell (instances come from these).
        shown = {obj.original.name_full for obj in depsgraph.objects}
        return shown != self._roles.keys()

    def displacement_effect(self):
        """The report's entry for the vertices displacements moved ({name, on, why}), or
        None where no mesh is displaced."""
        return displacement_effect(
            {key: g.displaced for key, g in self._geometry.items() if g.displaced}
        )

    @property
    def volume_bytes(self):
        """Bytes the Volume objects' grids hold natively (for the memory guard)."""
        return sum(read.native.bytes for read in self._volumes.values()) + sum(
            volume.bytes for volume in self._fluids.values()
        )

    @property
    def light_count(self):
        return len(self._lights)

    @property
    def world_lights(self):
        """Whether the world lights the scene as a light (export.world.WorldLightData)."""
        return self._world is not None and self._world.light is not None and self._world.light.on

    def sync(self, depsgraph, params):
        """Bring the native scene up to date with evaluated `depsgraph`; a SyncReport.

        Raises the native module's ValueError when it refuses data."""
        started = time.perf_counter()
        first = self._params is None
        changes = None if first else classify(depsgraph.updates)
        report = SyncReport(full=first)
        self.warnings = warnings = []
        stale = self._stale_layer_attributes(depsgraph)
        if self._materials_touched(changes, params) or stale:
            self._sync_materials(depsgraph, changes, params, report, warnings, stale)
        # Light linking is the whole scene's: when it changes, every instance may change.
        # Reading it visits every object (44 ms for 10,000 in Blender 5.2), so an update
        # that only moved objects or edited materials, lights or the world keeps it.
        relinked = False
        if _may_relink(changes):
            links = light_links(depsgraph.objects)
            relinked = links != self._links
            self._links = links
        warnings.extend(self._links.warnings())
        if (
            relinked
            or self._needs_walk(changes, params)
            or (changes.scene and self._shown_changed(depsgraph))
        ):
            self._walk(depsgraph, changes, params, report, warnings)
        else:
            self._update_objects(depsgraph, changes, params, report, warnings)
        # What the last walk read of the Volume objects, or skipped, in every sync's report.
        warnings.extend(self._volume_warnings)
        if first or changes.world or changes.scene or params != self._params:
            self._sync_world(depsgraph.scene, params, report, warnings)
        world_medium = None if self._world is None else self._world.medium
        bounces = volume_bounces_warning(depsgraph.scene, self._materials.values(), world_medium)
        if bounces is not None:
            warnings.append(bounces)
        self._params = params
        report.seconds = time.perf_counter() - started
        return report

    # --- materials and textures ------------------------------------------------

    def _materials_touched(self, changes, params):
        if (
            changes is None
            or params.texture_filter != self._params.texture_filter
            or params.uv_pass != self._params.uv_pass
            or params.local_model != self._params.local_model
        ):
            return True
        # Objects added or given other materials list their materials' updates too;
        # a removed material can only go with a structural or geometry change.
        return bool(
            changes.materials
            or changes.images
            or changes.node_groups
            or changes.structure
            or changes.reshaped
            or changes.meshes
        )

    def _stale_layer_attributes(self, depsgraph):
        # The materials a view layer's, scene's or world's property they folded now reads
        # otherwise for (not every such edit is listed among the updates): a few property
        # reads, once a sync.
        view_layer = depsgraph.view_layer_eval
        return frozenset(n for n, m in self._materials.items() if _reads_otherwise(m, view_layer))

    def _sync_materials(self, depsgraph, changes, params, report, warnings, stale):
        # Every material the evaluated objects use is in the depsgraph.
        current = {
            block.original.name_full: block
            for block in depsgraph.ids
            if isinstance(block, bpy.types.Material)
        }
        redo = (
            changes is None
            or changes.node_groups
            or params.local_model != self._params.local_model
            or params.ao_distance != self._params.ao_distance
        )
        if redo:
            # What an object without a material renders with.
            default = default_material(params.local_model)
            self.scene.set_material(
                DEFAULT_MATERIAL, native_data.native_material(self._native, default)
            )
        view_layer = depsgraph.view_layer_eval
        for name, material in current.items():
            known = self._materials.get(name)
            if redo or known is None or name in changes.materials or name in stale:
                exported = replace(
                    convert_material(
                        material,
                        warnings,
                        local_model=params.local_model,
                        ao_distance=params.ao_distance,
                        view_layer=view_layer,
                    ),
                    pass_index=material.pass_index,  # for the IndexMA pass
                )
                if exported != self._materials.get(name):
                    self.scene.set_material(
                        name, native_data.native_material(self._native, exported)
                    )
                    self._materials[name] = exported
                    report.materials += 1
        for name, (material, grids) in list(self._grid_materials.items()):
            # A Volume object's material edited (a removed one goes with the walk).
            if (
                material is not None
                and material in current
                and (redo or material in changes.materials)
            ):
                self._set_grid_material(name, current[material], grids, report, warnings)
        for name in self._materials.keys() - current.keys():
            # Left in the native scene until no instance names it (after the walk,
            # which a removed material always comes with: see _materials_touched).
            del self._materials[name]
            self.scene.remove_material(name)
            report.removed += 1
        self._sync_textures(changes, params, report, warnings)
        self._uv_maps = {n: m.uv_map for n, m in self._materials.items() if m.uv_map is not None}
        if params.uv_pass:
            # Every material ("" the default one) reads the active render map at least.
            self._uv_maps = {"": "", **dict.fromkeys(self._materials, ""), **self._uv_maps}
        needs = {
            name: MeshNeeds(m.uv_maps, m.attributes, bool(m.tangents))
            for name, m in self._materials.items()
        }
        self._needs = {name: n for name, n in needs.items() if n}
        self._info = frozenset(n for n, m in self._materials.items() if m.object_info)
        self._attributes = {
            n: m.instance_attributes for n, m in self._materials.items() if m.instance_attributes
        }
        self._displacements = {
            n: m.displacement for n, m in self._materials.items() if m.displacement is not None
        }

    def _sync_textures(self, changes, params, report, warnings):
        wanted = {spec.name: spec for m in self._materials.values() for spec in m.textures}
        if self._world is not None:
            wanted.update({spec.name: spec for spec in self._world.textures})
        refilter = changes is None or params.texture_filter != self._params.texture_filter
        stale = {
            name: spec
            for name, spec in wanted.items()
            if refilter
            or name not in self._textures
            # A checker's name holds all its values; an image's pixels can change.
            or (hasattr(spec, "image") and spec.image.name_full in changes.images)
        }
        for name, texture in convert_textures(stale, warnings, params.texture_filter).items():
            self.scene.set_texture(name, native_data.native_texture(self._native, texture))
            report.textures += 1
        for name in self._textures.keys() - wanted.keys():
            self.scene.remove_texture(name)
            report.removed += 1
        self._textures = wanted

    # --- instances ---------------------------------------------------------------

    def _needs_walk(self, changes, params):
        if (
            changes is None
            or params.light_samples != self._params.light_samples
            or params.local_model != self._params.local_model
        ):
            return True
        if changes.structure or changes.meshes:
            return True
        if self._uv_maps != self._walked_uv_maps:
            return True  # meshes may have to carry other UVs
        if (self._needs, self._info, self._attributes) != self._walked_needs:
            # Other program inputs: UV sets, attributes, tangents, object info, object
            # attributes.
            return True
        if self._displacements != self._walked_displacements:
            return True  # the meshes that use a displacement now moved otherwise
        roles = {name: self._roles.get(name) for name in changes.objects}
        if any(role in (None, _INSTANCER, _VOLUME) for role in roles.values()):
            return True  # an object new to the sync, one with instances, a Volume object
        if any(roles[name] == _MESH for name in changes.reshaped):
            return True  # a geometry to export again
        # A light data-block whose users may not all be listed (instances of it).
        if changes.lights & self._instanced_light_data:
            return True
        return bool(changes.lights) and _LIGHT not in roles.values()

    def _walk(self, depsgraph, changes, params, report, warnings):
        """Compare every instance of the depsgraph with what was exported."""
        report.walked = True
        render = depsgraph.mode == "RENDER"
        # Blender < 4.1 meshes with corner normals are read in place from a render
        # depsgraph only (export/mesh.py _corner_normals_ready).
        in_place = render
        view_layer = depsgraph.view_layer_eval
        keys = GeometryKeys(render)
        seen_geometry = set()
        instances = {}
        lights = {}
        roles = {}
        instanced_light_data = set()
        # Their temporary folder, if any, goes with the object on an exception.
        volumes = VolumeReads(self._native, self._volumes)
        grid_materials = {}  # native name -> (material or None, grids) of Volume objects
        fluids = {}  # instance name -> its VolumeObject: gas domains read with their grids
        for object_instance in depsgraph.object_instances:
            obj = object_instance.object
            if object_instance.is_instance:
                roles[object_instance.parent.original.name_full] = _INSTANCER
            strands = obj.type in STRAND_TYPES and not obj.original.hide_render
            if strands or is_renderable_mesh(object_instance):
                # A mesh, or a Curves or point-cloud object: its geometry once, then each
                # instance of it.
                key = keys.key(object_instance)
                if key not in seen_geometry:
                    seen_geometry.add(key)
                    if strands:
                        self._sync_strands(key, strands_data(obj, depsgraph.scene), report)
                    else:
                        self._sync_geometry(
                            object_instance, key, changes, in_place, report, warnings, params
                        )
                if self._geometry[key].has_primitives:
                    instance = self._instance_data(object_instance, key, view_layer, warnings)
                    domain = None if strands else fluid_domain(obj)
                    if domain is not None:
                        instance = self._fluid_instance(
                            obj, domain, instance, grid_materials, report
                        )
                        if instance is not None:
                            seen_geometry.add(instance.mesh)
                            fluids[instance.name] = instance.volume
                    if instance is not None:
                        instances[instance.name] = _with_motion(instance, params.motion)
                role = _MESH
            elif obj.type == "LIGHT" and not obj.original.hide_render:
                light = instance_light(
                    object_instance, warnings, params.light_samples, params.local_model
                )
                if light is not None:
                    lights[light.name] = self._linked(light, obj)
                if object_instance.is_instance:
                    instanced_light_data.add(obj.data.original.name_full)
                role = _LIGHT
            elif obj.type == "VOLUME" and not obj.original.hide_render:
                read = volumes.add(instance_name(object_instance), object_instance)
                if read is not None:
                    instance = self._volume_instance(
                        object_instance, read, view_layer, report, warnings
                    )
                    seen_geometry.add(instance.mesh)
                    instances[instance.name] = _with_motion(instance, params.motion)
                    grid_materials[instance.materials[0]] = (
                        grid_object_material(object_instance.object),
                        read.data.grids,
                    )
                role = _VOLUME
            else:
                role = _OTHER
            if object_instance.show_particles and hair_systems(obj, render):
                # Its particle hair: a geometry of its own, placed as the emitter is.
                key = f"hair:{obj.original.name_full}"
                if key not in seen_geometry:
                    seen_geometry.add(key)
                    self._sync_strands(
                        key, particle_hair_data(obj, render, depsgraph.scene), report
                    )
                if self._geometry[key].has_primitives:
                    # It moves as its emitter moves.
                    emitter = self._instance_data(object_instance, key, view_layer, warnings)
                    instance = replace(
                        _with_motion(emitter, params.motion), name=f"{emitter.name} hair"
                    )
                    instances[instance.name] = instance
            if not object_instance.is_instance:
                roles.setdefault(obj.original.name_full, role)
        volumes.close()
        self._volumes = volumes.read
        self._fluids = fluids
        self._volume_warnings = volumes.warnings()
        stale_materials = self._set_grid_materials(grid_materials, report, warnings)
        self._set_instances(instances, report, replace_all=True)
        for name in stale_materials:
            self.scene.remove_material(name)
        for key in self._geometry.keys() - seen_geometry:
            if self._geometry.pop(key).has_primitives:
                self.scene.remove_mesh(key)
                report.removed += 1
        self._set_lights(lights, report, replace_all=True)
        self._roles = roles
        self._instanced_light_data = instanced_light_data
        self._walked_uv_maps = dict(self._uv_maps)
        self._walked_needs = (dict(self._needs), self._info, dict(self._attributes))
        self._walked_displacements = dict(self._displacements)

    def _instance_data(self, object_instance, mesh, view_layer, warnings):
        """export.instance.instance_data of an instance placing `mesh`, with the Object
        Info, light links and Object and Instancer attributes its materials read."""
        keys = attribute_keys(object_instance.object, self._attributes, warnings)
        return instance_data(object_instance, mesh, view_layer, self._info, self._links, keys)

    def _volume_instance(self, object_instance, read, view_layer, report, warnings):
        """The instance of a Volume object whose grids were read (a sync.volumes.VolumeRead):
        its mesh (VolumeObject.bound_mesh) set again when the read built it anew, filled by
        its material read with its grids (grid_material_name)."""
        key = f"volume:{read.data.name}"
        if read.mesh is not None or key not in self._geometry:
            mesh = read.mesh if read.mesh is not None else read.native.bound_mesh()
            self.scene.set_mesh(key, mesh)
            self._geometry[key] = _Geometry(True, None, Sanitised())
            report.meshes += 1
        instance = self._instance_data(object_instance, key, view_layer, warnings)
        name = grid_material_name(read.data.material, read.data.grids)
        return replace(instance, materials=(name,), volume=read.native)

    def _fluid_instance(self, obj, domain, instance, grid_materials, report):
        """`instance` of mesh object `obj`, a gas domain (`domain`: its FluidDomainSettings),
        as Cycles renders a baked domain: as a Volume object, the mesh around its grids'
        blocks of voxels (VolumeObject.bound_mesh, set anew each walk: the grids are read
        each time) filled by its material read with the grids (export/volume_object.py
        fluid_grids); as it was where none is read; None where no voxel reaches the domain's
        Clipping (Cycles renders nothing there)."""
        fluid = fluid_grids(obj, domain)
        if fluid is None:
            return instance
        native = self._native
        grids = {
            role: native.dense_volume_grid(
                name, array, fluid.resolution, channels, fluid.index_to_object
            )
            for (role, name), array, channels in zip(
                fluid.grids, fluid.arrays, fluid.channels, strict=True
            )
        }
        volume = native.VolumeObject(
            instance.transform, centred=fluid.centred, clipping=fluid.clipping, **grids
        )
        mesh = volume.bound_mesh()
        if mesh.triangle_count == 0:
            return None
        key = f"fluid:{instance.name}"
        self.scene.set_mesh(key, mesh)
        self._geometry[key] = _Geometry(True, None, Sanitised())
        report.meshes += 1
        name = grid_material_name(fluid.material, fluid.grids)
        grid_materials[name] = (grid_object_material(obj), fluid.grids)
        return replace(instance, mesh=key, materials=(name,), volume=volume)

    def _set_grid_materials(self, wanted, report, warnings):
        """Export the Volume objects' materials `wanted` ({native name: (material or None,
        grids)}) not exported yet; the names of those no longer wanted, to remove once no
        instance names them."""
        for name, (material, grids) in wanted.items():
            if name not in self._grid_materials:
                self._set_grid_material(name, material, grids, report, warnings)
        stale = self._grid_materials.keys() - wanted.keys()
        for name in stale:
            del self._grid_materials[name]
        report.removed += len(stale)
        return stale

    def _set_grid_material(self, name, material, grids, report, warnings):
        exported = grid_material(material, dict(grids), warnings)
        self.scene.set_material(name, native_data.native_material(self._native, exported))
        self._grid_materials[name] = (
            None if material is None else material.original.name_full,
            grids,
        )
        report.materials += 1

    def _sync_geometry(self, object_instance, key, changes, in_place, report, warnings, params):
        obj = object_instance.object
        uv_map = object_uv_map(obj, self._uv_maps)
        needs = object_needs(obj, self._needs, warnings)
        displacement = slot_displacements(obj, self._displacements)
        if displacement:
            adaptive_warning(obj, params.experimental, warnings)
        known = self._geometry.get(key)
        if (
            known is not None
            and known.uv_map == uv_map
            and known.needs == needs
            and known.displacement == displacement
            and not _reshaped(object_instance, key, changes)
        ):
            return
        mesh, sanitised = export_geometry(
            obj,
            key,
            uv_map,
            warnings,
            convert=lambda data: native_data.native_mesh(self._native, data),
            in_place=in_place,
            needs=needs,
        )
        motion = params.motion
        if mesh is not None and motion is not None and not object_instance.is_instance:
            _deform(mesh, motion, obj, warnings)
        displaced = 0
        if mesh is not None and displacement:
            # After the deformation's steps are set: each step moves as the vertices do.
            displaced = displace(self._native, self.scene, mesh, displacement, object_instance)
        if mesh is not None:
            self.scene.set_mesh(key, mesh)
            report.meshes += 1
        elif known is not None and known.has_primitives:
            self.scene.remove_mesh(key)
            report.removed += 1
        self._geometry[key] = _Geometry(
            mesh is not None, uv_map, sanitised, needs, displacement, displaced
        )

    def _sync_strands(self, key, data, report):
        """Curves, points or particle hair (export/curves.py data, or None) as geometry
        `key`: read in bulk, so set again at every walk."""
        known = self._geometry.get(key)
        if data is not None and len(data) > 0:
            self.scene.set_mesh(key, native_data.native_strands(self._native, data))
            report.meshes += 1
        elif known is not None and known.has_primitives:
            self.scene.remove_mesh(key)
            report.removed += 1
        self._geometry[key] = _Geometry(data is not None and len(data) > 0, None, Sanitised())

    def _update_objects(self, depsgraph, changes, params, report, warnings):
        """The objects listed in the updates, when each is a mesh shown as itself
        (its geometry unchanged), a light, or neither: no walk needed."""
        view_layer = depsgraph.view_layer_eval
        instances = {}
        lights = {}
        gone = set()
        for obj in changes.evaluated_objects:
            name = obj.original.name_full
            role = self._roles[name]
            alone = _alone(obj)
            if role == _MESH:
                known = self._instances.get(name)
                if known is None or not is_renderable_mesh(alone):
                    gone.add(name)  # hidden from renders (or never had triangles)
                else:
                    instance = self._instance_data(alone, known.mesh, view_layer, warnings)
                    instances[name] = _with_motion(instance, params.motion)
            elif role == _LIGHT:
                light = None
                if not obj.original.hide_render:
                    light = instance_light(
                        _alone(obj), warnings, params.light_samples, params.local_model
                    )
                if light is None:
                    gone.add(name)
                else:
                    lights[name] = self._linked(light, obj)
        self._set_instances(instances, report, remove=gone & self._instances.keys())
        self._set_lights(lights, report, remove=gone & self._lights.keys())

    def _set_instances(self, instances, report, replace_all=False, remove=()):
        """Set the instances that differ from the exported ones; remove those not in
        `instances` (replace_all) or named in `remove`."""
        for name, instance in instances.items():
            if not _same_instance(instance, self._instances.get(name)):
                native_data.set_instance(self._native, self.scene, instance)
                self._instances[name] = instance
                report.instances += 1
        stale = (self._instances.keys() - instances.keys()) if replace_all else set(remove)
        for name in stale:
            del self._instances[name]
            self.scene.remove_instance(name)
            report.removed += 1

    def _linked(self, light, obj):
        # LightData of light object `obj` with its masks as an emitter (light linking).
        _, _, light_sets, shadow_sets = self._links.of_object(obj)
        return replace(light, light_sets=light_sets, shadow_sets=shadow_sets)

    def _set_lights(self, lights, report, replace_all=False, remove=()):
        for name, light in lights.items():
            if light != self._lights.get(name):
                self.scene.set_light(name, native_data.native_light(self._native, light))
                self._lights[name] = light
                report.lights += 1
        stale = (self._lights.keys() - lights.keys()) if replace_all else set(remove)
        for name in stale:
            del self._lights[name]
            self.scene.remove_light(name)
            report.removed += 1

    # --- world -------------------------------------------------------------------

    def _sync_world(self, blender_scene, params, report, warnings):
        world = convert_world(
            blender_scene.world, params.ambient_strength, warnings, params.local_model
        )
        if world != self._world:
            # The textures its program samples, before the program names them.
            new = {s.name: s for s in world.textures if s.name not in self._textures}
            for name, texture in convert_textures(new, warnings, params.texture_filter).items():
                self.scene.set_texture(name, native_data.native_texture(self._native, texture))
                self._textures[name] = new[name]
                report.textures += 1
            self.scene.background = world.background
            self.scene.ambient = world.ambient
            if world.program is not None or self._world is not None:
                program = (
                    None
                    if world.program is None
                    else native_data.native_program(self._native, world.program)
                )
                self.scene.set_world(program, world.output, world.ambient_strength)
            # The world light's map is built anew by the next compile: only when the world,
            # its images or these change (an edit elsewhere keeps it).
            self.scene.set_world_light(**asdict(world.light))
            self.scene.set_world_visibility(*world.visibility)
            medium = medium_material(world.medium or Medium())
            self.scene.set_world_medium(native_data.native_material(self._native, medium))
            self._world = world
            report.world = True


def _may_relink(changes):
    """Whether an update (None: a full sync) may change light linking: a collection's
    members or their include/exclude state, objects added or removed, or an object's
    own Light Linking collections (an object update that is not a move)."""
    if changes is None or changes.structure or changes.scene:
        return True
    return bool(changes.objects - changes.transformed)


def _reshaped(object_instance, key, changes):
    """Whether the updates say the geometry `key` of this instance changed."""
    if changes is None:
        return True
    original = object_instance.object.original
    if object_instance.is_instance:
        owner = object_instance.parent.original.name_full
        # Geometry the instancer generates is keyed by it (export/mesh.py geometry_key).
        if key.split("#")[0] == f"object:{owner}":
            return owner in changes.reshaped
    if original.name_full in changes.reshaped:
        return True
    data = original.data
    return data is not None and data.name_full in changes.meshes


def _alone(obj):
    """A real (not instanced) evaluated object in the shape of a depsgraph object
    instance, for the exporters that read one."""
    return SimpleNamespace(
        object=obj,
        is_instance=False,
        parent=None,
        matrix_world=obj.matrix_world,
        show_self=True,
    )


def _deform(mesh, motion, obj, warnings):
    # Deformation motion blur on native `mesh` of object `obj`, when it deforms within
    # the shutter and its exported vertices are its evaluated ones (no vertex dropped as
    # unusable).
    steps = motion.deformations.get(obj.original.name_full)
    if steps is None:
        return
    if len(steps[0]) != mesh.vertex_count:
        warnings.append(
            f"Whitted: object '{obj.name}': its deformation does not blur (vertices were "
            "dropped as unusable)"
        )
        return
    mesh.set_motion(list(steps))


def _with_motion(instance, motion):
    # The instance with its transforms over the shutter, when it moves within it.
    if motion is None or instance.name not in motion.objects:
        return instance
    return replace(instance, motion=motion.objects[instance.name])


def _same_instance(a, b):
    if b is None:
        return False
    return all(
        np.array_equal(getattr(a, f.name), getattr(b, f.name))
        if f.name == "transform"
        else getattr(a, f.name) == getattr(b, f.name)
        for f in fields(a)
    )


def _reads_otherwise(exported, view_layer):
    """Whether a View Layer attribute export.material.MaterialExport `exported` folded
    reads otherwise now."""
    return any(view_layer_attribute(view_layer, n) != v for n, v in exported.layer_attributes)
