"""The memory guard (addon/memory.py): a render that would not fit is refused with a
clear report before anything large is allocated, and Blender carries on."""

import json

import bpy
import pytest
from exported import exported_meshes
from whitted import memory


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    return scene


def test_estimate_counts_what_the_export_exports(demo):
    # A subdivided mesh with quads and an n-gon, besides the demo's meshes.
    bpy.ops.mesh.primitive_cylinder_add(vertices=7, location=(0, -5, 1))
    cylinder = bpy.context.object
    cylinder.modifiers.new("Subdivision", "SUBSURF").levels = 2
    depsgraph = bpy.context.evaluated_depsgraph_get()
    estimate = memory.estimate(depsgraph, 64 * 48)
    exported = exported_meshes(depsgraph, [])
    assert estimate.triangles == sum(len(mesh.triangles) for mesh in exported.meshes)
    assert estimate.instances == len(exported.instances)
    assert estimate.pixels == 64 * 48
    assert estimate.bytes > memory.BASE_BYTES


def test_a_render_over_the_budget_is_refused_and_blender_carries_on(demo, monkeypatch):
    monkeypatch.setenv("WHITTED_MEMORY_BUDGET", "1")  # MiB: less than the module itself
    with pytest.raises(RuntimeError, match=r"needs about \d+ MiB, \d+ MiB more than the budget"):
        bpy.ops.render.render()
    monkeypatch.delenv("WHITTED_MEMORY_BUDGET")
    bpy.ops.render.render()
    stats = json.loads(demo.whitted.last_stats)
    assert stats["pixels"] == 64 * 48
    assert 0 < stats["memory_estimate_mib"] < 64


def test_a_giant_resolution_is_refused_against_the_memory_available(demo):
    # As many pixels as Blender allows (it clamps the size): billions, at 40 B each far
    # more than this machine has.
    demo.render.resolution_x = demo.render.resolution_y = 100_000
    with pytest.raises(RuntimeError, match="more than the memory available"):
        bpy.ops.render.render()


def test_a_budget_that_is_not_a_number_is_reported(demo, monkeypatch):
    monkeypatch.setenv("WHITTED_MEMORY_BUDGET", "lots")
    with pytest.raises(RuntimeError, match="WHITTED_MEMORY_BUDGET='lots' is not a number"):
        bpy.ops.render.render()


def test_the_preference_budget_refuses_too(demo):
    preferences = bpy.context.preferences.addons["whitted"].preferences
    preferences.memory_budget_mib = 2
    try:
        with pytest.raises(RuntimeError, match="the memory budget in the add-on's preferences"):
            bpy.ops.render.render()
    finally:
        preferences.memory_budget_mib = 0
    bpy.ops.render.render()  # unset again: the memory available
