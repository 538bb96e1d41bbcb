"""Fog and clouds (issue 48; native integrator/volume.h, heterogeneous.h,
addon/export/volume.py): a fog cube of Principled Volume density 0.1 lit by a spot lamp,
a box inside it casting its shadow into the fog, and a procedural cloud (its Density a
Noise Texture through a Color Ramp) lit by a spot and by a sun, beside Cycles with
volume, diffuse and glossy bounces 0; what each volume node exports; the report and the
statistics."""

import json
from pathlib import Path

import bpy
import numpy as np
import pytest
from whitted.export.material import convert_material
from whitted.sync.frame import sync_frame
from whitted_tools.cycles_scenes import render_rgba, set_cycles_reference
from whitted_tools.material_scenes import lambert_material
from whitted_tools.scenes import add_object, cube_mesh, facing, mesh_from_faces
from whitted_tools.world_scenes import compare


def _material(name, build):
    """A material whose output's Volume is what build(nodes) returns (an output socket),
    and no Surface."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    for node in [n for n in tree.nodes if n.bl_idname != "ShaderNodeOutputMaterial"]:
        tree.nodes.remove(node)
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(build(tree), output.inputs["Volume"])
    return material


def _principled(density, colour=(1.0, 1.0, 1.0), anisotropy=0.0):
    def build(tree):
        node = tree.nodes.new("ShaderNodeVolumePrincipled")
        node.inputs["Density"].default_value = density
        node.inputs["Color"].default_value = (*colour, 1.0)
        node.inputs["Anisotropy"].default_value = anisotropy
        return node.outputs[0]

    return build


def _fog_stage(scene, fog_bottom=-0.3):
    """A 12 x 12 floor under a spot lamp, inside a fog cube of edge 6 standing on it (its
    bottom face `fog_bottom` below the floor's plane), a box in the cone casting its shadow
    into the fog, no world; the camera outside."""
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    corners = np.array([(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], dtype=np.float32)
    floor = add_object(
        scene, "Floor", mesh_from_faces("Floor", corners, [np.array([[0, 1, 2, 3]])])
    )
    # A diffuse floor of its own: an object without a material is Cycles' default
    # Principled BSDF in Blender 5.0 (a diffuse 0.8 in 3.4 and 4.2, as Whitted's still is).
    floor.data.materials.append(lambert_material("Floor", 0.8))
    add_object(scene, "Box", cube_mesh("Box", 0.8), location=(0.3, 0.0, 1.5))
    lamp = bpy.data.lights.new("Spot", "SPOT")
    lamp.energy, lamp.spot_size, lamp.spot_blend, lamp.shadow_soft_size = 1000.0, 0.9, 0.1, 0.0
    add_object(scene, "Spot", lamp, location=(0.0, 0.0, 5.0)).rotation_euler = facing((0, 0, -1))
    fog = add_object(scene, "Fog", cube_mesh("Fog", 6.0), location=(0.0, 0.0, 3.0 + fog_bottom))
    fog.data.materials.append(_material("Fog", _principled(0.1)))
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -11.0, 3.5), facing((0.0, 11.0, -2.0))
    scene.camera = camera
    return scene


ENGINES = ("CYCLES", "WHITTED")


def _fog_against_cycles(scene, tmp_path, monkeypatch, label="fog box"):
    """Renders `scene` in Cycles and Whitted and compares them; the statistics Whitted
    wrote (WHITTED_STATS)."""
    set_cycles_reference(scene, samples=256)
    # Cycles counts a volume bound a shadow ray crosses as a transparent bounce.
    scene.cycles.transparent_max_bounces = 8
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.whitted.pixel_filter_type = "BOX"
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = 8
    scene.whitted.max_depth = 0
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    cycles, whitted = (render_rgba(scene, e, str(tmp_path / f"{e}.exr")) for e in ENGINES)
    ratio, similarity = compare(cycles, whitted)
    print(f"\n{label}: summed luminance {ratio:.4f} of Cycles', SSIM {similarity:.4f}")
    assert abs(ratio - 1.0) < 0.02
    assert similarity >= 0.97
    stats = json.loads(Path(stats_path).read_text())
    assert stats["volume_feelers"] > 0 and stats["volume_queries"] > 0
    volumes = next(e for e in stats["effects"] if e["name"] == "volumes")
    assert volumes["on"] and "1 object" in volumes["why"], volumes
    return stats


def test_a_spot_lit_fog_box_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    # Blender 3.4, seen: summed luminance 0.9985 of Cycles', SSIM 0.9995.
    _fog_against_cycles(_fog_stage(empty_scene), tmp_path, monkeypatch)


@pytest.mark.xfail(
    strict=True,
    reason="a fog box whose bottom face lies in the floor's plane (Blender 3.4, seen): "
    "Whitted lights the floor under the fog unattenuated (2.5 times Cycles' floor, about "
    "1 / (0.61 x 0.7), the feeler's and the camera ray's transmittance); with the bottom "
    "0.3 below the floor both agree. Cycles at transparent bounces 0 shows that floor "
    "black (its shadow rays stop at the coplanar bound)",
)
def test_a_fog_box_standing_on_the_floor_renders_as_cycles(empty_scene, tmp_path, monkeypatch):
    _fog_against_cycles(_fog_stage(empty_scene, fog_bottom=0.0), tmp_path, monkeypatch)


def test_the_fog_shows_and_dims_what_is_behind_it(empty_scene, render_pixels):
    scene = _fog_stage(empty_scene)
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


def _nodes(tree, kind, **inputs):
    node = tree.nodes.new(kind)
    for name, value in inputs.items():
        node.inputs[name].default_value = value
    return node


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
        absorption = _nodes(
            tree, "ShaderNodeVolumeAbsorption", Color=(0.0, 0.5, 1.0, 1.0), Density=0.4
        )
        scatter = _nodes(
            tree, "ShaderNodeVolumeScatter", Color=(0.3, 0.2, 0.1, 1.0), Density=2.0, Anisotropy=0.5
        )
        if case == "absorption":
            return absorption.outputs[0]
        if case == "scatter":
            return scatter.outputs[0]
        if case == "principled":
            # Absorption Color 1 (its sqrt 1): no absorption beyond 1 - Color's; Color 0.5.
            return _nodes(
                tree,
                "ShaderNodeVolumePrincipled",
                Color=(0.5, 0.5, 0.5, 1.0),
                Density=0.5,
                **{"Absorption Color": (1.0, 1.0, 1.0, 1.0)},
            ).outputs[0]
        mix = _nodes(tree, "ShaderNodeMixShader", Fac=0.75)
        tree.links.new(absorption.outputs[0], mix.inputs[1])
        tree.links.new(scatter.outputs[0], mix.inputs[2])
        return mix.outputs[0]

    warnings = []
    data = convert_material(_material(case.title(), build), warnings).data
    assert not data.surface and not warnings, warnings
    for name, value in expected.items():
        np.testing.assert_allclose(getattr(data, name), value, rtol=1e-6, atol=1e-7)


def _cloud(tree):
    """A Principled Volume whose Density is a Noise Texture (of the cube's Generated
    coordinates, its default) through a Color Ramp: none where the noise is below 0.45,
    0.4 where it is above 0.6 (a grey ramp: the colour's luminance is its value)."""
    volume = tree.nodes.new("ShaderNodeVolumePrincipled")
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 3.0
    ramp = tree.nodes.new("ShaderNodeValToRGB")
    low, high = ramp.color_ramp.elements
    low.position, low.color = 0.45, (0.0, 0.0, 0.0, 1.0)
    high.position, high.color = 0.6, (0.4, 0.4, 0.4, 1.0)
    tree.links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    tree.links.new(ramp.outputs["Color"], volume.inputs["Density"])
    return volume.outputs[0]


def _cloud_stage(scene, lamp="SPOT"):
    """The fog stage with a procedural cloud in the fog cube, lit by its spot lamp or
    instead by a sun."""
    _fog_stage(scene)
    scene.objects["Fog"].data.materials[0] = _material("Cloud", _cloud)
    if lamp == "SUN":
        bpy.data.objects.remove(scene.objects["Spot"])
        sun = bpy.data.lights.new("Sun", "SUN")
        sun.energy, sun.angle = 3.0, 0.0
        add_object(scene, "Sun", sun).rotation_euler = facing((0.3, 0.4, -1.0))
    return scene


@pytest.mark.parametrize("lamp", ["SPOT", "SUN"])
def test_a_procedural_cloud_renders_as_cycles(lamp, empty_scene, tmp_path, monkeypatch):
    stats = _fog_against_cycles(
        _cloud_stage(empty_scene, lamp), tmp_path, monkeypatch, label=f"cloud ({lamp})"
    )
    assert stats["volume_steps"] > 0
    volumes = next(e for e in stats["effects"] if e["name"] == "volumes")
    assert "heterogeneous" in volumes["why"], volumes


def test_a_cloud_exports_its_density_as_a_program(empty_scene):
    warnings = []
    exported = convert_material(_material("Cloud", _cloud), warnings)
    assert exported.program is not None and not warnings, warnings
    assert not exported.data.surface
    # Density drives both; the emission and the anisotropy stay constants.
    assert {name for name, _ in exported.outputs} == {"volume_absorption", "volume_scattering"}


def test_a_volume_node_it_cannot_render_is_reported(empty_scene, native):
    def build(tree):
        volume = tree.nodes.new("ShaderNodeVolumePrincipled")
        noise = tree.nodes.new("ShaderNodeTexNoise")
        tree.links.new(noise.outputs[0], volume.inputs["Blackbody Intensity"])
        return volume.outputs[0]

    scene = _fog_stage(empty_scene)
    scene.objects["Fog"].data.materials[0] = _material("Fire", build)
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    fire = [w for w in warnings if "'Fire'" in w]
    assert len(fire) == 1 and "has blackbody emission" in fire[0], warnings
