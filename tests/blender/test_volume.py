"""Fog and clouds (issue 48; native integrator/volume.h, heterogeneous.h,
addon/export/volume.py): a fog cube of Principled Volume density 0.1 lit by a spot lamp,
a box inside it casting its shadow into the fog, and a procedural cloud (its Density a
Noise Texture through a Color Ramp) lit by a spot and by a sun, beside Cycles with
volume, diffuse and glossy bounces 0; what each volume node exports; the report and the
statistics."""

import json
import math
import shutil
import subprocess
import textwrap
from pathlib import Path

import bpy
import numpy as np
import pytest
from test_passes import render_multilayer, rgb
from whitted import result
from whitted import stats as whitted_stats
from whitted.export.material import convert_material
from whitted.sync.frame import sync_frame
from whitted_tools.blender import blender_command, child_environment
from whitted_tools.camera_scenes import linear_keys
from whitted_tools.cycles_scenes import read_rgba, render_rgba, set_cycles_reference
from whitted_tools.material_scenes import glass_bsdf_material, lambert_material
from whitted_tools.metrics import luminance
from whitted_tools.scenes import (
    add_object,
    background_world,
    cube_mesh,
    facing,
    mesh_from_faces,
    sphere_mesh,
)
from whitted_tools.volume_scenes import (
    add_light,
    cloud,
    cloud_stage,
    fog_stage,
    nodes,
    noise_temperature,
    principled_volume,
    smoke_domain,
    smoke_stage,
    volume_material,
)
from whitted_tools.world_scenes import compare


def _as_cycles(scene, specular_bounces=0):
    """Cycles and Whitted set to render `scene` alike: Cycles with volume bounces 0 and
    `specular_bounces` mirror and glass bounces, both averaging over the pixel (a box)."""
    set_cycles_reference(scene, samples=256, specular_bounces=specular_bounces)
    # Cycles counts a volume bound a shadow ray crosses as a transparent bounce.
    scene.cycles.transparent_max_bounces = 8
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.whitted.pixel_filter_type = "BOX"
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = 8
    scene.whitted.max_depth = specular_bounces


def _fog_against_cycles(
    scene, tmp_path, monkeypatch, then=None, specular_bounces=0, label="fog box"
):
    """Renders `scene` in Cycles and Whitted and compares them (_against_cycles), the
    fog's lights scattered; the statistics Whitted wrote (WHITTED_STATS)."""
    stats = _against_cycles(scene, tmp_path, monkeypatch, then, specular_bounces, label)
    assert stats["volume_feelers"] > 0 and stats["volume_queries"] > 0
    volumes = next(e for e in stats["effects"] if e["name"] == "volumes")
    assert volumes["on"] and "single scattering of" in volumes["why"], volumes
    return stats


def _against_cycles(scene, tmp_path, monkeypatch, then=None, specular_bounces=0, label="fog box"):
    """Renders `scene` in Cycles and Whitted and compares them: summed luminance within 2%
    and SSIM at least 0.97; `then(scene)`, when given, changes the scene between the two;
    `specular_bounces` the mirror and glass rays both trace. The statistics Whitted wrote
    (WHITTED_STATS)."""
    _as_cycles(scene, specular_bounces)
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    if then is not None:
        then(scene)
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    ratio, similarity = compare(cycles, whitted)
    print(f"\n{label}: summed luminance {ratio:.4f} of Cycles', SSIM {similarity:.4f}")
    assert abs(ratio - 1.0) < 0.02
    assert similarity >= 0.97
    return json.loads(Path(stats_path).read_text())


def _volumes_why(stats):
    """The report's reason for the volumes (render statistics)."""
    return next(e for e in stats["effects"] if e["name"] == "volumes")["why"]


def test_a_spot_lit_fog_box_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    # Blender 3.4, seen: summed luminance 0.9985 of Cycles', SSIM 0.9995.
    _fog_against_cycles(fog_stage(empty_scene), tmp_path, monkeypatch)


@pytest.mark.parametrize("light", ["sun", "panel", "world", "hdri"])
def test_fog_lit_by_a_sun_an_emitter_and_the_world_renders_as_cycles(
    light, empty_scene, tmp_path, monkeypatch
):
    why = _volumes_why(
        _fog_against_cycles(fog_stage(empty_scene, light=light), tmp_path, monkeypatch)
    )
    named = {"sun": "the lamps'", "panel": "the emissive meshes'"}.get(light, "the world's")
    assert why.startswith("1 object: ") and f"{named} light" in why, why


