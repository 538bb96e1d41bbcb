"""Emissive meshes as lights (native scene/mesh_light.h) against Cycles: a scene lit
only by an emissive panel, with and without an occluder, a sign of many small
emitters, a rough metal reflecting the panel (the feelers and the glossy rays combined
by multiple importance sampling), and Emission Sampling honoured and reported."""

import json

import bpy
import numpy as np
import pytest
from whitted_tools.cycles_scenes import render_rgba, set_cycles_direct_light
from whitted_tools.material_scenes import emission_material, lambert_material, panel_room


def cycles_and_whitted(scene, tmp_path, samples=256):
    set_cycles_direct_light(scene, samples=samples)
    scene.cycles.light_sampling_threshold = 0.0
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    return cycles, whitted


def lit_sum_ratio(cycles, whitted, mask=None):
    """Whitted's summed red channel over Cycles', over the pixels both cover (and
    `mask` keeps), the panel itself (brighter than any lit surface) left out."""
    both = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99) & (cycles[..., 0] < 3.0)
    if mask is not None:
        both &= mask
    return whitted[both][:, 0].sum() / cycles[both][:, 0].sum(), both


@pytest.mark.parametrize("occluded", [False, True])
def test_a_panel_lights_the_scene_as_cycles(occluded, empty_scene, tmp_path, native, monkeypatch):
    # Before emissive meshes were lights this scene rendered black but for the panel.
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    panel_room(scene, lambert_material("Grey", 0.8) if occluded else None)
    cycles, whitted = cycles_and_whitted(scene, tmp_path)
    ratio, both = lit_sum_ratio(cycles, whitted)
    lit = both & (cycles[..., 0] > 0.01)
    per_pixel = np.median(whitted[lit][:, 0] / cycles[lit][:, 0])
    print(
        f"\npanel, occluded {occluded}: summed Whitted / Cycles {ratio:.4f}, median {per_pixel:.4f}"
    )
    # Measured 0.99-1.01; Cycles' own noise at 256 samples is under 1% of the sum.
    assert abs(ratio - 1.0) < 0.03
    assert abs(per_pixel - 1.0) < 0.05
    stats = json.loads(stats_path.read_text())
    emitters = {"name": "emissive meshes as lights", "on": True, "why": "1 object, 2 triangles"}
    assert emitters in stats["effects"]
    assert stats["rays"]["shadow"] > 0


def test_a_sign_of_many_small_emitters_lights_as_cycles(empty_scene, tmp_path, native, monkeypatch):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    panel = panel_room(scene, lambert_material("Grey", 0.8), cuts=31)
    # Every other row dark: a sign of stripes, 1,024 emitting triangles of 2,048.
    dark = emission_material("Dark", 0.0)
    panel.data.materials.append(dark)
    for polygon in panel.data.polygons:
        polygon.material_index = (polygon.index // 32) % 2
    cycles, whitted = cycles_and_whitted(scene, tmp_path)
    ratio, _ = lit_sum_ratio(cycles, whitted)
    print(f"\nstriped sign: summed Whitted / Cycles {ratio:.4f}")
    assert abs(ratio - 1.0) < 0.03
    stats = json.loads(stats_path.read_text())
    emitters = {
        "name": "emissive meshes as lights",
        "on": True,
        "why": "1 object, 1,024 triangles",
    }
    assert emitters in stats["effects"]


@pytest.mark.parametrize("roughness", [0.15, 0.4])
def test_a_rough_metal_reflecting_the_panel_counts_it_once(
    roughness, empty_scene, tmp_path, native
):
    # The panel reaches the sphere by its feelers and by the glossy rays; MIS weighs the
    # two as Cycles does. Summed without weights, the reflection was about twice Cycles'.
    scene = empty_scene
    metal = bpy.data.materials.new("Metal")
    if bpy.app.version < (5, 0, 0):
        metal.use_nodes = True
    bsdf = metal.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.9, 0.9, 0.9, 1.0)
    bsdf.inputs["Metallic"].default_value = 1.0
    bsdf.inputs["Roughness"].default_value = roughness
    panel_room(scene, metal)
    scene.cycles.max_bounces = scene.cycles.glossy_bounces = 1
    scene.whitted.max_depth = 1
    scene.whitted.glossy_samples = 4
    set_cycles_direct_light(scene, samples=512)
    scene.cycles.max_bounces = scene.cycles.glossy_bounces = 1
    scene.cycles.light_sampling_threshold = 0.0
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    # The sphere's pixels: where the floor-only render differs.
    bpy.data.objects["Ball"].hide_render = True
    floor_only = render_rgba(scene, "WHITTED", str(tmp_path / "floor.exr"))
    ball = np.abs(floor_only[..., 0] - whitted[..., 0]) > 1e-4
    ratio, both = lit_sum_ratio(cycles, whitted, ball)
    print(f"\nmetal {roughness} reflecting the panel: summed Whitted / Cycles {ratio:.4f}")
    assert both.sum() > 100
    assert abs(ratio - 1.0) < 0.05


@pytest.mark.parametrize("falloff", ["Linear", "Constant"])
def test_a_panel_with_light_falloff_lights_as_cycles(falloff, empty_scene, tmp_path, native):
    # The panel's Emission Strength from a Light Falloff node: Cycles evaluates it at each
    # point the floor samples with the length of the ray from the floor to it, which
    # undoes one or both powers of the inverse-square law (Linear, Constant).
    scene = empty_scene
    panel = panel_room(scene, strength=1.0)
    tree = panel.data.materials[0].node_tree
    node = tree.nodes.new("ShaderNodeLightFalloff")
    node.inputs["Strength"].default_value = 3.0
    tree.links.new(node.outputs[falloff], tree.nodes["Emission"].inputs["Strength"])
    cycles, whitted = cycles_and_whitted(scene, tmp_path)
    ratio, both = lit_sum_ratio(cycles, whitted)
    lit = both & (cycles[..., 0] > 0.01)
    per_pixel = np.median(whitted[lit][:, 0] / cycles[lit][:, 0])
    print(f"\nLight Falloff {falloff}: summed Whitted / Cycles {ratio:.4f}, median {per_pixel:.4f}")
    assert lit.sum() > 100
    assert abs(ratio - 1.0) < 0.03
    assert abs(per_pixel - 1.0) < 0.05


def test_emission_sampling_none_lights_nothing_and_says_so(
    empty_scene, tmp_path, native, monkeypatch, render_pixels
):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    scene = empty_scene
    panel = panel_room(scene)
    settings = panel.data.materials[0].cycles
    if hasattr(settings, "emission_sampling"):  # 4.0 on
        settings.emission_sampling = "NONE"
    else:
        settings.sample_as_light = False
    pixels = render_pixels(scene)
    stats = json.loads(stats_path.read_text())
    skipped = {
        "name": "emissive meshes as lights",
        "on": False,
        "why": "no mesh emits with its Emission Sampling on",
    }
    assert skipped in stats["effects"]
    # Only the panel itself shows (seen by camera rays); the floor is black.
    assert np.count_nonzero(pixels[..., 0] > 0.0) < 0.1 * pixels[..., 0].size
    if hasattr(settings, "emission_sampling"):
        settings.emission_sampling = "BACK"  # the panel's front faces down: none lit
        dark = render_pixels(scene)
        settings.emission_sampling = "FRONT"
        lit = render_pixels(scene)
        assert np.array_equal(dark, pixels)
        # All but the panel (whose anti-aliased edge pixels alone are lit when unlit).
        floor = pixels[..., 0] < 3.0
        assert lit[floor][:, 0].sum() > 20.0 * pixels[floor][:, 0].sum()
