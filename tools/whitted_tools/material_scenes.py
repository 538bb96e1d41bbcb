"""Pieces of the material gallery's and the material cost benchmark's scenes (bpy):
camera, sun, worlds, a diffuse floor, packed float images, smooth spheres, and a
third-party model imported and framed as the gallery shows it."""

import math

import bpy
import numpy as np
from mathutils import Vector

from whitted_tools.blender import enable_addon


def add_camera(scene, location, target, lens=50.0):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = location
    camera.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    camera.data.lens = lens
    scene.collection.objects.link(camera)
    scene.camera = camera


def sphere_under_sun(scene, material, size, segments=48, rings=24):
    """A smooth unit sphere of `material` at the origin under a sun 45 degrees up (3
    W/m^2, no angular size) on a black world, seen side-on (side_camera, 2.2 m wide) at
    size x size pixels on a transparent film, Standard view: each pixel sees its own
    angles of light and view, for comparing lobes with Cycles pixel by pixel."""
    dark_stage(scene, size, size)
    smooth_sphere("Ball", (0.0, 0.0, 0.0), 1.0, material, segments, rings)
    side_camera(scene, 2.2)
    add_sun(scene, rotation=(45.0, 0.0, -40.0), strength=3.0)


def side_camera(scene, width):
    """An orthographic camera 5 m out along -Y looking at the origin along +Y, its frame
    `width` m wide: a unit sphere at the origin seen side-on."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = width
    camera.location = (0.0, -5.0, 0.0)
    camera.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera


def plain_film(scene, width, height):
    """No world (a black background, no ambient term), an opaque film of width x height
    pixels at 100%, the Standard view transform without a look: linear values as they
    are, for comparing two engines' renders."""
    scene.world = None
    standard_film(scene, width, height, transparent=False)


def standard_film(scene, width, height, transparent):
    """A film of width x height pixels at 100%, transparent or not, the Standard view
    transform without a look: linear values as they are."""
    render = scene.render
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.film_transparent = transparent
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"


def top_camera(scene, width):
    """An orthographic camera 5 m above the origin looking straight down, its frame `width`
    m wide: the plane z = 0 seen square-on, image x along +X."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = width
    camera.location = (0.0, 0.0, 5.0)
    scene.collection.objects.link(camera)
    scene.camera = camera


def add_sun(scene, rotation=(40.0, 10.0, 30.0), strength=3.0):
    """A sun of `strength` W/m^2 and no angular size; `rotation` Euler XYZ in degrees."""
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = strength
    sun.angle = 0.0
    obj = bpy.data.objects.new("Sun", sun)
    obj.rotation_euler = tuple(math.radians(a) for a in rotation)
    scene.collection.objects.link(obj)


def _world(scene, name, color):
    world = bpy.data.worlds.new(name)
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = color
    scene.world = world  # before its Cycles settings, whose update reads the scene's world
    # Seen by mirrors and glass, lighting no diffuse surface (Ray Visibility > Diffuse).
    world.cycles_visibility.diffuse = False
    return world


def dark_stage(scene, width, height):
    """`width` x `height` pixels at 100%, a transparent film, the Standard view (linear
    renders compare as they are) and a black world: where the comparison scenes start."""
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    black_world(scene)


def black_world(scene):
    return _world(scene, "Black", (0.0, 0.0, 0.0, 1.0))


def grey_world(scene, grey=0.4):
    """A uniform grey sky that mirrors show but that lights no diffuse surface."""
    return _world(scene, "Grey", (grey, grey, grey, 1.0))


def empty_node_material(name):
    """A new material whose node tree is empty (Blender 5.0 materials always use nodes;
    earlier ones are switched to them)."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    material.node_tree.nodes.clear()
    return material


def lambert_material(name="Lambert", albedo=0.8):
    """A Diffuse BSDF of roughness 0 (Lambertian in Cycles 3.x and 4.x+ alike), and the
    same in the viewport display values."""
    material = empty_node_material(name)
    material.diffuse_color = (albedo, albedo, albedo, 1.0)
    material.specular_intensity = 0.0
    material.metallic = 0.0
    nodes = material.node_tree.nodes
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
    return material


def add_floor(scene, size=6.0, albedo=0.5):
    """A Lambertian plane named "Floor" at z = 0."""
    bpy.ops.mesh.primitive_plane_add(size=size)
    floor = bpy.context.active_object
    floor.name = "Floor"
    floor.data.materials.append(lambert_material("Floor", albedo=albedo))
    return floor


def numpy_image(name, pixels, non_color=False):
    """A packed float image from float32[H, W, 4] (rows bottom to top)."""
    height, width, _ = pixels.shape
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    if non_color:
        # Before the pixels: changing it makes Blender generate the buffer anew.
        image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(pixels.astype(np.float32).reshape(-1))
    image.pack()
    return image


