"""Normals and tangents against Cycles (tests/blender/node_cases_surface.py): the
Texture Coordinate Normal (object space), the Bump node's and the Displacement's
normal, the Tangent node's and the Geometry node's radial tangents, rendered by Whitted
and by Cycles as an emission colour."""

import numpy as np
import pytest
from node_cases import render, set_cycles
from node_cases_surface import CASES, build_surface_scene
from whitted_tools.material_scenes import grey_world, side_camera, sphere_under_sun

# float32 differences of heights a few thousandths apart (the Bump's offsets).
BOUND = 1e-3


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_normal_matches_cycles(case, empty_scene, tmp_path, native):
    build_surface_scene(empty_scene, case)
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), case.name)
    whitted = render(empty_scene, "WHITTED", str(tmp_path), case.name)
    covered = cycles.sum(axis=-1) > 0.0  # the tilted plane leaves the top and bottom rows
    assert covered.mean() > 0.7
    # One normal over the plane (linear heights); a bump bends it away from the plane's.
    # A radial tangent turns about the axis across the plane.
    spread = np.ptp(cycles[covered], axis=0).max()
    assert spread < 1e-4 if case.uniform else spread > 0.2
    if case.name.startswith("bump"):
        assert not np.allclose(cycles[covered][0], (0.5, 0.5, 1.0), atol=1e-2)
    error = np.abs(whitted - cycles)[covered].max()
    print(f"\n{case.name}: max |Whitted - Cycles| = {error:.2e}")
    first = (whitted[covered][0], cycles[covered][0])
    assert error <= BOUND, f"{case.name}: Whitted {first[0]}, Cycles {first[1]}"


def test_glossy_dielectric_mirrors_the_world_as_cycles(empty_scene, tmp_path, native):
    # A black Principled BSDF of roughness 0 (F0 0.04: 3.x Specular 0.5, 4.x+ IOR 1.5)
    # seen at every angle from 0 to about 80 degrees, under a grey world that lights no
    # diffuse surface: Cycles shows the world Fresnel-weighted, F(theta) * 0.5; Whitted
    # showed black (a dielectric's specular was a highlight alone).
    import bpy
    from whitted_tools.cycles_scenes import render_rgba

    scene = empty_scene
    scene.render.resolution_x = scene.render.resolution_y = 12
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    grey_world(scene, 0.5)
    material = bpy.data.materials.new("Gloss")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    bsdf.inputs["IOR"].default_value = 1.5
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(material)
    side_camera(scene, 2.0)
    set_cycles(scene)
    scene.cycles.max_bounces = scene.cycles.glossy_bounces = 1
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "gloss_cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "gloss_whitted.exr"))
    covered = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99)
    assert covered.sum() > 60
    expected, got = cycles[covered][:, :3], whitted[covered][:, :3]
    # Normal incidence reflects 4%, the rim several times more.
    assert expected.min() > 0.015 and expected.max() > 0.06
    error = np.abs(got / expected - 1.0)
    print(f"\nglossy dielectric: median |Whitted / Cycles - 1| {np.median(error):.3f}")
    assert np.median(error) < 0.03


# BSDFs whose diffuse lobe is not Lambert's, as (id, node, inputs): a rough Principled
# (3.x: Burley's lobe and its retro-reflection; 4.x+: Lambert's), a sharp glossy
# dielectric over a diffuse base (3.x adds the specular layer on top; 4.x+ layers it,
# taking its Fresnel share from the base), and rough Diffuse BSDFs (Oren-Nayar).
UNDER_SUN = [
    ("principled_rough", "ShaderNodeBsdfPrincipled", {"Roughness": 1.0, "Specular": 0.0}),
    ("principled_half", "ShaderNodeBsdfPrincipled", {"Roughness": 0.6, "Specular": 0.0}),
    ("principled_glossy", "ShaderNodeBsdfPrincipled", {"Roughness": 0.0, "Specular": 0.5}),
    # 4.3+ only: Oren-Nayar's lobe under the Principled's dielectric layer.
    (
        "principled_diffuse_roughness",
        "ShaderNodeBsdfPrincipled",
        {"Roughness": 1.0, "Specular": 0.0, "Diffuse Roughness": 0.8},
    ),
    ("diffuse_rough", "ShaderNodeBsdfDiffuse", {"Roughness": 1.0}),
    ("diffuse_half", "ShaderNodeBsdfDiffuse", {"Roughness": 0.5}),
]


