"""The Ambient Occlusion node (issue 49, item 2) against Cycles: its Color output drives an
Emission, so each engine's image is the node's value at the camera's hits (nothing is
lit, the world is black), over a floor with a cube standing on it and a second cube
joined to the floor's own mesh (so that Only Local tells them apart). Default settings,
Only Local, Inside, a linked Normal, Distance 0 (the World's AO distance, unbounded
without a world) and Distance linked to a value 0 at the hit (no ray: 1).

Both engines average over each pixel alike (box_filtered): Cycles with 64 samples of
the node's 16 random directions each, Whitted with a 4 x 4 grid of 16 directions drawn
from the pixel's stratified sequence. Cycles' AO at a pixel is a mean of 1024 binary
draws: its standard deviation is at most 0.5 / 32 = 0.016, so the mean over the
thousands of object pixels is known to well under 1%, and SSIM is limited by the noise
of single pixels (measured below).
"""

import json

import bpy
import numpy as np
import pytest
from whitted import stats as whitted_stats
from whitted_tools.cycles_scenes import box_filtered, render_rgba
from whitted_tools.material_scenes import add_camera, black_world, empty_node_material
from whitted_tools.metrics import luminance, subject_figures

WIDTH, HEIGHT = 96, 72


def _box(x, y, half, z0=0.0):
    """Vertices and faces (outward) of an axis-aligned box standing on z = z0."""
    xs, ys, zs = (x - half, x + half), (y - half, y + half), (z0, z0 + 2.0 * half)
    vertices = [(a, b, c) for a in xs for b in ys for c in zs]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return vertices, faces


def ao_material(inside=False, only_local=False, normal_up=False, distance=None):
    """An Emission of an Ambient Occlusion node's Color (white: the AO value), samples 16;
    `distance` a float sets the socket, "zero at the hit" links Light Path's Is Shadow Ray
    to it (0 where the camera's rays meet the surface, and no constant either engine
    folds)."""
    material = empty_node_material("AO")
    tree = material.node_tree
    ao = tree.nodes.new("ShaderNodeAmbientOcclusion")
    ao.samples = 16
    ao.inside = inside
    ao.only_local = only_local
    ao.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    if distance == "zero at the hit":
        path = tree.nodes.new("ShaderNodeLightPath")
        tree.links.new(path.outputs["Is Shadow Ray"], ao.inputs["Distance"])
    elif distance is not None:
        ao.inputs["Distance"].default_value = distance
    if normal_up:
        up = tree.nodes.new("ShaderNodeCombineXYZ")
        up.inputs["Z"].default_value = 1.0
        tree.links.new(up.outputs[0], ao.inputs["Normal"])
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(ao.outputs["Color"], emission.inputs["Color"])
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(emission.outputs[0], output.inputs["Surface"])
    return material


def stage(scene, material):
    """A 6 m floor with a 1 m cube joined to its mesh (left) and a separate 1 m cube
    (right), all of `material`, seen from the front and above; no world."""
    floor = [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)]
    joined, joined_faces = _box(-0.9, 0.3, 0.5)
    faces = [(0, 1, 2, 3)] + [tuple(i + 4 for i in f) for f in joined_faces]
    mesh = bpy.data.meshes.new("Ground")
    mesh.from_pydata(floor + joined, [], faces)
    mesh.materials.append(material)
    scene.collection.objects.link(bpy.data.objects.new("Ground", mesh))
    vertices, cube_faces = _box(0.9, 0.3, 0.5)
    cube = bpy.data.meshes.new("Cube")
    cube.from_pydata(vertices, [], cube_faces)
    cube.materials.append(material)
    scene.collection.objects.link(bpy.data.objects.new("Cube", cube))
    add_camera(scene, (1.2, -4.0, 3.0), (0.0, 0.3, 0.3), lens=35.0)
    scene.world = None
    render = scene.render
    render.film_transparent = True  # alpha: the pixels the objects cover
    render.resolution_x, render.resolution_y = WIDTH, HEIGHT
    render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"


def both(scene, tmp_path):
    box_filtered(scene, cycles_samples=64, whitted_samples=4)
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    return cycles, whitted


def figures(label, cycles, whitted):
    """(SSIM of the images, summed luminance ratio over the pixels the objects cover, the
    same over those Cycles shows occluded (below 0.9), their count), printed."""
    covered = cycles[..., 3] > 0.99
    value, median = subject_figures(whitted, cycles, covered)
    w, c = luminance(whitted[..., :3]), luminance(cycles[..., :3])
    summed = w[covered].sum() / c[covered].sum()
    dark = covered & (c < 0.9)
    occluded = w[dark].sum() / c[dark].sum()
    print(
        f"\nAO {label}: SSIM {value:.4f}, summed ratio {summed:.4f} ({covered.sum()} px), "
        f"occluded {occluded:.4f} ({dark.sum()} px below 0.9), median {median:.4f}"
    )
    return value, summed, occluded, dark.sum()