def test_a_fog_box_standing_on_the_floor_renders_as_one_sunk_into_it(
    empty_scene, tmp_path, monkeypatch
):
    # The fog box's bottom face in the floor's plane: which of the two coplanar faces a ray
    # meets first is a toss-up, in Cycles too (its floor there is speckled, about half as
    # bright, seen in 3.4). Whitted meets the floor first, so the box renders as the same
    # box sunk 0.3 m into the floor does, against Cycles' render of that one.
    def stand_on_the_floor(scene):
        scene.objects["Fog"].location.z = 3.0

    scene = fog_stage(empty_scene, fog_bottom=-0.3)
    _fog_against_cycles(scene, tmp_path, monkeypatch, then=stand_on_the_floor)


def test_a_camera_inside_the_fog_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    scene = fog_stage(empty_scene)
    scene.camera.location = (0.0, -2.5, 2.5)
    _fog_against_cycles(scene, tmp_path, monkeypatch)


def test_glass_inside_the_fog_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    # A glass ball in the fog: the fog goes on inside it (Cycles fills a glass without a
    # volume with the volumes around it) and it refracts as glass in air does.
    scene = fog_stage(empty_scene)
    ball = add_object(scene, "Ball", sphere_mesh("Ball", 32, 16, 0.9), location=(-1.2, 0.0, 1.0))
    ball.data.materials.append(glass_bsdf_material("Glass", 0.0))
    _fog_against_cycles(scene, tmp_path, monkeypatch, specular_bounces=4)


def test_overlapping_fog_boxes_add_up_as_in_cycles(empty_scene, tmp_path, monkeypatch):
    # A second, denser and coloured box overlapping the first: Cycles sums the volumes
    # where they overlap.
    scene = fog_stage(empty_scene)
    dense = add_object(scene, "Dense", cube_mesh("Dense", 2.5), location=(-1.0, -1.0, 2.0))
    dense.data.materials.append(
        volume_material("Dense", principled_volume(0.3, colour=(0.9, 0.5, 0.2)))
    )
    why = _volumes_why(_fog_against_cycles(scene, tmp_path, monkeypatch))
    assert why.startswith("2 objects: "), why


@pytest.mark.parametrize("scale", [1e-3, 1e4])
def test_fog_at_tiny_and_huge_scales_renders_as_cycles(scale, empty_scene, tmp_path, monkeypatch):
    # The whole stage scaled, the densities by 1 / scale (the same optical depths) and the
    # spot's power by scale^2 (the same irradiance): the same image, against Cycles' at
    # scale 1 (Cycles 3.4's own render at 1e4 is 1.37 times as bright, seen; Whitted's sum
    # is the same to the last digit printed at 1, 1e2, 1e3 and 1e4).
    def scaled(scene):
        for obj in scene.objects:
            obj.location = obj.location * scale
            obj.scale = obj.scale * scale
        bpy.data.lights["Spot"].energy *= scale * scale
        volume = bpy.data.materials["Fog"].node_tree.nodes["Principled Volume"]
        volume.inputs["Density"].default_value /= scale
        scene.camera.data.clip_start *= scale
        scene.camera.data.clip_end *= scale

    _fog_against_cycles(fog_stage(empty_scene), tmp_path, monkeypatch, then=scaled)


def _light_passes(scene, tmp_path, engine):
    """`scene` rendered by `engine` with every pass of the View Layer's Light panel on
    (Cycles' Volume Direct and Indirect among them): {pass name: float32[h, w, 3]}, by
    their Blender 3.x names."""
    view_layer = scene.view_layers[0]
    for spec in result.PASSES:
        if spec.panel == "LIGHT":
            holder, prop = spec.switch(view_layer)
            setattr(holder, prop, True)
    channels = render_multilayer(scene, tmp_path / f"{engine}.exr", engine=engine)
    names = ("Combined", "Emit", "Env", "VolumeDir", "VolumeInd")
    names += tuple(f"{c}{k}" for c in ("Diff", "Gloss", "Trans") for k in ("Dir", "Ind", "Col"))
    return {name: rgb(channels, name) for name in names}


def _recombined(passes):
    """Combined as Blender's compositor rebuilds it from the light passes."""
    out = passes["Emit"] + passes["Env"] + passes["VolumeDir"] + passes["VolumeInd"]
    for c in ("Diff", "Gloss", "Trans"):
        out = out + passes[f"{c}Col"] * (passes[f"{c}Dir"] + passes[f"{c}Ind"])
    return out


def _summed(image):
    return float(luminance(image).sum())


