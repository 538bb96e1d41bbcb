"""What artists' files hold, by Whitted beside Cycles (in Blender): docs/FEATURES.md.

The features issue 49 added (a shadow catcher, the Ambient Occlusion and Bevel nodes,
anisotropic metal, an area lamp seen in a mirror, the Displacement output as a bump and
moving the vertices, a
coat over a glossy base), each in a small scene beside Cycles, with the time of its
render against the same scene with the feature turned off as an artist would turn it
off. The harness, measures and page are the distributed ray tracing gallery's
(gallery/effects.py).

    blender -b --factory-startup --python-exit-code 1 \
        --python tools/whitted_tools/__main__.py -- gallery-features --out docs
    .venv-5.2/bin/python -m whitted_tools gallery-features --out docs      (bpy 5.2 module)
"""

import bpy

# isort: split
from whitted_tools.gallery.effects import Page, run, sphere_on_floor
from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    grey_world,
    principled_sphere_material,
    smooth_sphere,
)

# --- the scenes: each builds itself; its switch turns the feature on and off ----------


def _principled(material):
    return material.node_tree.nodes["Principled BSDF"]


def _input(node, *names):
    """The first of `names` that `node` has: Blender renamed sockets between 3.x and 4.0."""
    return next(node.inputs[n] for n in names if n in node.inputs)


def _linked(material, from_socket, to_socket, on):
    """Link `from_socket` to `to_socket` of `material`'s tree, or unlink it."""
    links = material.node_tree.links
    if on:
        links.new(from_socket, to_socket)
    else:
        for link in list(to_socket.links):
            links.remove(link)


def scene_shadow_catcher(scene):
    """A plastic ball floating over a floor set as a shadow catcher, over the grey world
    (an opaque film: the catcher shows the world dimmed by the ball's shadow)."""
    sphere_on_floor(scene, principled_sphere_material("Plastic", (0.6, 0.1, 0.05), 0.3))
    bpy.data.objects["Ball"].location.z = 1.2  # floating 0.2 m above the floor
    catcher(scene, True)

    def finish(scene):
        scene.render.film_transparent = False

    return finish


def catcher(scene, on):
    bpy.data.objects["Floor"].is_shadow_catcher = on


def _monkey(scene, material):
    """Suzanne (crevices at the eyes and ears) on a floor under a sun and the grey sky."""
    grey_world(scene, 0.5)
    add_floor(scene, size=12.0, albedo=0.6)
    bpy.ops.mesh.primitive_monkey_add(size=2.0, location=(0.0, 0.0, 1.0), rotation=(0.4, 0, 0))
    monkey = bpy.context.active_object
    monkey.name = "Monkey"
    bpy.ops.object.shade_smooth()
    monkey.data.materials.append(material)
    add_camera(scene, (0.0, -4.5, 1.6), (0.0, 0.0, 1.0), lens=60.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=2.0)
    scene.whitted.ambient_strength = 0.0


def scene_ambient_occlusion(scene):
    """Suzanne whose base colour is an Ambient Occlusion node's Color (0.8 grey, distance
    0.3 m): darker in its crevices."""
    material = principled_sphere_material("Occluded", (0.8, 0.8, 0.8), 0.5)
    ao = material.node_tree.nodes.new("ShaderNodeAmbientOcclusion")
    ao.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    ao.inputs["Distance"].default_value = 0.3
    _monkey(scene, material)
    occlusion(scene, True)


def occlusion(scene, on):
    material = bpy.data.materials["Occluded"]
    ao = material.node_tree.nodes["Ambient Occlusion"]
    _linked(material, ao.outputs["Color"], _principled(material).inputs["Base Color"], on)


def scene_bevel(scene):
    """A cube turned towards the camera, its edges rounded by a Bevel node (radius 0.1 m)
    into the Principled's Normal, under a sun."""
    grey_world(scene, 0.5)
    add_floor(scene, size=12.0, albedo=0.6)
    bpy.ops.mesh.primitive_cube_add(size=1.6, location=(0.0, 0.0, 0.8), rotation=(0, 0, 0.6))
    cube = bpy.context.active_object
    cube.name = "Cube"
    material = principled_sphere_material("Bevelled", (0.7, 0.45, 0.2), 0.4)
    bevel_node = material.node_tree.nodes.new("ShaderNodeBevel")
    bevel_node.inputs["Radius"].default_value = 0.1
    cube.data.materials.append(material)
    add_camera(scene, (0.0, -4.5, 2.6), (0.0, 0.0, 0.8), lens=60.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=2.0)
    scene.whitted.ambient_strength = 0.0
    bevel(scene, True)


def bevel(scene, on):
    material = bpy.data.materials["Bevelled"]
    node = material.node_tree.nodes["Bevel"]
    _linked(material, node.outputs["Normal"], _principled(material).inputs["Normal"], on)


def scene_brushed_metal(scene):
    """A steel ball of roughness 0.3, Anisotropic 0.9 about the default radial tangent."""
    sphere_on_floor(scene, principled_sphere_material("Steel", (0.8, 0.8, 0.8), 0.3, metallic=1.0))
    anisotropy(scene, True)


def anisotropy(scene, on):
    _input(_principled(bpy.data.materials["Steel"]), "Anisotropic").default_value = (
        0.9 if on else 0.0
    )


