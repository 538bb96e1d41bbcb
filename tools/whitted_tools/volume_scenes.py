"""The scenes of issue 48's media, shared by tests/blender/test_volume.py, the tests that
render media (the ray-tree inspector's, the passes') and the benchmarks: a fog box on a
floor lit by a lamp, an emitter or the world; a procedural cloud; a Volume object's grid
(a Mesh to Volume sphere); a fire lighting the floor. Each builder fills the scene it is
given (in Blender)."""

import bpy
import numpy as np

from whitted_tools.material_scenes import emission_material, emissive_panel, lambert_material
from whitted_tools.scenes import (
    add_object,
    background_world,
    cube_mesh,
    facing,
    mesh_from_faces,
    mesh_to_volume,
    sphere_mesh,
)
from whitted_tools.world_scenes import environment_world, studio_hdri


def volume_material(name, build):
    """A material whose output's Volume is what build(nodes) returns (an output socket),
    and no Surface."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    for node in [n for n in tree.nodes if n.bl_idname != "ShaderNodeOutputMaterial"]:
        tree.nodes.remove(node)
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(build(tree), output.inputs["Volume"])
    return material


def principled_volume(density, colour=(1.0, 1.0, 1.0), anisotropy=0.0):
    def build(tree):
        node = tree.nodes.new("ShaderNodeVolumePrincipled")
        node.inputs["Density"].default_value = density
        node.inputs["Color"].default_value = (*colour, 1.0)
        node.inputs["Anisotropy"].default_value = anisotropy
        return node.outputs[0]

    return build


def nodes(tree, kind, **inputs):
    node = tree.nodes.new(kind)
    for name, value in inputs.items():
        node.inputs[name].default_value = value
    return node


def add_light(scene, light):
    """What lights the fog: "spot", a spot lamp 5 m above the floor pointing down (the box
    in its cone); "sun", a sun from the side above; "panel", an emissive square of 2 m
    facing down 5 m above the floor, inside the fog; "world", a grey world of one colour;
    "hdri", Blender's forest HDRI."""
    if light in ("spot", "sun"):
        lamp = bpy.data.lights.new(light.title(), light.upper())
        if light == "spot":
            lamp.energy, lamp.spot_size, lamp.spot_blend = 1000.0, 0.9, 0.1
            direction, location = (0.0, 0.0, -1.0), (0.0, 0.0, 5.0)
        else:
            lamp.energy, lamp.angle = 2.0, 0.0
            direction, location = (0.4, 0.3, -1.0), (0.0, 0.0, 8.0)
        lamp.shadow_soft_size = 0.0
        add_object(scene, light.title(), lamp, location=location).rotation_euler = facing(direction)
    elif light == "panel":
        emissive_panel("Panel", (0.0, 0.0, 5.0), 2.0, emission_material("Panel", 40.0))
    elif light == "world":
        scene.world = background_world("Grey", (0.5, 0.5, 0.5))
    else:
        environment_world(scene, bpy.data.images.load(studio_hdri("forest")))


def fog_stage(scene, fog_bottom=-0.3, light="spot"):
    """A 12 x 12 floor inside a fog cube of edge 6 standing on it (its bottom face
    `fog_bottom` below the floor's plane), a box in the fog casting its shadow into it, lit
    by `light` (add_light), no world unless it is the light; the camera outside."""
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    corners = np.array([(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], dtype=np.float32)
    floor = add_object(
        scene, "Floor", mesh_from_faces("Floor", corners, [np.array([[0, 1, 2, 3]])])
    )
    # A diffuse floor and box, the same in every Blender (without a material they would be
    # a Principled BSDF from 5.0 on, a Diffuse BSDF before: export/material.py).
    floor.data.materials.append(lambert_material("Floor", 0.8))
    box = add_object(scene, "Box", cube_mesh("Box", 0.8), location=(0.3, 0.0, 1.5))
    box.data.materials.append(floor.data.materials[0])
    add_light(scene, light)
    fog = add_object(scene, "Fog", cube_mesh("Fog", 6.0), location=(0.0, 0.0, 3.0 + fog_bottom))
    fog.data.materials.append(volume_material("Fog", principled_volume(0.1)))
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -11.0, 3.5), facing((0.0, 11.0, -2.0))
    scene.camera = camera
    return scene


def cloud(tree):
    """A Principled Volume whose Density is a Noise Texture (of the cube's Generated
    coordinates, its default) through a Color Ramp: none where the noise is below 0.45,
    0.4 where it is above 0.6 (a grey ramp: the colour's luminance is its value)."""
    volume = tree.nodes.new("ShaderNodeVolumePrincipled")
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 3.0
    ramp = tree.nodes.new("ShaderNodeValToRGB")
    low, high = ramp.color_ramp.elements
    low.position, low.color = 0.45, (0.0, 0.0, 0.0, 1.0)
    high.position, high.color = 0.6, (0.4, 0.4, 0.4, 1.0)
    tree.links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    tree.links.new(ramp.outputs["Color"], volume.inputs["Density"])
    return volume.outputs[0]