def test_the_volume_direct_pass_holds_the_fogs_light_as_cycles_own(empty_scene, tmp_path):
    # Cycles' Volume Direct is the light a volume scatters once towards the camera's rays
    # (direct light at the scatter points of camera segments); with Volume Bounces 0 its
    # Volume Indirect is black (seen in 3.4 and 5.0), as Whitted's always is. Blender 3.4,
    # seen: Volume Direct summed 0.9977 of Cycles' (bpy 5.0: 0.9992).
    scene = fog_stage(empty_scene)
    _as_cycles(scene)
    cycles = _light_passes(scene, tmp_path, "CYCLES")
    whitted = _light_passes(scene, tmp_path, "WHITTED")
    ratio = _summed(whitted["VolumeDir"]) / _summed(cycles["VolumeDir"])
    print(f"\nVolume Direct: summed luminance {ratio:.4f} of Cycles'")
    assert abs(ratio - 1.0) < 0.02
    # Most of the fog's light: the cone in the fog outshines the floor it lights.
    assert _summed(whitted["VolumeDir"]) > 0.1 * _summed(whitted["Combined"])
    assert whitted["VolumeInd"].max() == 0.0 and cycles["VolumeInd"].max() == 0.0
    assert whitted["Emit"].max() == 0.0  # the fog emits nothing
    # The light passes give back Combined, the fog's light and the dimming of the floor
    # behind it among them.
    assert np.abs(_recombined(whitted) - whitted["Combined"]).max() < 1e-4


def test_the_fogs_own_emission_is_in_the_emission_pass_as_in_cycles(empty_scene, tmp_path):
    # Cycles writes a volume's emission the camera's rays meet to Emission (as a surface's);
    # its emission scattered by the fog or lighting the floor is not simulated (light that
    # scatters twice, or reaches a surface from a volume), so only Emission is compared.
    # Blender 3.4 and bpy 5.0, seen: summed 1.0000 of Cycles'.
    scene = fog_stage(empty_scene)
    volume = bpy.data.materials["Fog"].node_tree.nodes["Principled Volume"]
    volume.inputs["Emission Strength"].default_value = 0.5
    volume.inputs["Emission Color"].default_value = (1.0, 0.5, 0.2, 1.0)
    _as_cycles(scene)
    cycles = _light_passes(scene, tmp_path, "CYCLES")
    whitted = _light_passes(scene, tmp_path, "WHITTED")
    ratio = _summed(whitted["Emit"]) / _summed(cycles["Emit"])
    print(f"\nEmission of the fog: summed luminance {ratio:.4f} of Cycles'")
    assert abs(ratio - 1.0) < 0.02
    assert np.abs(_recombined(whitted) - whitted["Combined"]).max() < 1e-4


def test_the_report_counts_what_media_cost(empty_scene, render_pixels, tmp_path, monkeypatch):
    # The statistics count the fog's feelers (among the shadow rays), the rays going on
    # behind its bounds and walking feelers through them (among all rays, so in the
    # Whitted Rays pass) and a cloud's marched steps; the summary line says them, and says
    # nothing of media in a render without any.
    path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(path))
    scene = cloud_stage(empty_scene)
    scene.whitted.aa_samples = 2
    render_pixels(scene)
    stats = json.loads(path.read_text())
    rays = stats["rays"]
    assert 0 < stats["volume_feelers"] < rays["shadow"]
    assert rays["volume"] == stats["volume_bounds"] + stats["volume_queries"] > 0
    # The total is every kind's rays.
    assert rays["total"] == sum(n for kind, n in rays.items() if kind != "total")
    assert stats["volume_steps"] > 0
    line = whitted_stats.summary_line(stats)
    assert (
        f"media: {stats['volume_feelers'] / 1e6:.2f} M feelers, {rays['volume'] / 1e6:.2f} M "
        f"rays through bounds, {stats['volume_steps'] / 1e6:.2f} M steps" in line
    ), line
    bpy.data.objects.remove(scene.objects["Fog"])
    render_pixels(scene)
    stats = json.loads(path.read_text())
    assert stats["volume_feelers"] == stats["rays"]["volume"] == stats["volume_steps"] == 0
    assert "media" not in whitted_stats.summary_line(stats)


def _world_fog(scene, density, colour=(0.0, 0.0, 0.0)):
    """The stage without its fog box, in a world of `colour` whose Volume output is a
    Principled Volume of `density`: fog everywhere."""
    bpy.data.objects.remove(scene.objects["Fog"])
    scene.world = background_world("Foggy", colour)
    tree = scene.world.node_tree
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    tree.links.new(principled_volume(density)(tree), output.inputs["Volume"])
    return scene


def test_a_world_volume_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    # Fog everywhere, lit by the spot, in front of a grey world the camera sees through
    # 100 m of it (its clip end).
    scene = _world_fog(fog_stage(empty_scene), 0.05, colour=(0.5, 0.5, 0.5))
    why = _volumes_why(_fog_against_cycles(scene, tmp_path, monkeypatch))
    assert why.startswith("the world: "), why


