"""A material without a Surface output is no surface (issue 48, step 0): the issue's fog
box, a cube whose material has a Principled Volume and no surface shader over a floor lit
by a spot lamp, shows what is behind it (Whitted used to draw it opaque black), the camera
outside the cube or inside it, as Cycles lets rays through a volume's bounds; the report
says nothing of a constant volume, which renders (test_volume.py)."""

from dataclasses import replace

import bpy
import numpy as np
import pytest
from node_cases import set_cycles
from whitted.export.material import convert_material
from whitted.sync.frame import sync_frame
from whitted_tools.render import render_exr
from whitted_tools.scenes import (
    add_object,
    cube_mesh,
    facing,
    mesh_from_faces,
    uses_node_tree_always,
)


def _material(name, density=None, surface=False):
    """A material whose output has a Principled Volume of `density` (None: no volume) and,
    with `surface`, a Diffuse BSDF as its surface shader."""
    material = bpy.data.materials.new(name)
    if not uses_node_tree_always():
        material.use_nodes = True
    tree = material.node_tree
    for node in [n for n in tree.nodes if n.bl_idname != "ShaderNodeOutputMaterial"]:
        tree.nodes.remove(node)
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    if density is not None:
        volume = tree.nodes.new("ShaderNodeVolumePrincipled")
        volume.inputs["Density"].default_value = density
        tree.links.new(volume.outputs[0], output.inputs["Volume"])
    if surface:
        diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
        tree.links.new(diffuse.outputs[0], output.inputs["Surface"])
    return material


def _stage(scene, inside):
    """A 12 x 12 floor (the default material) under a spot lamp, no world, and a camera
    outside the fog box's place or inside it."""
    scene.render.resolution_x, scene.render.resolution_y = 32, 24
    scene.whitted.aa_samples = 1
    corners = np.array([(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], dtype=np.float32)
    floor = mesh_from_faces("Floor", corners, [np.array([[0, 1, 2, 3]])], smooth=False)
    add_object(scene, "Floor", floor)
    lamp = bpy.data.lights.new("Spot", "SPOT")
    lamp.energy, lamp.spot_size, lamp.shadow_soft_size = 800.0, 1.0, 0.0
    add_object(scene, "Spot", lamp, location=(0.0, 0.0, 5.0)).rotation_euler = facing((0, 0, -1))
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"))
    scene.camera = camera
    if inside:
        camera.location, camera.rotation_euler = (0.0, -0.6, 2.0), facing((0.0, 0.8, -1.0))
    else:
        camera.location, camera.rotation_euler = (0.0, -7.0, 3.0), facing((0.0, 7.0, -2.5))
    return scene


def _fog_box(scene, density=0.08):
    cube = add_object(scene, "Fog Box", cube_mesh("Fog Box", 2.0), location=(0.0, 0.0, 1.5))
    cube.data.materials.append(_material("Fog", density))
    return cube


@pytest.mark.parametrize("inside", [False, True], ids=["camera outside", "camera inside"])
def test_a_fog_box_shows_what_is_behind_it(empty_scene, render_pixels, inside):
    # The box stands between the camera and the floor and between the lamp and the floor:
    # camera rays and shadow feelers cross it.
    # Its volume of density 0: its bounds alone (test_volume.py renders the fog).
    scene = _stage(empty_scene, inside)
    without = render_pixels(scene).copy()
    _fog_box(scene, density=0.0)
    with_box = render_pixels(scene)
    assert without[..., :3].max() > 0.1  # the lit floor shows
    # Equal up to float rounding: 4e-7 at most was seen in Blender 3.4 (tests/native's
    # no_surface_test finds the native pixels equal to the bit).
    np.testing.assert_allclose(with_box, without, rtol=1e-5, atol=1e-6)


def test_a_constant_volume_is_rendered_and_not_reported(empty_scene, native):
    _fog_box(_stage(empty_scene, inside=False))
    warnings = sync_frame(bpy.context.evaluated_depsgraph_get(), native).warnings
    assert not [w for w in warnings if "'Fog'" in w], warnings


def test_a_surface_beside_a_volume_renders_as_before(empty_scene, warnings):
    # Cycles 3.4 and 5.0: the surface of a material with both outputs shows as without the
    # volume (the medium it holds fills only what its refraction enters).
    data = convert_material(_material("Both", density=0.08, surface=True), warnings).data
    alone = convert_material(_material("Surface", surface=True), []).data
    # Principled Volume's Color 0.5 by default: sigma_s = 0.5 * 0.08.
    assert data.surface and data.volume_scattering == pytest.approx((0.04, 0.04, 0.04))
    assert (
        replace(
            data,
            volume_absorption=alone.volume_absorption,
            volume_scattering=alone.volume_scattering,
        )
        == alone
    )
    assert warnings == []


def test_an_output_with_nothing_linked_is_still_black(empty_scene, warnings):
    # Cycles 3.4 and 5.0 draw such a mesh opaque black, casting its shadow.
    data = convert_material(_material("Nothing"), warnings).data
    assert data.surface and data.diffuse == (0.0, 0.0, 0.0)
    assert warnings == [
        "Whitted: material 'Nothing' has no surface shader; it renders black, as in Cycles"
    ]


def test_as_cycles_renders_the_box_without_its_volume(empty_scene, tmp_path, native):
    # The fog box of density 0 (its bounds alone) changes Cycles' image no more than its
    # sampling noise, and Whitted's not at all: Whitted stands to Cycles as without it.
    # (Whitted's spot-lit floor is Cycles' to 1% in Blender 3.4; 5.0's differs by about 6%,
    # with the box or without: the floor has no material, which Cycles 5.0 shades as its
    # default Principled BSDF and Whitted as a diffuse 0.8, Cycles' default to 4.2.)
    scene = _stage(empty_scene, inside=False)
    set_cycles(scene)

    def both(name):
        cycles = render_exr(scene, tmp_path / f"{name}_cycles.exr", engine="CYCLES")
        whitted = render_exr(scene, tmp_path / f"{name}_whitted.exr", engine="WHITTED")
        return cycles[..., :3], whitted[..., :3]

    cycles_without, whitted_without = both("without")
    _fog_box(scene, density=0.0)
    cycles_with, whitted_with = both("with")
    lit = cycles_without.mean(axis=-1) > 0.05
    assert lit.mean() > 0.2
    np.testing.assert_allclose(cycles_with, cycles_without, rtol=1e-3, atol=1e-3)
    np.testing.assert_allclose(whitted_with, whitted_without, rtol=1e-5, atol=1e-6)
    error = np.abs(whitted_with[lit] / cycles_with[lit] - 1.0)
    print(f"\nfog box: median |Whitted / Cycles - 1| {np.median(error):.4f}, max {error.max():.4f}")
    if bpy.app.version < (4, 0, 0):
        assert np.median(error) < 0.01
