"""World export: background radiance and ambient light."""

import bpy
import pytest
from whitted.export.world import convert_world


def node_world(color, strength):
    world = bpy.data.worlds.new("World")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    return world


def test_no_world_is_black(warnings):
    world = convert_world(None, warnings)
    assert world.background == (0.0, 0.0, 0.0)
    assert world.ambient == (0.0, 0.0, 0.0)


def test_background_node_color_times_strength(warnings):
    world = convert_world(node_world((0.2, 0.4, 0.8), 2.0), warnings)
    assert world.background == pytest.approx((0.4, 0.8, 1.6))
    assert world.ambient == pytest.approx((0.4, 0.8, 1.6))
    assert warnings == []


def test_linked_background_color_warns(warnings):
    world = node_world((0.2, 0.4, 0.8), 1.0)
    tree = world.node_tree
    sky = tree.nodes.new("ShaderNodeTexSky")
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    assert convert_world(world, warnings).background == pytest.approx((0.2, 0.4, 0.8))
    assert "'World'" in warnings[0]
    assert "'Background'" in warnings[0]


def test_world_without_nodes_uses_its_colour(warnings):
    if bpy.app.version >= (5, 0, 0):
        pytest.skip("Blender 5.0 worlds always use nodes")
    world = bpy.data.worlds.new("Plain")
    world.use_nodes = False
    world.color = (0.1, 0.2, 0.3)
    assert convert_world(world, warnings).background == pytest.approx((0.1, 0.2, 0.3))