def test_a_world_volume_lets_no_sunlight_through_as_in_cycles(empty_scene, tmp_path):
    # The sun's light crosses infinitely much of the world's fog: none arrives, in Cycles
    # too (seen in 3.4 and 5.0: a black image).
    scene = _world_fog(fog_stage(empty_scene, light="sun"), 0.05)
    set_cycles_reference(scene, samples=16)
    for engine in ("CYCLES", "WHITTED"):
        pixels = render_rgba(scene, engine, str(tmp_path / f"{engine}.exr"))
        assert pixels[..., :3].max() < 1e-6, engine


def test_the_fog_shows_and_dims_what_is_behind_it(empty_scene, render_pixels):
    scene = fog_stage(empty_scene)
    scene.whitted.aa_samples = 2
    fog = render_pixels(scene).copy()
    bpy.data.materials["Fog"].node_tree.nodes["Principled Volume"].inputs[
        "Density"
    ].default_value = 0.0
    clear = render_pixels(scene)
    # The sky above the floor is black without fog and lit with it (the cone); the floor
    # under the lamp is dimmed by the fog the light and the view cross.
    top = slice(-6, None)  # rows bottom to top
    assert clear[top, :, :3].max() == 0.0 and fog[top, :, :3].max() > 0.0
    floor = slice(0, 12)  # the near floor, under the fog
    assert fog[floor, :, :3].sum() < clear[floor, :, :3].sum()


