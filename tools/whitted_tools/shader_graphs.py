"""Shader node set-ups of real files, built by script (tests and scripts share them; bpy)."""

import bpy


def new_material(name):
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    return material


def principled(material):
    return material.node_tree.nodes["Principled BSDF"]


def output(material):
    return material.node_tree.nodes["Material Output"]


def first_input(node, names):
    return next(node.inputs[n] for n in names if n in node.inputs)


def new_group(name, inputs=(), outputs=()):
    """A shader node group with (name, socket type, default) inputs and (name, socket
    type) outputs; returns (tree, group input node, group output node)."""
    tree = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for socket_name, socket_type, default in inputs:
        if hasattr(tree, "interface"):  # Blender 4.0+
            socket = tree.interface.new_socket(socket_name, in_out="INPUT", socket_type=socket_type)
        else:
            socket = tree.inputs.new(socket_type, socket_name)
        if default is not None:
            socket.default_value = default
    for socket_name, socket_type in outputs:
        if hasattr(tree, "interface"):
            tree.interface.new_socket(socket_name, in_out="OUTPUT", socket_type=socket_type)
        else:
            tree.outputs.new(socket_type, socket_name)
    return tree, tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")


def group_node(material, tree):
    node = material.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = tree
    return node


def gltf_wrapper_material(name, image):
    """The old glTF importer's set-up: a group holding a Principled BSDF whose Base
    Color comes from a group input, fed by an Image Texture outside the group."""
    tree, group_in, group_out = new_group(
        f"{name} settings",
        inputs=[
            ("Base Color", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0)),
            ("Roughness", "NodeSocketFloat", 0.25),
        ],
        outputs=[("Shader", "NodeSocketShader")],
    )
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    tree.links.new(group_in.outputs["Base Color"], bsdf.inputs["Base Color"])
    tree.links.new(group_in.outputs["Roughness"], bsdf.inputs["Roughness"])
    tree.links.new(bsdf.outputs[0], group_out.inputs["Shader"])
    material = new_material(name)
    nodes = material.node_tree.nodes
    nodes.remove(principled(material))
    group = group_node(material, tree)
    group.inputs["Roughness"].default_value = 0.25
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Color"], group.inputs["Base Color"])
    material.node_tree.links.new(group.outputs["Shader"], output(material).inputs["Surface"])
    return material, group, texture
