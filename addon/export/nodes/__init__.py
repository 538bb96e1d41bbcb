"""Reading shader node trees (graph.py walks them; values.py and shaders.py lower them)."""

import bpy

from .graph import source


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
    """The node linked into the Surface socket of the active output (the one Cycles
    renders with), or None: reroutes followed, groups entered, a muted link no link
    (graph.source)."""
    output = node_tree.get_output_node("CYCLES")
    if output is None:
        return None
    found, _ = source(output.inputs["Surface"])
    return None if found is None else found.node
