"""Plain exported data (export/*.py) as whitted_native objects.

Where every object of a native scene is built (meshes, strands, materials, programs,
lights, cameras, textures, instances); the scene itself is SceneSync's
(sync/scene.py), a render's settings settings.py's (the Estimate's probes
estimate.py's), and each render's job its caller's (sync/frame.py,
viewport/session.py, ray_tree/tree.py). The module is passed in
(native.py loads it), so this imports without it.
"""

from dataclasses import asdict

import numpy as np

from ..export.camera import PINHOLE
from ..export.curves import CurvesData
from ..export.texture import CheckerTextureSpec


def native_camera(native, camera):
    """export.camera.CameraData or viewport.camera.ViewCamera as a native.Camera."""
    lens = getattr(camera, "lens", PINHOLE)
    panorama = getattr(camera, "panorama", None)
    rolling = getattr(camera, "rolling_shutter", None)
    return native.Camera(
        to_world=np.asarray(camera.to_world, dtype=np.float64),
        projection=getattr(native.Projection, camera.projection),
        window=camera.window,
        clip_start=camera.clip_start,
        clip_end=camera.clip_end,
        aperture_radius=lens.aperture_radius,
        focus_distance=lens.focus_distance,
        aperture_blades=lens.blades,
        aperture_rotation=lens.rotation,
        aperture_ratio=lens.ratio,
        panorama=None if panorama is None else native_panorama(native, panorama),
        motion=list(getattr(camera, "motion", ())),
        shutter_curve=list(getattr(camera, "shutter_curve", ())),
        rolling_shutter=-1.0 if rolling is None else rolling,
    )


def native_panorama(native, panorama):
    # export.camera.PanoramaData as a native.Panorama.
    fields = asdict(panorama)
    fields["type"] = getattr(native.PanoramaType, panorama.type)
    return native.Panorama(**fields)


def native_material(native, material):
    # export.material.MaterialExport as a native.Material (which takes its enums by
    # name), with its shader program.
    program = None if material.program is None else native_program(native, material.program)
    return native.Material(
        **asdict(material.data),
        program=program,
        outputs=dict(material.outputs),
        pass_index=material.pass_index,
    )


def native_program(native, program):
    # export.nodes.program.ProgramData as a native.Program.
    return program.native(native)


def native_light(native, light):
    # export.light.LightData as a native.Light.
    fields = asdict(light)
    del fields["name"]
    # Its program as a native.Program (asdict made the ProgramData a dict).
    fields["program"] = None if light.program is None else native_program(native, light.program)
    fields["type"] = getattr(native.LightType, light.type)
    fields["shape"] = getattr(native.AreaShape, light.shape)
    return native.Light(**fields)


def native_strands(native, data):
    # export.curves.CurvesData or PointsData as a native.Mesh of no triangles.
    mesh = native.Mesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
    if isinstance(data, CurvesData):
        mesh.set_curves(data.keys, data.counts, data.slots, linear=data.linear, flat=data.flat)
    else:
        mesh.set_points(data.spheres, data.slots)
    return mesh


def native_mesh(native, mesh):
    # export.mesh.MeshData as a native.Mesh (a copy of its arrays).
    # The arrays shader programs read go only when some program reads them.
    extra = {
        name: list(getattr(mesh, name))
        for name in ("uv_sets", "attributes", "tangents")
        if getattr(mesh, name)
    }
    return native.Mesh(
        mesh.positions,
        mesh.triangles,
        normals=mesh.normals,
        material_slots=mesh.material_slots,
        uvs=mesh.uvs,
        vertex_normals=mesh.vertex_normals,
        **extra,
    )


def set_instance(native, scene, instance):
    """Add or replace export.mesh.InstanceData `instance` in native `scene`."""
    extra = {} if instance.info is None else {"info": _native_info(instance.info)}
    if instance.cryptomatte is not None:
        object_id, asset_id, materials = instance.cryptomatte
        extra["cryptomatte"] = (object_id, asset_id, list(materials))
    scene.set_instance(
        instance.name,
        instance.mesh,
        instance.transform,
        list(instance.materials),
        visibility=_native_visibility(native, instance.visibility),
        holdout=instance.holdout,
        shadow_catcher=instance.shadow_catcher,
        motion=list(instance.motion),
        links=instance.links,
        volume=instance.volume,
        attributes=list(instance.attributes),
        **extra,
    )


def _native_info(info):
    # (x, y, z, random, pass index, r, g, b, a): the binding takes the nine floats flat.
    return tuple(float(x) for x in info)


def native_texture(native, texture):
    # ImageTextureData or CheckerTextureSpec (export/texture.py) as a native texture.
    coordinates = getattr(native.TexCoord, texture.coordinates)
    if isinstance(texture, CheckerTextureSpec):
        return native.CheckerTexture(
            color1=texture.color1,
            color2=texture.color2,
            scale=texture.scale,
            coordinates=coordinates,
        )
    sampling = {
        "extension": getattr(native.Extension, texture.extension),
        "interpolation": getattr(native.Interpolation, texture.interpolation),
        "coordinates": coordinates,
    }
    if texture.udim:
        return native.UdimTexture(tiles=list(texture.tiles), **sampling)
    ((_, pixels),) = texture.tiles
    return native.ImageTexture(pixels=pixels, **sampling)


def _native_visibility(native, visibility):
    # RayVisibility's fields as an int of whitted_native.RayVisibility flags.
    flags = native.RayVisibility
    return (
        (flags.CAMERA if visibility.camera else 0)
        | (flags.SHADOW if visibility.shadow else 0)
        | (flags.REFLECTION if visibility.reflection else 0)
        | (flags.REFRACTION if visibility.refraction else 0)
    )
