"""Reading shader node trees: the node behind an output, and input values by name."""

import bpy


def uses_nodes(id_data):
    """Whether a material or world is shaded by its node tree."""
    if id_data.node_tree is None:
        return False
    # Blender 5.0 always shades with the node tree and deprecates `use_nodes`.
    return bpy.app.version >= (5, 0, 0) or id_data.use_nodes


def warn(warnings, message):
    """Append `message` unless it is already there: each problem is reported once
    per render, however many paths of a node tree lead to it."""
    if message not in warnings:
        warnings.append(message)


def surface_node(node_tree):
    """The node linked into the Surface socket of the active output, or None.

    Reroutes are followed; a muted link counts as no link. The active output
    is the one Cycles would render with.
    """
    output = node_tree.get_output_node("CYCLES")
    if output is None:
        return None
    return linked_node(output.inputs["Surface"])


def find_input(node, names):
    """The first input of `node` called one of `names` (newest name first), or None."""
    return next((s for name in names if (s := node.inputs.get(name)) is not None), None)


def socket_value(socket):
    """An unlinked socket's value: a float, or a tuple for colours and vectors."""
    value = socket.default_value
    return value if isinstance(value, float) else tuple(value)


def input_value(node, names, default, owner, warnings):
    """The value of the first input of `node` called one of `names`, else `default`.

    `names` lists the socket's names across Blender versions (newest first). A
    linked input (a texture, say) cannot be evaluated here: its unlinked value
    is used and a warning naming `owner` and the node is added.
    """
    socket = find_input(node, names)
    if socket is None:
        return default
    if linked_node(socket) is not None:
        warn(
            warnings,
            f"Whitted: {owner}, node '{node.name}': input '{socket.name}' is linked; "
            "Whitted uses its unlinked value",
        )
    return socket_value(socket)


def linked_node(socket):
    """The node whose output feeds `socket` (reroutes followed), or None."""
    output = linked_output(socket)
    return None if output is None else output.node


def linked_output(socket):
    """The output socket that feeds `socket`, following reroutes; None when unlinked
    or when a link on the way is muted."""
    while socket.is_linked:
        link = socket.links[0]
        if link.is_muted:
            return None
        if link.from_node.bl_idname != "NodeReroute":
            return link.from_socket
        socket = link.from_node.inputs[0]
    return None
