"""The exporters' output for a whole depsgraph, for the tests that check what the mesh
and light exporters make of a scene: the production functions (export/mesh.py
mesh_instances, export_geometry, instance_data; export/light.py instance_light)
composed as SceneSync's walk composes them, with the plain data kept (the walk hands
each piece straight to the native scene). And an exported shader program run by the
native program on one hit (run_program)."""

from dataclasses import dataclass, field

from whitted.export.instance import instance_data
from whitted.export.light import DEFAULT_LIGHT_SAMPLES, instance_light
from whitted.export.mesh import export_geometry, mesh_instances
from whitted.export.mesh_layers import object_needs, object_uv_map
from whitted.export.nodes import ops
from whitted.export.sanitise import Sanitised
from whitted.native import load_native
from whitted.sync.native_data import native_program


@dataclass(frozen=True)
class Exported:
    meshes: list  # MeshData, each distinct geometry once
    instances: list  # InstanceData, one per mesh instance with triangles
    sanitised: Sanitised = field(default_factory=Sanitised)  # totals over all meshes


def exported_meshes(depsgraph, warnings, uv_maps=None, in_place=None, needs=None, info=()):
    """Every renderable mesh of evaluated `depsgraph`: `uv_maps` maps a material to the
    UV map its textures read, `needs` a material to its MeshNeeds, `info` names the
    materials that read Object Info; `in_place` (default: a render depsgraph) reads
    Blender < 4.1 meshes with corner normals in place, as the walk does."""
    if in_place is None:
        in_place = depsgraph.mode == "RENDER"
    meshes, instances, exported = [], [], {}
    sanitised = Sanitised()
    view_layer = depsgraph.view_layer_eval
    for object_instance, key in mesh_instances(depsgraph):
        obj = object_instance.object
        if key not in exported:
            mesh, repaired = export_geometry(
                obj,
                key,
                object_uv_map(obj, uv_maps or {}),
                warnings,
                in_place=in_place,
                needs=object_needs(obj, needs or {}, warnings),
            )
            sanitised += repaired
            exported[key] = mesh is not None
            if mesh is not None:
                meshes.append(mesh)
        if exported[key]:
            instances.append(instance_data(object_instance, key, view_layer, info))
    return Exported(meshes, instances, sanitised)


def exported_lights(depsgraph, warnings, default_samples=DEFAULT_LIGHT_SAMPLES):
    """LightData of every renderable light of evaluated `depsgraph`, instances included;
    `default_samples` per axis for a sized light whose own setting is 0."""
    lights = []
    for object_instance in depsgraph.object_instances:
        obj = object_instance.object
        if obj.type != "LIGHT" or obj.original.hide_render:
            continue
        light = instance_light(object_instance, warnings, default_samples)
        if light is not None:
            lights.append(light)
    return lights


def run_program(program, inputs):
    """The registers (float32[R, 4]) after the native program runs exported ProgramData
    `program` on one hit: `inputs` maps each INPUT mode it reads to four floats; FRESNEL
    and LAYER_WEIGHT read the hit's IN_INCOMING, IN_NORMAL and IN_BACKFACING from them
    (default: facing +Z, front)."""
    up = (0.0, 0.0, 1.0, 0.0)
    incoming = tuple(inputs.get(ops.IN_INCOMING, up))[:3]
    normal = tuple(inputs.get(ops.IN_NORMAL, up))[:3]
    backfacing = inputs.get(ops.IN_BACKFACING, (0.0,))[0] != 0.0
    native = native_program(load_native(), program)
    return native.run(dict(inputs), incoming, normal, backfacing)
