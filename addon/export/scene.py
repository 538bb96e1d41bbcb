"""The whole evaluated depsgraph as a whitted_native.Scene.

The only exporter that touches the native module: the others return plain
data, which this module turns into native objects. The module is passed in
(engine.py loads it), so the exporters import without it.
"""

from dataclasses import asdict, dataclass

import bpy

from .camera import convert_camera
from .light import convert_lights
from .material import convert_material
from .mesh import convert_meshes
from .world import convert_world


@dataclass(frozen=True)
class ExportedScene:
    scene: object  # whitted_native.Scene
    width: int  # image size in pixels
    height: int
    warnings: list[str]  # one line per object that could not be exported as authored


def convert_scene(depsgraph, native):
    """Export the evaluated depsgraph into a new native.Scene.

    Raises export.ExportError when the scene cannot be rendered, and the native
    module's ValueError when it refuses data.
    """
    warnings = []
    blender_scene = depsgraph.scene  # the evaluated scene
    scene = native.Scene()

    camera = convert_camera(blender_scene.camera, blender_scene.render, warnings)
    scene.camera = native.Camera(
        to_world=camera.to_world,
        projection=getattr(native.Projection, camera.projection),
        window=camera.window,
        clip_start=camera.clip_start,
        clip_end=camera.clip_end,
    )

    # Every material the evaluated objects use is in the depsgraph.
    for material in depsgraph.ids:
        if isinstance(material, bpy.types.Material):
            data = convert_material(material, warnings)
            scene.set_material(material.name_full, native.Material(**asdict(data)))

    exported = convert_meshes(depsgraph, warnings)
    for mesh in exported.meshes:
        scene.set_mesh(mesh.name, mesh.positions, mesh.triangles, mesh.normals, mesh.material_slots)
    for instance in exported.instances:
        scene.set_instance(
            instance.name, instance.mesh, instance.transform, list(instance.materials)
        )

    lights = convert_lights(depsgraph, warnings)
    for light in lights:
        fields = asdict(light)
        name = fields.pop("name")
        fields["type"] = getattr(native.LightType, light.type)
        fields["shape"] = getattr(native.AreaShape, light.shape)
        scene.set_light(name, native.Light(**fields))
    if not lights:
        warnings.append("Whitted: the scene has no lights; only ambient light and emission show")

    world = convert_world(blender_scene.world, warnings)
    scene.background = world.background
    scene.ambient = world.ambient

    return ExportedScene(scene=scene, width=camera.width, height=camera.height, warnings=warnings)