@pytest.mark.parametrize(
    ("case", "expected"),
    [
        (
            "absorption",
            {"volume_absorption": (0.4, 0.2, 0.0), "volume_scattering": (0.0, 0.0, 0.0)},
        ),
        ("scatter", {"volume_scattering": (0.6, 0.4, 0.2), "volume_anisotropy": 0.5}),
        ("principled", {"volume_scattering": (0.25, 0.25, 0.25)}),
        ("mix", {"volume_absorption": (0.1, 0.05, 0.0), "volume_scattering": (0.45, 0.3, 0.15)}),
    ],
)
def test_each_volume_node_exports_cycles_coefficients(case, expected, empty_scene):
    def build(tree):
        absorption = nodes(
            tree, "ShaderNodeVolumeAbsorption", Color=(0.0, 0.5, 1.0, 1.0), Density=0.4
        )
        scatter = nodes(
            tree, "ShaderNodeVolumeScatter", Color=(0.3, 0.2, 0.1, 1.0), Density=2.0, Anisotropy=0.5
        )
        if case == "absorption":
            return absorption.outputs[0]
        if case == "scatter":
            return scatter.outputs[0]
        if case == "principled":
            # Absorption Color 1 (its sqrt 1): no absorption beyond 1 - Color's; Color 0.5.
            return nodes(
                tree,
                "ShaderNodeVolumePrincipled",
                Color=(0.5, 0.5, 0.5, 1.0),
                Density=0.5,
                **{"Absorption Color": (1.0, 1.0, 1.0, 1.0)},
            ).outputs[0]
        mix = nodes(tree, "ShaderNodeMixShader", Fac=0.75)
        tree.links.new(absorption.outputs[0], mix.inputs[1])
        tree.links.new(scatter.outputs[0], mix.inputs[2])
        return mix.outputs[0]

    warnings = []
    data = convert_material(volume_material(case.title(), build), warnings).data
    assert not data.surface and not warnings, warnings
    for name, value in expected.items():
        np.testing.assert_allclose(getattr(data, name), value, rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize("lamp", ["SPOT", "SUN", "PANEL", "HDRI"])
def test_a_procedural_cloud_renders_as_cycles(lamp, empty_scene, tmp_path, monkeypatch):
    # A cloud scatters the emissive meshes' and the world's light as a homogeneous fog
    # does (volume.h scattered_lights over the marched steps).
    stats = _fog_against_cycles(
        cloud_stage(empty_scene, lamp), tmp_path, monkeypatch, label=f"cloud ({lamp})"
    )
    assert stats["volume_steps"] > 0
    why = _volumes_why(stats)
    assert "heterogeneous" in why, why
    named = {"PANEL": "the emissive meshes'", "HDRI": "the world's"}.get(lamp, "the lamps'")
    assert f"{named} light" in why, why


@pytest.mark.parametrize("case", ["material", "default", "scaled"])
def test_a_volume_objects_grid_renders_as_cycles(case, empty_scene, tmp_path, monkeypatch):
    # Blender 3.4, seen (a cube's grid, before this sphere): 1.0000, 0.9876, 1.0018; bpy 5.0
    # with a voxel's value at its index point: 1.0045 (material), 0.9974 (a density 1 grey
    # cube); at its cube's centre instead 5.0 was 1.0174 and 1.0327, lopsided.
    scene = smoke_stage(empty_scene, case)
    stats = _fog_against_cycles(scene, tmp_path, monkeypatch, label=f"smoke ({case})")
    assert stats["volume_steps"] > 0
    assert "a Volume object's grids" in _volumes_why(stats), stats


def test_a_camera_inside_a_volume_objects_grid_renders_as_cycles(
    empty_scene, tmp_path, monkeypatch
):
    # The camera in the Mesh to Volume sphere's smoke, looking across it at the box: the
    # media around it are found along its rays' lines through the grid's mesh of blocks
    # (a union of cubes, not convex), as for a fog box.
    scene = smoke_stage(empty_scene, "material")
    camera = scene.camera
    camera.location, camera.rotation_euler = (0.0, -0.6, 2.4), facing((0.3, 1.0, -0.3))
    stats = _fog_against_cycles(scene, tmp_path, monkeypatch, label="smoke (camera inside)")
    assert "a Volume object's grids" in _volumes_why(stats), stats


def test_a_moving_volume_object_blurs_as_cycles(empty_scene, tmp_path, monkeypatch):
    # The Mesh to Volume sphere (its source parented to it, so its grid moves with it)
    # crossing the frame during the shutter: its grids are read where the object stands
    # at each ray's time (CompiledScene::medium), as Cycles blurs an object's volume.
    scene = smoke_stage(empty_scene, "material")
    smoke, source = scene.objects["Smoke"], scene.objects["Source"]
    source.parent = smoke
    for frame, x in ((1, -1.2), (3, 1.2)):
        smoke.location = (x, 0.0, 0.0)
        smoke.keyframe_insert("location", frame=frame)
    linear_keys(smoke)
    scene.frame_set(2)
    scene.render.use_motion_blur = True
    scene.render.motion_blur_shutter = 1.0
    stats = _fog_against_cycles(scene, tmp_path, monkeypatch, label="smoke (moving)")
    blur = next(e for e in stats["effects"] if e["name"] == "motion blur")
    assert blur["on"], blur
    # The smear, held to a closer likeness than the suite's bound. Seen: SSIM 0.9993
    # (Blender 3.4) and 0.9994 (bpy 5.0); with its grids read where the frame puts them
    # (its mesh alone moving) 0.9930 and 0.9865; with nothing of it moving 0.9926 (3.4).
    cycles, whitted = (read_rgba(tmp_path / f"{name}.exr") for name in ("cycles", "whitted"))
    assert compare(cycles, whitted)[1] >= 0.997


def test_a_baked_smoke_domain_renders_its_grids_as_cycles(empty_scene, tmp_path, monkeypatch):
    # A gas domain baked in Blender (Quick Smoke's set-up, whitted_tools.volume_scenes), its
    # "density" grid read as Cycles reads a domain's: before, Whitted filled the whole cube
    # uniformly. Blender 3.4, seen: summed luminance 1.0145 of Cycles', SSIM 0.9997 (beside
    # another lamp, 1.0421: the cause of that difference is not found; the bound here is
    # 5%, not the 2%).
    if bpy.app.version >= (5, 0, 0):
        pytest.skip(
            "the bpy 5.0.1 module's mantaflow does not bake here: 'LevelsetGrid' object has "
            "no attribute 'setConst', then the process crashed"
        )
    scene = empty_scene
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    assert smoke_domain(scene, tmp_path / "cache") is not None
    add_light(scene, "spot")
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -7.0, 2.0), facing((0.0, 7.0, -0.5))
    scene.camera = camera
    _as_cycles(scene)
    monkeypatch.setenv("WHITTED_STATS", str(tmp_path / "stats.json"))
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    ratio, similarity = compare(cycles, whitted)
    print(f"\nsmoke domain: summed luminance {ratio:.4f} of Cycles', SSIM {similarity:.4f}")
    assert abs(ratio - 1.0) < 0.05 and similarity >= 0.97
    why = _volumes_why(json.loads((tmp_path / "stats.json").read_text()))
    assert "a Volume object's grids, " in why, why


def test_a_cloud_exports_its_density_as_a_program(empty_scene):
    warnings = []
    exported = convert_material(volume_material("Cloud", cloud), warnings)
    assert exported.program is not None and not warnings, warnings
    assert not exported.data.surface
    # Density drives both; the emission and the anisotropy stay constants.
    assert {name for name, _ in exported.outputs} == {"volume_absorption", "volume_scattering"}


