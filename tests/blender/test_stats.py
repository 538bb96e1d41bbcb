"""Render statistics and the cost pass: the WHITTED_STATS JSON a headless or farm
render writes, scene.whitted.last_stats, and the "Whitted Rays" render pass."""

import json

import bpy
import numpy as np
import pytest
import whitted.stats
from whitted import result
from whitted_tools.render import use_multilayer_exr

WIDTH, HEIGHT = 64, 48


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene


def test_stats_json_counts_every_ray_and_times_every_phase(
    demo, render_pixels, tmp_path, monkeypatch
):
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    demo.whitted.aa_samples = 2
    demo.whitted.max_depth = 4
    render_pixels(demo)
    stats = json.loads(path.read_text())
    assert stats["settings"] == {
        "width": WIDTH,
        "height": HEIGHT,
        "max_depth": 4,
        "aa_mode": "REGULAR",
        "aa_samples": 2,
        "aa_threshold": pytest.approx(0.3),
        "aa_depth": 3,
        "adaptive_sampling": False,
        "noise_threshold": pytest.approx(0.01),
        "adaptive_min_samples": 16,
        "light_samples": 4,
        "glossy_samples": 2,
        "emitter_samples": 2,
        "fresnel": "EXACT",
        "cutoff": pytest.approx(1.0 / 255.0),
        "texture_filter": "AUTHORED",
        "volume_step_rate": 1.0,
        "pixel_filter": "BOX",
        "filter_width": pytest.approx(1.5),  # unused by the Box
        "seed": 0,
    }
    rays = stats["rays"]
    assert rays["camera"] == WIDTH * HEIGHT * 4
    # The demo has a mirror, glass and two shadow-casting lights: every kind is traced.
    assert rays["reflection"] > 0
    assert rays["refraction"] > 0
    assert rays["shadow"] > rays["camera"]
    assert rays["transparent"] == 0  # nothing has alpha
    assert rays["volume"] == 0  # no media
    assert rays["ambient_occlusion"] == rays["bevel"] == 0  # no Ambient Occlusion or Bevel
    # The total is every kind's rays.
    assert rays["total"] == sum(n for kind, n in rays.items() if kind != "total")
    assert stats["total_internal_reflections"] > 0  # light trapped in the glass sphere
    assert stats["depth_limited"] > 0
    assert stats["samples"] == rays["camera"]
    assert stats["pixels"] == WIDTH * HEIGHT
    assert stats["samples_per_pixel"] == 4.0
    assert stats["pixel_samples"] == {"min": 4, "mean": 4.0, "max": 4}
    assert stats["noisy_pixels"] == 0
    assert stats["peak_memory_mib"] > 10.0
    phases = stats["phases"]
    assert all(phases[k] >= 0.0 for k in phases)
    assert phases["trace"] > 0.0
    assert phases["total"] >= phases["trace"] + phases["export"]
    assert stats["rays_per_second"] == pytest.approx(rays["total"] / phases["trace"])
    assert stats["nonfinite_samples"] == 0
    assert stats["cancelled"] is False
    assert stats["lights"] == 2
    # The demo's five objects in 3,072 pixels: fewer than one per 500 pixels, packets.
    packets = stats["camera_packets"]
    assert packets["on"] is True
    assert packets["visible_instances"] == 5
    assert packets["instances_per_pixel"] == pytest.approx(5 / (WIDTH * HEIGHT))
    # The same statistics stay on the scene for Python after the render.
    assert json.loads(demo.whitted.last_stats) == stats


def test_last_stats_without_the_environment_variable(demo, render_pixels, monkeypatch):
    monkeypatch.delenv("WHITTED_STATS", raising=False)
    assert demo.whitted.last_stats == ""
    render_pixels(demo)
    stats = json.loads(demo.whitted.last_stats)
    assert stats["settings"]["width"] == WIDTH
    assert stats["rays"]["total"] > 0


