"""True displacement against Cycles: a material's Displacement Only and Displacement and
Bump methods move the mesh's vertices (Cycles without adaptive subdivision), each vertex
by the displacement its program gives there (sync/displace.py, native displace), and
Displacement Only gives the moved faces' vertices new normals. A finely divided plane
displaced by a Noise Texture, lit by a grazing sun, seen from above (its shading) and
edge-on (its silhouette), rendered by Cycles and by Whitted in the same Blender."""

import json

import bpy
import numpy as np
import pytest
from whitted_tools.cycles_scenes import (
    render_rgba,
    set_cycles_direct_light,
    set_whitted_direct_light,
)
from whitted_tools.material_scenes import (
    add_sun,
    dark_stage,
    lambert_material,
    side_camera,
    top_camera,
)
from whitted_tools.metrics import luminance, subject_figures

SIZE = 96
CUTS = 64  # the grid's subdivisions along each side


def displaced_plane(scene, method, space="OBJECT", scale=0.25, object_scale=1.0):
    """A smooth 2 m grid of CUTS x CUTS faces at the origin whose Lambert material's
    Displacement is a Displacement node of `space` and `scale` (Midlevel 0.5) fed a Noise
    Texture (its default Generated coordinates), under displacement method `method`,
    lit by a sun 20 degrees above the horizon; the object scaled by `object_scale`."""
    dark_stage(scene, SIZE, SIZE)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=CUTS, y_subdivisions=CUTS, size=2.0)
    plane = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    plane.scale = (object_scale,) * 3
    material = lambert_material("Displaced", 0.8)
    settings = material if hasattr(material, "displacement_method") else material.cycles
    settings.displacement_method = method
    tree = material.node_tree
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 3.0
    noise.inputs["Detail"].default_value = 1.0
    displacement = tree.nodes.new("ShaderNodeDisplacement")
    displacement.space = space
    displacement.inputs["Scale"].default_value = scale
    displacement.inputs["Midlevel"].default_value = 0.5
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(noise.outputs["Fac"], displacement.inputs["Height"])
    tree.links.new(displacement.outputs["Displacement"], output.inputs["Displacement"])
    plane.data.materials.append(material)
    add_sun(scene, rotation=(70.0, 0.0, 30.0), strength=3.0)
    set_cycles_direct_light(scene, samples=4)
    set_whitted_direct_light(scene)
    return plane


def both_engines(scene, tmp_path, name):
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / f"{name}_cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / f"{name}_whitted.exr"))
    return whitted, cycles


def shading_figures(whitted, cycles, label):
    """(SSIM, median per-pixel luminance ratio, summed luminance ratio) of the two
    renders from above, printed."""
    value, median = subject_figures(whitted, cycles)
    summed = luminance(whitted[..., :3]).sum() / luminance(cycles[..., :3]).sum()
    print(f"\n{label}: SSIM {value:.3f}, median ratio {median:.3f}, summed ratio {summed:.3f}")
    return value, median, summed


@pytest.mark.parametrize(
    "method",
    [
        "DISPLACEMENT",
        # Measured in 3.4: SSIM 0.955, median ratio 0.976, summed 0.949 (the bump over
        # the moved surface is not yet Cycles 3.x's; not investigated). bpy 5.0: SSIM
        # 0.999, ratios 0.993. Blender 4.x not measured (the smoke tier does not run this).
        pytest.param(
            "BOTH",
            marks=pytest.mark.xfail(
                bpy.app.version < (5, 0, 0), strict=True, reason="3.4: summed ratio 0.949"
            ),
        ),
    ],
)
def test_displaced_plane_shades_as_cycles(method, empty_scene, tmp_path, native):
    displaced_plane(empty_scene, method)
    top_camera(empty_scene, 1.8)
    whitted, cycles = both_engines(empty_scene, tmp_path, method.lower())
    lum_c = luminance(cycles[..., :3])
    # The sun grazes the relief: slopes towards it lit far more than slopes away
    # (a flat plane, as Whitted rendered Displacement Only before, is one grey): measured
    # 1.98 times in 3.4.
    assert np.percentile(lum_c, 95) > 1.5 * np.percentile(lum_c, 20)
    value, median, summed = shading_figures(whitted, cycles, method)
    # Cycles at a pixel's centre under a sun of no size is exact: what is left is each
    # engine's shadow terminator on the relief's slopes.
    assert value > 0.9
    assert abs(median - 1.0) < 0.03
    assert abs(summed - 1.0) < 0.05
    error = np.abs(luminance(whitted[..., :3]) - lum_c)
    assert np.median(error) < 0.02 * np.median(lum_c)
    stats = json.loads(empty_scene.whitted.last_stats)
    entries = [e for e in stats["effects"] if e["name"] == "displacement"]
    vertices = (CUTS + 1) ** 2
    assert entries == [
        {"name": "displacement", "on": True, "why": f"displaced {vertices:,} vertices of 'Grid'"}
    ], stats["effects"]


