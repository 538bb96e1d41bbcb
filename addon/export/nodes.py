"""Reading shader node trees: the node behind an output, and input values by name."""

import bpy


def uses_nodes(id_data):
    """Whether a material or world is shaded by its node tree."""
    if id_data.node_tree is None:
        return False
    # Blender 5.0 always shades with the node tree and deprecates `use_nodes`.
    return bpy.app.version >= (5, 0, 0) or id_data.use_nodes


def surface_node(node_tree):
    """The node linked into the Surface socket of the active output, or None.

    Reroutes are followed; a muted link counts as no link. The active output
    is the one Cycles would render with.
    """
    output = node_tree.get_output_node("CYCLES")
    if output is None:
        return None
    return _linked_node(output.inputs["Surface"])


def input_value(node, names, default, owner, warnings):
    """The value of the first input of `node` called one of `names`, else `default`.

    `names` lists the socket's names across Blender versions (newest first). A
    linked input (a texture, say) cannot be evaluated here: its unlinked value
    is used and a warning naming `owner` and the node is added.
    """
    socket = next((s for name in names if (s := node.inputs.get(name)) is not None), None)
    if socket is None:
        return default
    if _linked_node(socket) is not None:
        warnings.append(
            f"Whitted: {owner}, node '{node.name}': input '{socket.name}' is linked; "
            "Whitted uses its unlinked value"
        )
    value = socket.default_value
    return value if isinstance(value, float) else tuple(value)


def _linked_node(socket):
    while socket.is_linked:
        link = socket.links[0]
        if link.is_muted:
            return None
        node = link.from_node
        if node.bl_idname != "NodeReroute":
            return node
        socket = node.inputs[0]
    return None