def test_a_volume_node_it_cannot_render_is_reported(empty_scene, native):
    def build(tree):
        return tree.nodes.new("ShaderNodeBsdfDiffuse").outputs[0]

    scene = fog_stage(empty_scene)
    scene.objects["Fog"].data.materials[0] = volume_material("Odd", build)
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    odd = [w for w in warnings if "'Odd'" in w]
    assert len(odd) == 1 and "is not a volume shader rendered" in odd[0], warnings


def _fire(temperature=None, tint=(1.0, 1.0, 1.0), density=0.2, colour=0.0):
    """A Principled Volume glowing as a black body (Blackbody Intensity 1) at 1500 K, or at
    what `temperature(tree)` (an output socket), when given, feeds its Temperature; its
    Blackbody Tint `tint`; of `density` and scattering Color `colour` (grey; 0: a smoke
    that absorbs only)."""

    def build(tree):
        volume = nodes(
            tree,
            "ShaderNodeVolumePrincipled",
            Density=density,
            Color=(colour, colour, colour, 1.0),
            Temperature=1500.0,
            **{"Blackbody Intensity": 1.0, "Blackbody Tint": (*tint, 1.0)},
        )
        if temperature is not None:
            tree.links.new(temperature(tree), volume.inputs["Temperature"])
        return volume.outputs[0]

    return build


def _mixed_fire(tree):
    """The smoky fire through a Mix Shader at 0.5 with a Volume Absorption of Density 0.4:
    Cycles 5.0 halves the fire's glow, 3.4 does not (export/volume.py)."""
    mix = nodes(tree, "ShaderNodeMixShader", Fac=0.5)
    absorption = nodes(tree, "ShaderNodeVolumeAbsorption", Density=0.4)
    tree.links.new(absorption.outputs[0], mix.inputs[1])
    tree.links.new(_fire()(tree), mix.inputs[2])
    return mix.outputs[0]


def _fire_stage(scene, build):
    """A cube of edge 2 filled with `build`'s volume, seen from above its front against
    black: no world, no lamp."""
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    fire = add_object(scene, "Fire", cube_mesh("Fire", 2.0))
    fire.data.materials.append(volume_material("Fire", build))
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -6.0, 2.5), facing((0.0, 6.0, -2.5))
    scene.camera = camera
    return scene


FIRES = [
    ("glow", _fire(density=0.0)),  # emission alone
    ("smoke", _fire()),  # and absorption
    ("mixed", _mixed_fire),
    ("noise", _fire(noise_temperature)),  # heterogeneous
    # Its own glow scattered by its smoke (glow.h; before: 0.9318 of Cycles' at Color 0.5,
    # 0.8689 at Color 1, Blender 3.4).
    ("scattering", _fire(colour=0.5)),
    ("white smoke", _fire(colour=1.0)),
]


@pytest.mark.parametrize(("case", "build"), FIRES)
def test_a_fire_renders_as_cycles(case, build, empty_scene, tmp_path, monkeypatch):
    # Cycles keeps the black body's blue, below 0 at 1500 K, which Whitted's medium
    # clamps at 0: Whitted's sum is 0.46% above Cycles' for the glow (Blender 3.4).
    stats = _against_cycles(
        _fire_stage(empty_scene, build), tmp_path, monkeypatch, label=f"fire ({case})"
    )
    volumes = next(e for e in stats["effects"] if e["name"] == "volumes")
    assert volumes["on"], volumes
    assert ("heterogeneous" in volumes["why"]) == (case == "noise"), volumes