def silhouette(scene, tmp_path, name):
    """The columns' covered heights (pixels) of the plane seen edge-on, Whitted's and
    Cycles'."""
    side_camera(scene, 2.4)
    whitted, cycles = both_engines(scene, tmp_path, name)
    return (whitted[..., 3] > 0.5).sum(axis=0), (cycles[..., 3] > 0.5).sum(axis=0)


def test_the_silhouette_moves_as_cycles(empty_scene, tmp_path, native):
    displaced_plane(empty_scene, "DISPLACEMENT", scale=0.4)
    whitted, cycles = silhouette(empty_scene, tmp_path, "edge")
    # A flat plane seen edge-on covers no pixel; the displaced one rises and sinks by up
    # to 0.2 m: a band several pixels tall (40 pixels a metre).
    assert np.median(cycles) >= 3
    print(f"\nedge-on: {cycles.sum()} pixels covered in Cycles, {whitted.sum()} in Whitted")
    # Each column's height within a pixel of Cycles' (the edges of the band fall across
    # pixels as the two engines' rays meet the same triangles).
    assert np.abs(whitted.astype(int) - cycles).max() <= 1
    assert abs(whitted.sum() / cycles.sum() - 1.0) < 0.05


def test_space_on_a_scaled_object_as_cycles(empty_scene, tmp_path, native):
    # A plane scaled 1.5 times: Object space scales the displacement with it (Cycles
    # carries the normal to object space and back), World space does not.
    plane = displaced_plane(empty_scene, "DISPLACEMENT", scale=0.3, object_scale=1.5)
    node = plane.active_material.node_tree.nodes["Displacement"]
    covered = {}
    for space in ("OBJECT", "WORLD"):
        node.space = space
        whitted, cycles = silhouette(empty_scene, tmp_path, space.lower())
        print(f"\n{space}: {cycles.sum()} pixels covered in Cycles, {whitted.sum()} in Whitted")
        assert np.abs(whitted.astype(int) - cycles).max() <= 1
        assert abs(whitted.sum() / cycles.sum() - 1.0) < 0.05
        covered[space] = cycles.sum()
    # The band edge-on is about 1.5 times as tall in Object space (a pixel of each
    # column's edges aside).
    assert 1.3 < covered["OBJECT"] / covered["WORLD"] < 1.7


def test_adaptive_subdivision_is_said_not_rendered(empty_scene, native):
    # Cycles' adaptive subdivision (microdisplacement) dices the mesh at render time:
    # Whitted displaces the mesh's own vertices and says so, only where it is asked for.
    from test_sync import full_export

    plane = displaced_plane(empty_scene, "DISPLACEMENT")
    bpy.context.view_layer.update()
    assert not [w for w in full_export(native, empty_scene).warnings if "adaptive" in w]
    if bpy.app.version >= (4, 5, 0):
        modifier = plane.modifiers.new("Subdivision", "SUBSURF")
        modifier.use_adaptive_subdivision = True
    else:
        empty_scene.cycles.feature_set = "EXPERIMENTAL"
        plane.cycles.use_adaptive_subdivision = True
    bpy.context.view_layer.update()
    assert [w for w in full_export(native, empty_scene).warnings if "adaptive" in w] == [
        "Whitted: object 'Grid': adaptive subdivision (microdisplacement) is not rendered; "
        "its vertices are displaced at the mesh's own resolution"
    ]