CASES = {
    "default": {},
    "only local": {"only_local": True},
    "inside": {"inside": True, "distance": 0.5},
    "normal up": {"normal_up": True},
    # Distance 0: the World's AO distance, unbounded without a world, 0.4 with one.
    "distance 0": {"distance": 0.0},
    "world distance": {"distance": 0.0, "world_distance": 0.4},
}


@pytest.mark.parametrize("case", list(CASES))
def test_ambient_occlusion_matches_cycles(case, empty_scene, tmp_path, native):
    settings = dict(CASES[case])
    world_distance = settings.pop("world_distance", None)
    stage(empty_scene, ao_material(**settings))
    if world_distance is not None:
        black_world(empty_scene).light_settings.distance = world_distance
    cycles, whitted = both(empty_scene, tmp_path)
    value, summed, occluded, count = figures(case, cycles, whitted)
    # Every case darkens a good part of the objects (the test fails if the node is
    # ignored, which gives 1 everywhere).
    assert count > 200
    assert (luminance(whitted[..., :3])[cycles[..., 3] > 0.99] < 0.9).sum() > 200
    # Cycles' noise on a pixel is at most 0.016 (the module's docstring), on the mean of
    # 200 pixels at most 0.0011: the sums hold to a few thousandths. Measured (bpy 5.0 and
    # 3.4): summed 0.9999 to 1.0002, occluded 0.9997 to 1.0010, SSIM 0.9955 to 0.9987.
    assert summed == pytest.approx(1.0, abs=0.005)
    assert occluded == pytest.approx(1.0, abs=0.01)
    assert value > 0.99


def test_only_local_leaves_the_separate_cube_out(empty_scene, tmp_path, native):
    # The floor beside the separate cube (right) is occluded by it by default and not with
    # Only Local; beside the joined cube (left) it is occluded both ways.
    images = {}
    for only_local in (False, True):
        for obj in list(empty_scene.objects):
            bpy.data.objects.remove(obj)
        stage(empty_scene, ao_material(only_local=only_local))
        box_filtered(empty_scene, cycles_samples=16, whitted_samples=2)
        images[only_local] = luminance(
            render_rgba(empty_scene, "WHITTED", str(tmp_path / f"{only_local}.exr"))[..., :3]
        )
    right = (slice(None), slice(WIDTH // 2 + 8, None))
    left = (slice(None), slice(0, WIDTH // 2 - 8))
    print(
        f"\nfloor sums, default / only local: left {images[False][left].sum():.1f} / "
        f"{images[True][left].sum():.1f}, right {images[False][right].sum():.1f} / "
        f"{images[True][right].sum():.1f}"
    )
    assert images[True][right].sum() > 1.03 * images[False][right].sum()
    assert images[True][left].sum() == pytest.approx(images[False][left].sum(), rel=0.01)


def test_a_distance_of_zero_at_the_hit_gives_one_as_cycles(empty_scene, tmp_path, native):
    stage(empty_scene, ao_material(distance="zero at the hit"))
    cycles, whitted = both(empty_scene, tmp_path)
    covered = cycles[..., 3] > 0.99
    assert covered.sum() > 1000
    assert np.allclose(cycles[..., :3][covered], 1.0, atol=1e-4)
    assert np.allclose(whitted[..., :3][covered], 1.0, atol=1e-4)


def test_the_report_counts_the_nodes_rays(empty_scene, render_pixels, tmp_path, monkeypatch):
    # Every camera sample meeting the objects runs the node once: 16 rays; the statistics
    # count them in the total (so in the Whitted Rays and cost passes), the summary line
    # names them, the effects report names the material.
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    stage(empty_scene, ao_material())
    empty_scene.whitted.aa_samples = 2
    render_pixels(empty_scene)
    stats = json.loads(path.read_text())
    rays = stats["rays"]
    assert rays["ambient_occlusion"] > 0
    assert rays["ambient_occlusion"] % 16 == 0
    assert rays["ambient_occlusion"] <= 16 * rays["camera"]
    assert rays["bevel"] == 0
    assert rays["total"] >= rays["camera"] + rays["ambient_occlusion"]
    assert f"ambient occlusion {rays['ambient_occlusion'] / 1e6:.2f}" in whitted_stats.summary_line(
        stats
    )
    traced = next(e for e in stats["effects"] if e["name"] == "ray-traced nodes")
    assert traced["on"]
    assert "1 material" in traced["why"]