@pytest.mark.parametrize("case", ["glow", "smoke", "noise"])
def test_a_fire_lights_the_floor_under_it_as_cycles(case, empty_scene, tmp_path, monkeypatch):
    # The fire cube above a diffuse floor, nothing else lighting it: Cycles' diffuse rays
    # gather the glow even with no bounce; Whitted's glow feelers aim at the fire's sphere
    # (lights.h). Before them the floor stayed black: Blender 3.4, the glow case, summed
    # luminance 0.83 of Cycles', SSIM 0.72.
    build = {"glow": _fire(density=0.0), "smoke": _fire(), "noise": _fire(noise_temperature)}
    scene = _fire_stage(empty_scene, build[case])
    scene.objects["Fire"].location = (0.0, 0.0, 1.5)
    corners = np.array([(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], dtype=np.float32)
    floor = add_object(
        scene, "Floor", mesh_from_faces("Floor", corners, [np.array([[0, 1, 2, 3]])])
    )
    floor.data.materials.append(lambert_material("Floor", 0.8))
    stats = _against_cycles(scene, tmp_path, monkeypatch, label=f"fire over a floor ({case})")
    assert stats["volume_feelers"] > 0
    assert "the glow of 1 object lights surfaces and media" in _volumes_why(stats)


# A fireball's grids, as a simulation cache holds them, written by OpenVDB's own Python
# module (Debian's python3-openvdb under the system's python3): a ball of 12 voxels'
# radius at voxels of 0.1, its density falling from 1 at the centre to 0 at the rim and
# its temperature (a factor of the material's Temperature) from 2 to 1.
FIREBALL = textwrap.dedent(
    """
    import sys
    import pyopenvdb as vdb
    density, temperature = vdb.FloatGrid(), vdb.FloatGrid()
    density.name, temperature.name = "density", "temperature"
    for grid in (density, temperature):
        grid.transform = vdb.createLinearTransform(voxelSize=0.1)
    d, t = density.getAccessor(), temperature.getAccessor()
    for i in range(-12, 13):
        for j in range(-12, 13):
            for k in range(-12, 13):
                r = (i * i + j * j + k * k) ** 0.5 / 12.0
                if r <= 1.0:
                    d.setValueOn((i, j, k), 1.0 - r)
                    t.setValueOn((i, j, k), 2.0 - r)
    vdb.write(sys.argv[1], grids=[density, temperature])
    """
)


def _differs_in_cycles_5(reason):
    """A strict xfail in Blender 5.0 and later, where Cycles renders the case otherwise
    than 3.4 does (`reason`: how, and what is known of why)."""
    return pytest.mark.xfail(bpy.app.version >= (5, 0, 0), strict=True, reason=reason)


FIREBALLS = [
    # Cycles 5.x reads the temperature grid one voxel at a time, picked by its trilinear
    # weight, and glows by that voxel's temperature: on average brighter at the ball's rim
    # than 3.4's glow of the interpolated temperature (export/volume.py
    # STOCHASTIC_GRID_READS). Whitted takes that average in 5.x: bpy 5.0.1, seen: 1.0046,
    # SSIM 0.9999 (0.940 and 0.987 with 3.4's interpolated glow).
    "temperature",
    # No temperature grid: a constant 1500 K glows in every block of voxels the Volume's
    # mesh encloses, wider than the ball (Cycles' mesh: VolumeObject.bound_mesh). Blender
    # 3.4, seen: 1.0055, SSIM 0.9999 (0.64 of Cycles' with the ball's box as the mesh).
    pytest.param(
        "constant",
        marks=_differs_in_cycles_5(
            "Cycles 5.0.1 renders this file's constant-temperature glow dimmer: "
            "Whitted's summed luminance is 1.82 of its, SSIM 0.705 (2.09 and 0.647 in "
            "5.2.4; with the black world; "
            "1.36 without); as if 5.0 glowed nearer the ball than the blocks of 3.4's mesh; "
            "not explained",
        ),
    ),
]


@pytest.mark.parametrize("temperature", FIREBALLS)
def test_a_fireball_from_a_vdb_file_renders_as_cycles(
    temperature, empty_scene, tmp_path, monkeypatch
):
    # Its grids' density and temperature read by a Principled Volume (blackbody, black
    # smoke), against black: Blender 3.4, seen: summed luminance 1.0083 of Cycles', SSIM
    # 0.9998. (A floor beside it is lit by the glow: test_a_fire_lights_the_floor_under_it.)
    # The black world is for Cycles 5.x: without one, the fireball is its object 0 and the
    # world's index is 0 too, so volume_is_homogeneous() takes the fireball for the world
    # and Cycles shades it as a homogeneous medium, once where each ray enters it, where
    # the grids are near 0: summed red 0.0035 in 5.0.1, 0 in 5.2.3; a world or another
    # object linked first brings back 72.3 (docs/notes/fireball_cycles5.md).
    path = tmp_path / "fireball.vdb"
    written = subprocess.run(
        ["/usr/bin/python3", "-c", FIREBALL, str(path)], capture_output=True, text=True, check=False
    )
    assert written.returncode == 0, written.stderr
    scene = empty_scene
    scene.world = background_world("Black", (0.0, 0.0, 0.0))
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -6.0, 2.5), facing((0.0, 6.0, -2.5))
    scene.camera = camera
    volume = bpy.data.volumes.new("Fireball")
    volume.filepath = str(path)
    fire = _fire(colour=0.0, density=3.0)
    volume.materials.append(volume_material("Fireball", fire))
    node = volume.materials[0].node_tree.nodes["Principled Volume"]
    if temperature == "temperature":
        node.inputs["Temperature"].default_value = 1000.0
        node.inputs["Temperature Attribute"].default_value = "temperature"
    else:
        node.inputs["Temperature Attribute"].default_value = ""
    add_object(scene, "Fireball", volume)
    why = _volumes_why(
        _against_cycles(scene, tmp_path, monkeypatch, label=f"fireball ({temperature})")
    )
    assert "a Volume object's grids, 25^3 voxels" in why, why