@pytest.mark.parametrize("node, inputs", [c[1:] for c in UNDER_SUN], ids=[c[0] for c in UNDER_SUN])
def test_diffuse_lobe_under_a_sun_as_cycles(node, inputs, empty_scene, tmp_path, native):
    # A smooth sphere under a sun seen along a side, black world: every pixel's light
    # and view angles differ. Cycles' direct light is deterministic here (a sun of angle
    # 0, a centre-point filter), so each pixel is compared with its own.
    import bpy

    scene = empty_scene
    material = bpy.data.materials.new("Under a sun")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    bsdf = tree.nodes.new(node)
    colour = "Base Color" if "Base Color" in bsdf.inputs else "Color"
    bsdf.inputs[colour].default_value = (0.5, 0.4, 0.3, 1.0)
    for name, value in inputs.items():
        if name == "Specular" and name not in bsdf.inputs:
            name = "Specular IOR Level"  # 4.0 renamed it
        if name not in bsdf.inputs:
            pytest.skip(f"this Blender's {bsdf.name} has no {name}")
        bsdf.inputs[name].default_value = value
    tree.links.new(bsdf.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    _under_a_sun_as_cycles(scene, material, tmp_path, f"{node} {inputs}")


def test_an_object_without_a_material_renders_as_in_cycles(empty_scene, tmp_path, native):
    # Cycles renders an object without a material with its default surface: a Diffuse
    # BSDF of 0.8 up to 4.5, a new material's Principled BSDF from 5.0 (its highlight
    # included; export/material.py's default_material).
    _under_a_sun_as_cycles(empty_scene, None, tmp_path, "no material")


def _under_a_sun_as_cycles(scene, material, tmp_path, name):
    """A sphere of `material` under a sun (sphere_under_sun), each lit pixel of Whitted's
    within 1% of Cycles' (2nd to 98th percentile)."""
    from whitted_tools.cycles_scenes import render_rgba, set_cycles_direct_light

    sphere_under_sun(scene, material, 48, segments=96, rings=48)
    set_cycles_direct_light(scene, samples=4)
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 1
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "under_sun_cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "under_sun_whitted.exr"))
    lit = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99) & (cycles[..., 0] > 0.01)
    assert lit.sum() > 400
    ratio = whitted[lit][:, :3] / cycles[lit][:, :3]
    low, high = np.percentile(ratio, [2, 98])
    print(f"\n{name}: Whitted / Cycles {low:.4f}..{high:.4f}")
    assert low > 0.99 and high < 1.01


@pytest.mark.parametrize(
    "normalised",
    [
        True,
        pytest.param(
            False,
            marks=pytest.mark.xfail(
                __import__("bpy").app.version < (4, 0, 0),
                strict=True,
                reason="Cycles 3.x does not normalise a linked Normal: its lobes scale by "
                "the vector's length (0.64..1.47 here); Whitted normalises, as 4.x+",
            ),
        ),
    ],
)
def test_any_vector_into_normal_shades_as_in_cycles(normalised, empty_scene, tmp_path, native):
    # A Diffuse BSDF whose Normal is a vector of the graph's own (the Geometry normal
    # leaned towards +X, normalised in the graph or not): Cycles shades with it. Whitted
    # read only a Normal Map, a Bump or a Bevel there, and ignored this link.
    import bpy

    material = bpy.data.materials.new("Leaning")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (0.5, 0.4, 0.3, 1.0)
    lean = tree.nodes.new("ShaderNodeVectorMath")
    lean.operation = "ADD"
    lean.inputs[1].default_value = (0.6, 0.0, 0.2)
    tree.links.new(tree.nodes.new("ShaderNodeNewGeometry").outputs["Normal"], lean.inputs[0])
    normal = lean.outputs[0]
    if normalised:
        unit = tree.nodes.new("ShaderNodeVectorMath")
        unit.operation = "NORMALIZE"
        tree.links.new(normal, unit.inputs[0])
        normal = unit.outputs[0]
    tree.links.new(normal, bsdf.inputs["Normal"])
    tree.links.new(bsdf.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    _under_a_sun_as_cycles(empty_scene, material, tmp_path, f"a leaning normal, {normalised}")
