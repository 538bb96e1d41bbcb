"""Hair, curves and point clouds (issue 31): particle hair with children, a Curves object
whose curves geometry nodes make, and a point cloud from Distribute Points on Faces,
each traced as round tubes or spheres (export/curves.py, native Mesh curves and points)
against Cycles' Thick curves; the report names none of them as not rendered."""

import json

import bpy
import numpy as np
import pytest
from cycles_scenes import box_filtered, render_rgba
from whitted_tools.material_scenes import (
    add_camera,
    add_floor,
    add_sun,
    dark_stage,
    lambert_material,
)
from whitted_tools.metrics import subject_figures
from whitted_tools.scenes import geometry_nodes_tree


def _plane(scene, name, size):
    mesh = bpy.data.meshes.new(name)
    h = 0.5 * size
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def _stage(scene):
    dark_stage(scene, 96, 72)
    add_floor(scene, size=20.0, albedo=0.5)
    bpy.context.active_object.location.z = -0.01
    add_camera(scene, (0.0, -2.2, 1.1), (0.0, 0.0, 0.2), lens=35.0)
    add_sun(scene, rotation=(35.0, 0.0, 25.0), strength=3.0)
    scene.whitted.ambient_strength = 0.0
    if hasattr(scene, "cycles_curves"):
        scene.cycles_curves.shape = "THICK"  # round tubes, as Whitted traces them


def particle_hair(scene):
    """A 1 m plane with 200 straight hairs and 10 interpolated children each, of radius
    0.01 m at the root to 0.004 m at the tip."""
    _stage(scene)
    emitter = _plane(scene, "Furry", 1.0)
    emitter.data.materials.append(lambert_material("Skin", 0.3))
    emitter.data.materials.append(lambert_material("Hair", 0.8))
    emitter.modifiers.new("Fur", "PARTICLE_SYSTEM")
    settings = emitter.particle_systems[0].settings
    settings.type = "HAIR"
    settings.count = 200
    settings.hair_length = 0.5
    settings.child_type = "INTERPOLATED"
    settings.rendered_child_count = 10
    settings.render_step = 3
    settings.root_radius = 1.0
    settings.tip_radius = 0.4
    settings.radius_scale = 0.02
    settings.material = 2  # the Hair slot
    return emitter


def curves_object(scene):
    """A Curves object whose geometry nodes stand a 0.6 m line, of radius 0.03, on each of
    a 7 x 7 grid's points (6 keys a curve)."""
    _stage(scene)
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
    _stage(scene)
    plane = _plane(scene, "Dusty", 1.0)
    plane.data.materials.append(lambert_material("Dust", 0.8))
    tree, group_input, output = geometry_nodes_tree("Scatter")
    nodes, links = tree.nodes, tree.links
    scatter = nodes.new("GeometryNodeDistributePointsOnFaces")
    scatter.inputs["Density"].default_value = 300.0
    radius = nodes.new("GeometryNodeSetPointRadius")
    radius.inputs["Radius"].default_value = 0.03
    lift = nodes.new("GeometryNodeSetPosition")
    lift.inputs["Offset"].default_value = (0.0, 0.0, 0.1)
    links.new(group_input.outputs[0], scatter.inputs["Mesh"])
    links.new(scatter.outputs["Points"], radius.inputs[0])
    links.new(radius.outputs[0], lift.inputs["Geometry"])
    links.new(lift.outputs["Geometry"], output.inputs[0])
    plane.modifiers.new("Scatter", "NODES").node_group = tree
    return plane


SCENES = {"particle hair": particle_hair, "curves": curves_object, "point cloud": point_cloud}


@pytest.mark.parametrize("name", SCENES)
def test_strands_and_points_as_cycles(empty_scene, tmp_path, monkeypatch, name):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    SCENES[name](scene)
    box_filtered(scene, cycles_samples=128, whitted_samples=6)
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    image = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    stats = json.loads(stats_path.read_text())
    assert np.isfinite(image).all() and stats["nonfinite_samples"] == 0
    # Counted as traced, per instance (an instanced mesh's each time): the render's
    # 2,000 children (not their 200 parents) of 9 keys, 49 curves of 6 keys, the points.
    expected = {"particle hair": ("curve_segments", 2000 * 8), "curves": ("curve_segments", 49 * 5)}
    if name in expected:
        what, count = expected[name]
        assert stats[what] == count
    else:
        assert stats["points"] > 100
    # Alone (the floor hidden), their coverage of the image: how thick and where.
    floor = scene.objects["Floor"]
    floor.hide_render = True
    alone = render_rgba(scene, "WHITTED", str(tmp_path / "alone.exr"))
    alone_cycles = render_rgba(scene, "CYCLES", str(tmp_path / "alone_cycles.exr"))
    floor.hide_render = False
    covered = alone[..., 3] > 0.5
    coverage = alone[..., 3].mean() / alone_cycles[..., 3].mean()
    value, ratio = subject_figures(image, cycles, covered)
    print(
        f"\n{name}: SSIM {value:.4f}, ratio {ratio:.4f}, coverage {alone[..., 3].mean():.4f} "
        f"(Cycles {alone_cycles[..., 3].mean():.4f})"
    )
    assert covered.mean() > 0.02  # they are in the picture
    assert coverage == pytest.approx(1.0, abs=0.05)
    assert value > 0.95
    assert abs(ratio - 1.0) < 0.05