# Blender's own fluid solver baking a fire (smoke_domain, its flow giving fire and smoke),
# run by Blender 3.4 (`blender -b`): the bpy 5.0.1 module's mantaflow does not bake here.
FIRE_BAKE = textwrap.dedent(
    """
    import sys
    import bpy
    from whitted_tools.volume_scenes import smoke_domain
    bpy.ops.wm.read_factory_settings(use_empty=True)
    cache = sys.argv[sys.argv.index("--") + 1]
    assert smoke_domain(bpy.context.scene, cache, flow_type="BOTH") is not None
    """
)


def test_a_baked_fire_read_as_a_volume_object_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    # A fire's cache file (its last frame: "density", "flame", "temperature", "velocity"
    # grids) read by a Volume object whose Principled Volume glows as Quick Smoke's fire
    # does (Blackbody Intensity 1, Temperature 1000 times the "temperature" grid), black
    # smoke of Density 5, against a black world (Cycles 5.x needs one: the fireball's test).
    # Seen: Blender 3.4 1.0015, SSIM 0.9999; bpy 5.0.1 1.0048, SSIM 0.9999 (0.775 and 0.975
    # before Whitted took Cycles 5.x's stochastic temperature reads: the fireball's test).
    if shutil.which("blender") is None:
        pytest.skip("no `blender` (Blender 3.4) on PATH to bake the fire in")
    script, cache = tmp_path / "bake.py", tmp_path / "cache"
    script.write_text(FIRE_BAKE)
    baked = subprocess.run(
        blender_command(script, cache),
        capture_output=True,
        text=True,
        check=False,
        env=child_environment(),
    )
    assert baked.returncode == 0, baked.stdout[-2000:] + baked.stderr[-2000:]
    scene = empty_scene
    scene.world = background_world("Black", (0.0, 0.0, 0.0))
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -7.0, 2.0), facing((0.0, 7.0, -0.5))
    scene.camera = camera
    volume = bpy.data.volumes.new("Fire")
    volume.filepath = str(cache / "data" / "fluid_data_0008.vdb")
    volume.materials.append(volume_material("Fire", _fire(colour=0.0, density=5.0)))
    node = volume.materials[0].node_tree.nodes["Principled Volume"]
    node.inputs["Temperature"].default_value = 1000.0
    node.inputs["Temperature Attribute"].default_value = "temperature"
    # The cache's grids start at the domain's lowest corner (their index 0 at the origin,
    # voxels of 3 / 24 m): there, the fire stands where the domain had it.
    add_object(scene, "Fire", volume, location=(-1.5, -1.5, 0.0))
    why = _volumes_why(_against_cycles(scene, tmp_path, monkeypatch, label="baked fire"))
    assert "a Volume object's grids" in why, why


def test_a_fire_exports_cycles_blackbody_emission(empty_scene):
    # Blackbody Tint * 5.670373e-8 * 1e-6 / pi * T^4 * the node's colour at 1500 K as
    # Cycles 3.4 renders the Blackbody node: red 3.26430678, green 0.434045345; the node
    # clamps the fit's blue, below 0 there, which the volume's emission keeps.
    tint = (1.0, 0.5, 0.25)
    warnings = []
    data = convert_material(volume_material("Fire", _fire(tint=tint)), warnings).data
    assert not warnings, warnings
    glow = 5.670373e-8 * 1e-6 / math.pi * 1500.0**4
    expected = glow * np.array(tint[:2]) * np.array([3.26430678, 0.434045345])
    np.testing.assert_allclose(data.volume_emission[:2], expected, rtol=1e-5)
    assert data.volume_emission[2] < 0.0
    # A Temperature a texture drives: the emission is the program's.
    exported = convert_material(volume_material("Flames", _fire(noise_temperature)), warnings)
    assert not warnings, warnings
    assert "volume_emission" in dict(exported.outputs)


def test_volume_bounces_above_0_are_reported_as_not_simulated(empty_scene, native):
    scene = fog_stage(empty_scene)
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    assert not [w for w in warnings if "Volume Bounces" in w], warnings
    scene.cycles.volume_bounces = 2
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    said = [w for w in warnings if "Volume Bounces is 2" in w]
    assert len(said) == 1 and "scatter light once" in said[0], warnings
    # Fog in the world alone says it too.
    _world_fog(scene, 0.05)
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    assert len([w for w in warnings if "Volume Bounces is 2" in w]) == 1, warnings