def scene_softbox_in_chrome(scene):
    """A chrome ball (roughness 0.05) under a 1.5 x 0.8 m area lamp up to its left: the
    lamp's rectangle shows in the ball."""
    sphere_on_floor(
        scene, principled_sphere_material("Chrome", (0.9, 0.9, 0.9), 0.05, metallic=1.0)
    )
    lamp = bpy.data.lights.new("Softbox", "AREA")
    lamp.shape, lamp.size, lamp.size_y, lamp.energy = "RECTANGLE", 1.5, 0.8, 300.0
    softbox = bpy.data.objects.new("Softbox", lamp)
    softbox.location = (-1.6, -1.6, 2.6)
    softbox.rotation_euler = (0.7, 0.0, -0.8)
    scene.collection.objects.link(softbox)


def lamp_in_glossy(scene, on):
    bpy.data.objects["Softbox"].visible_glossy = on


def scene_bump_displacement(scene):
    """A ball whose Displacement output is a Noise texture (scale 6) through a
    Displacement node of Scale 0.05: Cycles' default method, Bump Only."""
    material = principled_sphere_material("Bumpy", (0.2, 0.35, 0.6), 0.35)
    nodes = material.node_tree.nodes
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 6.0
    displacement = nodes.new("ShaderNodeDisplacement")
    displacement.inputs["Scale"].default_value = 0.05
    material.node_tree.links.new(noise.outputs["Fac"], displacement.inputs["Height"])
    sphere_on_floor(scene, material)
    displaced(scene, True)


def displaced(scene, on):
    material = bpy.data.materials["Bumpy"]
    nodes = material.node_tree.nodes
    output = nodes["Material Output"].inputs["Displacement"]
    _linked(material, nodes["Displacement"].outputs["Displacement"], output, on)


def scene_displaced(scene):
    """A ball (128 x 64 faces) whose vertices a Noise texture (scale 4) moves along their
    normals, by a Displacement node of Scale 0.15: Displacement Only, Cycles without
    adaptive subdivision."""
    material = principled_sphere_material("Displaced", (0.55, 0.4, 0.25), 0.5)
    nodes = material.node_tree.nodes
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 4.0
    displacement = nodes.new("ShaderNodeDisplacement")
    displacement.inputs["Scale"].default_value = 0.15
    links = material.node_tree.links
    links.new(noise.outputs["Fac"], displacement.inputs["Height"])
    links.new(displacement.outputs["Displacement"], nodes["Material Output"].inputs["Displacement"])
    sphere_on_floor(scene, material)
    bpy.data.objects.remove(bpy.data.objects["Ball"])  # for a denser one
    smooth_sphere("Ball", (0.0, 0.0, 1.0), 1.0, material, segments=128, rings=64)
    moved(scene, True)


def moved(scene, on):
    material = bpy.data.materials["Displaced"]
    settings = material if hasattr(material, "displacement_method") else material.cycles
    settings.displacement_method = "DISPLACEMENT" if on else "BUMP"


def scene_coat(scene):
    """A red plastic of roughness 0.4 under a full clear coat of roughness 0.05 (3.x
    Clearcoat, 4.x+ Coat Weight)."""
    sphere_on_floor(scene, principled_sphere_material("Coated", (0.5, 0.03, 0.03), 0.4))
    bsdf = _principled(bpy.data.materials["Coated"])
    _input(bsdf, "Clearcoat Roughness", "Coat Roughness").default_value = 0.05
    coated(scene, True)


def coated(scene, on):
    bsdf = _principled(bpy.data.materials["Coated"])
    _input(bsdf, "Clearcoat", "Coat Weight").default_value = 1.0 if on else 0.0


# (name, build, the feature's name in the report (None: a material's shading, which the
# report does not name), what turns it on and off, how off)
SCENES = (
    ("shadow_catcher", scene_shadow_catcher, "shadow catcher", catcher, "Shadow Catcher off"),
    ("ambient_occlusion", scene_ambient_occlusion, "ray-traced nodes", occlusion, "AO unlinked"),
    ("bevel", scene_bevel, "ray-traced nodes", bevel, "Bevel unlinked"),
    ("brushed_metal", scene_brushed_metal, "glossy reflection", anisotropy, "Anisotropic 0"),
    (
        "softbox_in_chrome",
        scene_softbox_in_chrome,
        "lamps seen by rays",
        lamp_in_glossy,
        "the lamp's Visibility > Glossy off",
    ),
    ("bump_displacement", scene_bump_displacement, None, displaced, "Displacement unlinked"),
    ("displaced_vertices", scene_displaced, "displacement", moved, "Bump Only"),
    ("coat", scene_coat, "glossy reflection", coated, "Coat 0"),
)

FEATURES_PAGE = Page(
    __name__,
    __doc__,
    "gallery-features",
    "FEATURES.md",
    "features",
    "What artists' files hold: Whitted beside Cycles",
    "What issue 49 added for the scenes artists make: a shadow catcher, the ray-traced "
    "Ambient Occlusion and Bevel nodes, anisotropic metal, an area lamp seen in a mirror, "
    "the Displacement output shaded as a bump and moving the vertices, a clear coat over a "
    "glossy base. Each "
    "scene's feature is turned off as an artist would turn it off (the last column).",
    SCENES,
)


def main(argv):
    run(argv, FEATURES_PAGE)