def test_cost_pass_holds_the_rays_of_each_pixel(demo, render_pixels, monkeypatch):
    # Read every pass back from Blender's render result right after writing it
    # (Blender 3.4 cannot read the Render Result image from Python).
    read_back = {}
    write = result._set_pass

    def write_and_read_back(render_pass, pixels):
        write(render_pass, pixels)
        back = np.empty(pixels.size if result.FLAT_RECT else pixels.shape, dtype=np.float32)
        render_pass.rect.foreach_get(back)
        read_back.setdefault(render_pass.name, []).append(back.reshape(pixels.shape))

    monkeypatch.setattr(result, "_set_pass", write_and_read_back)
    render_pixels(demo)
    stats = json.loads(demo.whitted.last_stats)
    assert sorted(read_back) == ["Combined", result.COST_PASS]
    rays = np.concatenate(read_back[result.COST_PASS])
    assert rays.shape == (WIDTH * HEIGHT, 1)
    # Every ray of the render is in some pixel; each pixel traced its 4 camera rays.
    assert rays.sum() == stats["rays"]["total"]
    assert rays.min() >= 4.0
    assert rays.max() > 4.0 * 10  # the glass and the mirror cost more
    combined = np.concatenate(read_back["Combined"])
    assert combined.shape == (WIDTH * HEIGHT, 4)
    assert np.all(combined[:, 3] == 1.0)  # the colour pass is not overwritten by the cost


def test_cost_pass_is_saved_in_a_multilayer_exr(demo, tmp_path):
    demo.render.engine = "WHITTED"
    use_multilayer_exr(demo.render.image_settings)
    demo.render.filepath = str(tmp_path / "passes.exr")
    bpy.ops.render.render(write_still=True)
    assert (tmp_path / "passes.exr").stat().st_size > 0
    text = (tmp_path / "passes.exr").read_bytes()[:4096]
    assert f"{result.COST_PASS}.X".encode() in text  # the channel list is in the header


def test_each_render_states_what_it_simulated_and_skipped(
    demo, render_pixels, tmp_path, monkeypatch
):
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    # Make the demo diffuse only: no glass, no mirror.
    for name in ("Glass", "Mirror"):
        principled = next(
            n
            for n in bpy.data.materials[name].node_tree.nodes
            if n.bl_idname == "ShaderNodeBsdfPrincipled"
        )
        for socket in ("Metallic", "Transmission Weight", "Transmission"):
            if socket in principled.inputs:
                principled.inputs[socket].default_value = 0.0
    # And no specular layer anywhere: a dielectric's, sharp or (in the Blender local
    # model) rough, reflects its surroundings, Fresnel-weighted.
    for material in bpy.data.materials:
        for node in material.node_tree.nodes if material.node_tree else ():
            if node.bl_idname == "ShaderNodeBsdfPrincipled":
                for socket in ("Specular IOR Level", "Specular"):
                    if socket in node.inputs:
                        node.inputs[socket].default_value = 0.0
    render_pixels(demo)
    stats = json.loads(path.read_text())
    refraction = {"name": "refraction", "on": False, "why": "no transmissive material"}
    reflection = {
        "name": "reflection",
        "on": False,
        "why": "no reflective or transmissive material",
    }
    assert refraction in stats["effects"]
    assert reflection in stats["effects"]
    assert stats["rays"]["reflection"] == 0
    assert stats["rays"]["refraction"] == 0
    line = whitted.stats.effects_line(stats)
    assert (
        "skipped: emissive meshes as lights (no mesh emits with its Emission Sampling on), "
        "reflection (no reflective or transmissive material)" in line
    )
    assert "shadows (lights cast shadows)" in line
    # Points facing away from one of the two lights send it no feeler.
    assert stats["shadow_rays_skipped"]["backfacing"] > 0


def test_camera_packets_are_left_out_where_hundreds_of_instances_are_in_view(
    empty_scene, render_pixels, tmp_path, monkeypatch
):
    # 400 linked duplicates of one small cube seen from above: one instance in view per
    # 7.7 pixels, far more than the one per 500 up to which packets pay (sampler.h).
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    scene = empty_scene
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location = (0.0, 0.0, 10.0)  # looking down -Z
    scene.collection.objects.link(camera)
    scene.camera = camera
    cube = bpy.data.meshes.new("pebble")
    corners = [(x, y, z) for x in (-0.1, 0.1) for y in (-0.1, 0.1) for z in (0.0, 0.2)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    cube.from_pydata(corners, [], faces)
    for i in range(20):
        for j in range(20):
            pebble = bpy.data.objects.new(f"pebble{i}_{j}", cube)
            pebble.location = (-2.375 + 0.25 * i, -2.375 + 0.25 * j, 0.0)
            scene.collection.objects.link(pebble)
    render_pixels(scene)
    packets = json.loads(path.read_text())["camera_packets"]
    assert packets["visible_instances"] == 400
    assert packets["on"] is False