def checker_pixels(size=64, cells=8, a=(0.8, 0.3, 0.1), b=(0.1, 0.4, 0.7)):
    """float[size, size, 4]: a cells x cells checkerboard of colours a and b."""
    y, x = np.mgrid[0:size, 0:size]
    mask = ((x * cells // size + y * cells // size) % 2 == 0)[..., None]
    rgb = np.where(mask, a, b)
    return np.concatenate([rgb, np.ones((size, size, 1))], axis=-1)


def smooth_sphere(name, location, radius=0.8, material=None, segments=48, rings=24):
    """A smooth-shaded UV sphere (48 segments and 24 rings unless told)."""
    bpy.ops.mesh.primitive_uv_sphere_add(
        radius=radius, location=location, segments=segments, ring_count=rings
    )
    sphere = bpy.context.active_object
    sphere.name = name
    bpy.ops.object.shade_smooth()
    if material is not None:
        sphere.data.materials.append(material)
    return sphere


def import_file(path):
    """Import a model with Blender's own importer for its file type."""
    suffix = path.suffix.lower()
    if suffix in (".gltf", ".glb"):
        enable_addon("io_scene_gltf2")
        if not hasattr(np, "bool"):
            np.bool = bool  # as in scene_gltf_round_trip
        bpy.ops.import_scene.gltf(filepath=str(path))
    elif suffix == ".obj":
        bpy.ops.wm.obj_import(filepath=str(path))
    elif suffix == ".dae":
        bpy.ops.wm.collada_import(filepath=str(path))
    else:
        raise ValueError(f"no importer for {path.name}")


def frame_subject(scene):
    """The gallery's set-up around whatever was imported: its own lights and cameras
    removed; a camera 27 degrees wide from the front right above, fitting the bounds;
    a floor just under them; the sun; the black world."""
    for obj in [o for o in scene.objects if o.type in ("LIGHT", "CAMERA")]:
        bpy.data.objects.remove(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    corners = [
        tuple(obj.matrix_world @ Vector(corner))
        for obj in scene.objects
        if obj.type == "MESH"
        for corner in obj.evaluated_get(depsgraph).bound_box
    ]
    low, high = np.min(corners, axis=0), np.max(corners, axis=0)
    centre, radius = (low + high) / 2.0, float(np.linalg.norm(high - low)) / 2.0
    view = np.array([0.55, -1.0, 0.6]) / np.linalg.norm([0.55, -1.0, 0.6])
    distance = 1.05 * radius / math.sin(math.radians(27.0) / 2.0)
    add_camera(scene, tuple(centre + distance * view), tuple(centre))
    scene.camera.data.clip_start = 1e-3 * distance
    scene.camera.data.clip_end = 10.0 * distance
    floor = add_floor(scene, size=8.0 * radius)
    floor.location.z = low[2] - 0.01 * radius  # not coplanar with a flat model
    add_sun(scene)
    black_world(scene)


def emission_material(name, strength, colour=(1.0, 1.0, 1.0)):
    """An Emission shader of `colour` times `strength`: that radiance, W/(m^2 sr), seen
    from either side."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*colour, 1.0)
    emission.inputs["Strength"].default_value = strength
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def emissive_panel(name, location, size, material, cuts=0):
    """A square plane of `size` m facing down (its front, the side its normal points
    to, towards -Z) at `location`, of `material`; `cuts` subdivisions per side make it
    2 (cuts + 1)^2 triangles (a screen or sign of many small emitters)."""
    bpy.ops.mesh.primitive_grid_add(
        x_subdivisions=cuts + 1, y_subdivisions=cuts + 1, size=size, location=location
    )
    panel = bpy.context.active_object
    panel.name = name
    panel.rotation_euler = (math.pi, 0.0, 0.0)
    panel.data.materials.append(material)
    return panel


def panel_room(scene, sphere_material=None, cuts=0, strength=6.0):
    """A Lambertian floor lit only by a 1 m emissive panel 2 m above it, facing down
    (`cuts`: emissive_panel's), on a black world, at 64 x 48 pixels; `sphere_material`
    puts a sphere between them. Whitted: 2 x 2 samples, 4 x 4 emitter feelers."""
    dark_stage(scene, 64, 48)
    add_floor(scene, size=8.0, albedo=0.8)
    panel = emissive_panel("Panel", (0.0, 0.0, 2.0), 1.0, emission_material("Glow", strength), cuts)
    if sphere_material is not None:
        smooth_sphere("Ball", (0.3, 0.0, 0.6), 0.5, sphere_material, segments=64, rings=32)
    add_camera(scene, (0.0, -5.0, 3.0), (0.0, 0.0, 0.6), lens=32.0)
    scene.whitted.ambient_strength = 0.0
    scene.whitted.aa_samples = 2
    scene.whitted.emitter_samples = 4
    return panel


def principled_sphere_material(name, base, roughness, metallic=0.0, specular=0.5):
    """A Principled BSDF of `base` colour, `roughness`, `metallic` and specular level
    `specular` (3.x Specular, 4.x+ Specular IOR Level), IOR 1.5."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    level = "Specular IOR Level" if "Specular IOR Level" in bsdf.inputs else "Specular"
    bsdf.inputs[level].default_value = specular
    bsdf.inputs["IOR"].default_value = 1.5
    return material


def glass_bsdf_material(name, roughness, ior=1.5):
    """A Glass BSDF (GGX) of `roughness` and `ior`: frosted glass above roughness 0."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    glass = tree.nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = "GGX"
    glass.inputs["Roughness"].default_value = roughness
    glass.inputs["IOR"].default_value = ior
    tree.links.new(glass.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    return material
