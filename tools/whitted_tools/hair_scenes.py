"""Hair, curves and point-cloud scenes, shared by their tests against Cycles
(tests/blender/test_hair.py) and the hair benchmark (whitted_tools bench-hair)."""

import math

import bpy

from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    dark_stage,
    lambert_material,
)
from whitted_tools.scenes import geometry_nodes_tree


def flat_square(scene, name, size):
    """A square of `size` m in the plane z = 0, facing up, as object `name`."""
    mesh = bpy.data.meshes.new(name)
    h = 0.5 * size
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def stage(scene):
    """96x72 on a black world, a floor just under z = 0, a camera 2.2 m away looking a
    little down at the origin, a sun; Cycles' curves as Thick (round, as Whitted's)."""
    dark_stage(scene, 96, 72)
    add_floor(scene, size=20.0, albedo=0.5)
    bpy.context.active_object.location.z = -0.01
    add_camera(scene, (0.0, -2.2, 1.1), (0.0, 0.0, 0.2), lens=35.0)
    add_sun(scene, rotation=(35.0, 0.0, 25.0), strength=3.0)
    scene.whitted.ambient_strength = 0.0
    if hasattr(scene, "cycles_curves"):
        scene.cycles_curves.shape = "THICK"  # round tubes, as Whitted traces them


def particle_hair(scene, parents=200, children=10):
    """A 1 m plane with `parents` straight hairs and `children` interpolated children
    each (9 keys a strand in renders), of radius 0.01 m at the root to 0.004 m at the
    tip."""
    stage(scene)
    emitter = flat_square(scene, "Furry", 1.0)
    emitter.data.materials.append(lambert_material("Skin", 0.3))
    emitter.data.materials.append(lambert_material("Hair", 0.8))
    grow_fur(emitter, parents, children, length=0.5, radius_scale=0.02)
    return emitter


def grow_fur(obj, parents, children, length, radius_scale):
    """Particle hair on mesh object `obj`: `parents` straight hairs of `length` with
    `children` interpolated children each, 9 keys a strand in renders, radius
    `radius_scale` at the root to 0.4 of it at the tip, in the object's second material
    slot."""
    obj.modifiers.new("Fur", "PARTICLE_SYSTEM")
    settings = obj.particle_systems[0].settings
    settings.type = "HAIR"
    settings.count = parents
    settings.hair_length = length
    settings.child_type = "INTERPOLATED"
    settings.rendered_child_count = children
    settings.render_step = 3
    settings.root_radius = 1.0
    settings.tip_radius = 0.4
    settings.radius_scale = radius_scale
    settings.material = 2


def ribbon_hair(scene):
    """particle_hair with Cycles' default curve shape, Ribbons, strands twice as thick
    and the sun 20 degrees off the upright strands: ribbons there shade their own
    strand further along (a feeler within 30 degrees of a strand meets it), round tubes
    do not, so the two shapes render apart."""
    emitter = particle_hair(scene)
    emitter.particle_systems[0].settings.radius_scale = 0.04
    bpy.data.objects["Sun"].rotation_euler = tuple(math.radians(a) for a in (20.0, 0.0, 25.0))
    if hasattr(scene, "cycles_curves"):
        scene.cycles_curves.shape = "RIBBONS"
    return emitter


def curves_object(scene):
    """A Curves object whose geometry nodes stand a 0.6 m line, of radius 0.03, on each of
    a 7 x 7 grid's points (6 keys a curve)."""
    stage(scene)
    data = bpy.data.hair_curves.new("Strands")
    data.materials.append(lambert_material("Strands", 0.8))
    obj = bpy.data.objects.new("Strands", data)
    scene.collection.objects.link(obj)
    tree, _, output = geometry_nodes_tree("Stand lines")
    nodes, links = tree.nodes, tree.links
    grid = nodes.new("GeometryNodeMeshGrid")
    grid.inputs["Vertices X"].default_value = grid.inputs["Vertices Y"].default_value = 7
    grid.inputs["Size X"].default_value = grid.inputs["Size Y"].default_value = 1.2
    points = nodes.new("GeometryNodeMeshToPoints")
    line = nodes.new("GeometryNodeCurvePrimitiveLine")
    line.inputs["End"].default_value = (0.1, 0.0, 0.6)
    resample = nodes.new("GeometryNodeResampleCurve")
    resample.inputs["Count"].default_value = 6
    on_points = nodes.new("GeometryNodeInstanceOnPoints")
    realize = nodes.new("GeometryNodeRealizeInstances")
    radius = nodes.new("GeometryNodeSetCurveRadius")
    radius.inputs["Radius"].default_value = 0.03
    links.new(grid.outputs["Mesh"], points.inputs["Mesh"])
    links.new(line.outputs["Curve"], resample.inputs["Curve"])
    links.new(points.outputs["Points"], on_points.inputs["Points"])
    links.new(resample.outputs["Curve"], on_points.inputs["Instance"])
    links.new(on_points.outputs["Instances"], realize.inputs["Geometry"])
    links.new(realize.outputs["Geometry"], radius.inputs["Curve"])
    links.new(radius.outputs["Curve"], output.inputs[0])
    obj.modifiers.new("Lines", "NODES").node_group = tree
    return obj


def point_cloud(scene):
    """A 1 m plane whose geometry nodes scatter 300 points of radius 0.03 over it, lifted
    0.1 m (a point cloud, not instances)."""
    stage(scene)
    plane = flat_square(scene, "Dusty", 1.0)
    plane.data.materials.append(lambert_material("Dust", 0.8))
    point_cloud_modifier(plane, density=300.0, radius=0.03)
    return plane


def point_cloud_modifier(obj, density, radius):
    """Geometry nodes on mesh object `obj` that replace it by points scattered over its
    faces (`density` a square metre) of `radius`, lifted 0.1 m: a point cloud."""
    tree, group_input, output = geometry_nodes_tree("Scatter")
    nodes, links = tree.nodes, tree.links
    scatter = nodes.new("GeometryNodeDistributePointsOnFaces")
    scatter.inputs["Density"].default_value = density
    set_radius = nodes.new("GeometryNodeSetPointRadius")
    set_radius.inputs["Radius"].default_value = radius
    lift = nodes.new("GeometryNodeSetPosition")
    lift.inputs["Offset"].default_value = (0.0, 0.0, 0.1)
    links.new(group_input.outputs[0], scatter.inputs["Mesh"])
    links.new(scatter.outputs["Points"], set_radius.inputs[0])
    links.new(set_radius.outputs[0], lift.inputs["Geometry"])
    links.new(lift.outputs["Geometry"], output.inputs[0])
    obj.modifiers.new("Scatter", "NODES").node_group = tree


SCENES = {"particle hair": particle_hair, "curves": curves_object, "point cloud": point_cloud}
