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
from .texture import CheckerTextureSpec, convert_textures
from .world import convert_world


@dataclass(frozen=True)
class ExportedScene:
    scene: object  # whitted_native.Scene
    width: int  # image size in pixels
    height: int
    warnings: list[str]  # one line per object that could not be exported as authored
    sanitised: dict[str, int]  # bad geometry dropped or repaired, totals (export.mesh.Sanitised)


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
    materials = {
        material.name_full: convert_material(material, warnings)
        for material in depsgraph.ids
        if isinstance(material, bpy.types.Material)
    }
    # The textures the materials name, each image read once.
    specs = {spec.name: spec for m in materials.values() for spec in m.textures}
    whitted = blender_scene.whitted
    for name, texture in convert_textures(specs, warnings, whitted.texture_filter).items():
        scene.set_texture(name, _native_texture(native, texture))
    for name, material in materials.items():
        scene.set_material(name, native.Material(**asdict(material.data)))
    # Material name -> the UV map its textures read: the meshes that use it export it.
    uv_maps = {name: m.uv_map for name, m in materials.items() if m.uv_map is not None}

    # Each mesh is copied into a native Mesh as soon as it is read, so its numpy arrays
    # are freed before the next is read and before any BVH is built (they would add to
    # the peak of memory); set_mesh then moves it into the scene and builds its BVH.
    exported = convert_meshes(
        depsgraph, warnings, uv_maps, convert=lambda mesh: (mesh.name, _native_mesh(native, mesh))
    )
    for name, mesh in exported.meshes:
        scene.set_mesh(name, mesh)
    for instance in exported.instances:
        scene.set_instance(
            instance.name,
            instance.mesh,
            instance.transform,
            list(instance.materials),
            visibility=_native_visibility(native, instance.visibility),
            holdout=instance.holdout,
        )

    lights = convert_lights(depsgraph, warnings, whitted.light_samples)
    set_lights(scene, lights, native)
    if not lights:
        warnings.append("Whitted: the scene has no lights; only ambient light and emission show")

    world = convert_world(blender_scene.world, whitted.ambient_strength, warnings)
    scene.background = world.background
    scene.ambient = world.ambient

    return ExportedScene(
        scene=scene,
        width=camera.width,
        height=camera.height,
        warnings=warnings,
        sanitised=asdict(exported.sanitised),
    )


def set_lights(scene, lights, native):
    """Add (or replace, by name) export.light.LightData `lights` in native `scene`."""
    for light in lights:
        fields = asdict(light)
        name = fields.pop("name")
        fields["type"] = getattr(native.LightType, light.type)
        fields["shape"] = getattr(native.AreaShape, light.shape)
        scene.set_light(name, native.Light(**fields))


def _native_mesh(native, mesh):
    # export.mesh.MeshData as a native.Mesh (a copy of its arrays).
    return native.Mesh(
        mesh.positions,
        mesh.triangles,
        normals=mesh.normals,
        material_slots=mesh.material_slots,
        uvs=mesh.uvs,
        vertex_normals=mesh.vertex_normals,
    )


def _native_visibility(native, visibility):
    # RayVisibility's fields as an int of whitted_native.Visibility flags.
    flags = native.Visibility
    return (
        (flags.CAMERA if visibility.camera else 0)
        | (flags.SHADOW if visibility.shadow else 0)
        | (flags.REFLECTION if visibility.reflection else 0)
        | (flags.REFRACTION if visibility.refraction else 0)
    )


def _native_texture(native, texture):
    # ImageTextureData or CheckerTextureSpec (export/texture.py) as a native texture.
    coordinates = getattr(native.TexCoord, texture.coordinates)
    if isinstance(texture, CheckerTextureSpec):
        return native.CheckerTexture(
            color1=texture.color1,
            color2=texture.color2,
            scale=texture.scale,
            coordinates=coordinates,
        )
    return native.ImageTexture(
        pixels=texture.pixels,
        extension=getattr(native.Extension, texture.extension),
        interpolation=getattr(native.Interpolation, texture.interpolation),
        coordinates=coordinates,
    )
