"""Geometry-nodes trees shared by the tests and scripts/bench_instances.py."""

import bpy


def ico_sphere_on_points(name, radius=1.0, subdivisions=1):
    """A geometry-nodes tree that puts an ico sphere on every point of its input."""
    tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if hasattr(tree, "interface"):  # Blender 4.0+
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    group_input = tree.nodes.new("NodeGroupInput")
    group_output = tree.nodes.new("NodeGroupOutput")
    instance_on_points = tree.nodes.new("GeometryNodeInstanceOnPoints")
    ico_sphere = tree.nodes.new("GeometryNodeMeshIcoSphere")
    ico_sphere.inputs["Radius"].default_value = radius
    ico_sphere.inputs["Subdivisions"].default_value = subdivisions
    tree.links.new(group_input.outputs[0], instance_on_points.inputs["Points"])
    tree.links.new(ico_sphere.outputs["Mesh"], instance_on_points.inputs["Instance"])
    tree.links.new(instance_on_points.outputs["Instances"], group_output.inputs[0])
    return tree