def cloud_stage(scene, lamp="SPOT"):
    """The fog stage with a procedural cloud in the fog cube, lit by its spot lamp or
    instead by a sun, the emissive panel ("PANEL") or the forest HDRI ("HDRI")."""
    fog_stage(scene)
    scene.objects["Fog"].data.materials[0] = volume_material("Cloud", cloud)
    if lamp != "SPOT":
        bpy.data.objects.remove(scene.objects["Spot"])
    if lamp == "SUN":
        sun = bpy.data.lights.new("Sun", "SUN")
        sun.energy, sun.angle = 3.0, 0.0
        add_object(scene, "Sun", sun).rotation_euler = facing((0.3, 0.4, -1.0))
    elif lamp in ("PANEL", "HDRI"):
        add_light(scene, lamp.lower())
    return scene


def noise_temperature(tree):
    """A Noise Texture (of the Generated coordinates) mapped from [0.3, 0.7] onto 800 K to
    2000 K (clamped): flames from dull red to orange."""
    noise = nodes(tree, "ShaderNodeTexNoise", Scale=3.0)
    remap = nodes(
        tree,
        "ShaderNodeMapRange",
        **{"From Min": 0.3, "From Max": 0.7, "To Min": 800.0, "To Max": 2000.0},
    )
    tree.links.new(noise.outputs["Fac"], remap.inputs["Value"])
    return remap.outputs["Result"]


def fire(tree):
    """A Principled Volume of grey smoke (Density 1, Color 0.5) glowing as a black body
    (Blackbody Intensity 1) at noise_temperature(): flames their own smoke scatters."""
    volume = nodes(
        tree,
        "ShaderNodeVolumePrincipled",
        Density=1.0,
        Color=(0.5, 0.5, 0.5, 1.0),
        **{"Blackbody Intensity": 1.0},
    )
    tree.links.new(noise_temperature(tree), volume.inputs["Temperature"])
    return volume.outputs[0]


def fire_stage(scene):
    """The fog stage's floor and box, no fog and no lamp: a cube of fire (edge 2, fire())
    beside the box, the only light, lighting the floor and the box and scattered by its
    smoke."""
    fog_stage(scene)
    for name in ("Fog", "Spot"):
        bpy.data.objects.remove(scene.objects[name])
    flames = add_object(scene, "Fire", cube_mesh("Fire", 2.0), location=(-1.5, 0.0, 1.2))
    flames.data.materials.append(volume_material("Fire", fire))
    return scene


def smoke_stage(scene, case):
    """The fog stage with a Volume object instead of its fog box: a Mesh to Volume filling
    a sphere of radius 1.5 (hidden) at voxels of 0.1, density 1 inside and falling to 0
    over its rim. `case`: "material", a Principled Volume of Density 0.3 reading the grid;
    "default", no material (Cycles' default volume: grey, density 1 times the grid);
    "scaled", the material, the object scaled by 1.5 about the floor (a density per unit
    of the object: Volume > Render > Space, Object)."""
    fog_stage(scene)
    bpy.data.objects.remove(scene.objects["Fog"])
    source = add_object(scene, "Source", sphere_mesh("Source", 32, 16, 1.5), location=(0, 0, 2.5))
    source.hide_render = True
    smoke = mesh_to_volume(scene, "Smoke", source, 0.1)
    if case != "default":
        smoke.data.materials.append(volume_material("Smoke", principled_volume(0.3)))
    if case == "scaled":
        smoke.scale = (1.5, 1.5, 1.5)
    return scene


def smoke_domain(scene, cache_directory, frames=8, flow_type="SMOKE"):
    """A gas fluid domain (a cube of edge 3, resolution 24) filled by a sphere of radius 0.4
    emitting smoke (or what the flow's `flow_type` says: "BOTH" is fire and smoke) near its
    floor, baked for `frames` frames into `cache_directory` (OpenVDB files, Blender's
    default: data/fluid_data_0001.vdb on), at its last frame; shaded by a Principled Volume
    of Density 5 reading the domain's "density" grid, as Quick Smoke's material does. The
    domain, or None where the bake fails. (The bpy 5.0.1 module's mantaflow fails here:
    "'LevelsetGrid' object has no attribute 'setConst'", then the process crashes.)"""
    domain = add_object(scene, "Domain", cube_mesh("Domain", 3.0), location=(0.0, 0.0, 1.5))
    flow = add_object(scene, "Flow", sphere_mesh("Flow", 12, 6, 0.4), location=(0.0, 0.0, 0.5))
    flow.hide_render = True
    fluid = domain.modifiers.new("Fluid", "FLUID")
    fluid.fluid_type = "DOMAIN"
    settings = fluid.domain_settings
    settings.domain_type = "GAS"
    settings.resolution_max = 24
    settings.cache_directory = str(cache_directory)
    settings.cache_frame_end = frames
    settings.cache_type = "ALL"
    emitter = flow.modifiers.new("Fluid", "FLUID")
    emitter.fluid_type = "FLOW"
    emitter.flow_settings.flow_type = flow_type
    emitter.flow_settings.flow_behavior = "INFLOW"
    domain.data.materials.append(volume_material("Smoke", principled_volume(5.0)))
    scene.frame_end = frames
    with bpy.context.temp_override(scene=scene, active_object=domain, object=domain):
        baked = bpy.ops.fluid.bake_all()
    if baked != {"FINISHED"}:
        return None
    scene.frame_set(frames)
    return domain
