"""Glossy reflection in the Blender local model (the GGX lobe, native
scene/microfacet.h) against Cycles: a lamp's highlight on a rough glossy surface pixel
by pixel, and a rough metal reflecting its surroundings; the Lecture model keeps the
seed's mirror and Phong highlight."""

import bpy
import numpy as np
import pytest
from whitted_tools.cycles_scenes import render_rgba, set_cycles_direct_light
from whitted_tools.material_scenes import (
    empty_node_material,
    glass_bsdf_material,
    principled_sphere_material,
    sphere_under_sun,
)


def glossy_material(name, colour, roughness, distribution):
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    bsdf = tree.nodes.new("ShaderNodeBsdfGlossy")
    bsdf.distribution = distribution
    bsdf.inputs["Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    tree.links.new(bsdf.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    return material


def render_both(scene, tmp_path):
    """(Cycles' render, Whitted's) of `scene`, float32 RGBA."""
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    return cycles, whitted


def lit_ratio(cycles, whitted, darkest):
    """Whitted / Cycles (red channel) over the pixels both cover and Cycles shows above
    `darkest`."""
    lit = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99) & (cycles[..., 0] > darkest)
    return lit, whitted[lit][:, 0] / cycles[lit][:, 0]


def lobe_under_sun(scene, material, tmp_path, samples=1):
    """A unit sphere of `material` under a sun (sphere_under_sun), Cycles' direct light at
    `samples` samples against Whitted's one sample a pixel: (Cycles' render, the pixels lit
    in both, Whitted / Cycles there)."""
    sphere_under_sun(scene, material, 48, segments=96, rings=48)
    set_cycles_direct_light(scene, samples=samples)
    # No Russian roulette on faint light samples (3.x's default threshold 0.01 turns
    # them into 0 or 0.01).
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 1  # glossy rays see the black world: nothing
    cycles, whitted = render_both(scene, tmp_path)
    lit, ratio = lit_ratio(cycles, whitted, 1e-3)
    assert lit.sum() > 300
    return cycles, whitted, lit, ratio


LOBES = [(r, d) for r in (0.3, 0.6, 1.0) for d in ("GGX", "MULTI_GGX")]


@pytest.mark.parametrize(("roughness", "distribution"), LOBES)
def test_a_suns_highlight_on_a_glossy_sphere_is_cycles(
    roughness, distribution, empty_scene, tmp_path, native
):
    # A smooth sphere under a sun seen along a side, black world: every pixel has its own
    # light and view angles, and Cycles' direct light from a sun of angle 0 is exact (no
    # ray can hit the sun), so each pixel is compared with its own. Before the glossy lobe
    # the highlight was a Phong lobe clamped at exponent 1 above roughness 0.76.
    material = glossy_material("Brushed", (0.9, 0.6, 0.3), roughness, distribution)
    # Cycles 3.x evaluates Multiscatter GGX by a random walk: one per sample, so average.
    stochastic = distribution == "MULTI_GGX" and bpy.app.version < (4, 0, 0)
    samples = 256 if stochastic else 1
    cycles, whitted, lit, ratio = lobe_under_sun(empty_scene, material, tmp_path, samples)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    energy = whitted[lit][:, 0].sum() / cycles[lit][:, 0].sum()
    print(
        f"\nglossy {distribution} {roughness}: Whitted / Cycles {low:.4f} {median:.4f} "
        f"{high:.4f} (5%, median, 95%), summed {energy:.4f}"
    )
    if stochastic:
        # Whitted scales the single-scattering lobe by the energy it loses (Cycles 4.0
        # on does so); 3.x's random walk spreads that energy in another shape. Only the
        # sum is compared (docs/SUPPORT.md gives the figures).
        assert 0.85 < energy < 1.15
        return
    assert 0.99 < median < 1.01
    assert low > 0.98 and high < 1.02


def metal_reflecting_surroundings(scene, material):
    """A rough sphere of `material` on a checker-free grey floor lit by a sun, under a
    uniform grey sky that lights no diffuse surface; the camera sees the sphere and
    what its lobe reflects: the floor below, the sky above."""
    from whitted_tools.material_scenes import add_camera, add_floor, add_sun, grey_world

    scene.render.resolution_x = scene.render.resolution_y = 48
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    grey_world(scene, 0.5)
    add_floor(scene, size=12.0, albedo=0.6)
    smooth_sphere_at(material)
    add_camera(scene, (0.0, -4.0, 1.4), (0.0, 0.0, 1.0), lens=70.0)
    add_sun(scene, rotation=(40.0, 0.0, 30.0), strength=2.0)
    scene.whitted.ambient_strength = 0.0  # the sky lights no diffuse surface, as in Cycles


def metal_figures(scene, material, tmp_path):
    """(SSIM, luminance ratio) of Whitted against Cycles over the sphere of
    metal_reflecting_surroundings: Cycles one glossy bounce at 512 samples (its noise is
    what the tests' bounds leave room for), Whitted the Final preset's glossy rays."""
    from whitted_tools.metrics import subject_figures

    metal_reflecting_surroundings(scene, material)
    set_cycles_direct_light(scene, samples=512)
    scene.cycles.max_bounces = scene.cycles.glossy_bounces = 1
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_samples = 3
    scene.whitted.glossy_samples = 6
    scene.whitted.max_depth = 1
    cycles, whitted = render_both(scene, tmp_path)
    return subject_figures(whitted, cycles, sphere_disc(cycles, whitted))


def sphere_disc(cycles, whitted):
    """The pixels of the sphere in the middle of the frame that both renders cover: the
    floor covers the rest, so the disc the sphere projects to (radius 0.3 of the width)."""
    ball = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99)
    height, width = ball.shape
    ys, xs = np.mgrid[0:height, 0:width]
    centre = (width / 2.0 - 0.5, height / 2.0 - 0.5)
    return ball & ((xs - centre[0]) ** 2 + (ys - centre[1]) ** 2 < (0.3 * width) ** 2)


def smooth_sphere_at(material):
    from whitted_tools.material_scenes import smooth_sphere

    return smooth_sphere("Ball", (0.0, 0.0, 1.0), 1.0, material, segments=64, rings=32)


METALS = [("glossy", 0.15), ("glossy", 0.4), ("principled", 0.4), ("glossy", 1.0)]


@pytest.mark.parametrize(("kind", "roughness"), METALS)
def test_a_rough_metal_reflects_its_surroundings_as_cycles(
    kind, roughness, empty_scene, tmp_path, native
):
    # Before glossy rays a metal of roughness 0.4 was black but for its highlights, and
    # one of 0.15 a sharp mirror. Cycles: one glossy bounce, many samples (its noise is
    # what the bound leaves room for); Whitted: the Final preset's glossy rays.
    scene = empty_scene
    colour = (1.0, 0.78, 0.34)  # gold
    if kind == "glossy":
        material = glossy_material("Gold", colour, roughness, "GGX")
    else:
        material = bpy.data.materials.new("Gold")
        if bpy.app.version < (5, 0, 0):
            material.use_nodes = True
        bsdf = material.node_tree.nodes["Principled BSDF"]
        bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
        bsdf.inputs["Metallic"].default_value = 1.0
        bsdf.inputs["Roughness"].default_value = roughness
    value, ratio = metal_figures(scene, material, tmp_path)
    print(f"\n{kind} metal {roughness}: SSIM {value:.4f}, luminance ratio {ratio:.4f}")
    # Measured: 0.995 to 1.010 in 3.4 and 5.2 (the Principled metal's rim, brightened
    # towards white by Cycles' Fresnel, is a few pixels of the disc); SSIM 0.94-0.97,
    # Cycles' own noise at 512 samples most of the difference.
    assert abs(ratio - 1.0) < 0.05
    assert value > 0.9


def test_a_scene_without_rough_reflection_renders_the_same_in_both_models(
    demo_scene_module, empty_scene, render_pixels
):
    # What calls for no glossy reflection renders as the seed does: the Blender model
    # changes only rough reflections and the world's light. The demo's mirror, glass and
    # checker floor have none; its blue cube and green cylinder have the Principled
    # BSDF's default rough specular layer, taken off here; its sky is set to light no
    # diffuse surface (then neither model has an ambient term or a world light).
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.world.cycles_visibility.diffuse = False
    for name in ("Diffuse Blue", "Diffuse Green"):
        bsdf = bpy.data.materials[name].node_tree.nodes["Principled BSDF"]
        level = "Specular IOR Level" if "Specular IOR Level" in bsdf.inputs else "Specular"
        bsdf.inputs[level].default_value = 0.0
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.render.resolution_percentage = 100
    blender_model = render_pixels(scene)
    scene.whitted.local_model = "LECTURE"
    lecture = render_pixels(scene)
    assert np.array_equal(blender_model, lecture)


def test_the_lecture_model_keeps_the_seeds_mirror_and_phong_highlight(
    empty_scene, render_pixels, tmp_path, monkeypatch
):
    # A rough metal: glossy rays in the Blender model, none in the Lecture model, whose
    # image is the Phong highlight and the faded mirror of before.
    import json

    material = glossy_material("Gold", (1.0, 0.78, 0.34), 0.4, "GGX")
    metal_reflecting_surroundings(empty_scene, material)
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    glossy = render_pixels(empty_scene)
    glossy_rays = json.loads(stats_path.read_text())["rays"]["glossy"]
    empty_scene.whitted.local_model = "LECTURE"
    lecture = render_pixels(empty_scene)
    lecture_rays = json.loads(stats_path.read_text())["rays"]["glossy"]
    assert glossy_rays > 0 and lecture_rays == 0
    assert not np.array_equal(glossy, lecture)


@pytest.mark.parametrize("roughness", [0.2, 0.5])
def test_rough_plastic_under_a_sun_as_cycles(roughness, empty_scene, tmp_path, native):
    # The Principled BSDF's dielectric specular layer over its diffuse base, rough: in
    # the Blender model a GGX lobe weighted by the Fresnel factor at the view, on top.
    scene = empty_scene
    sphere_under_sun(
        scene, principled_sphere_material("Plastic", (0.5, 0.4, 0.3), roughness), 48, 96, 48
    )
    set_cycles_direct_light(scene, samples=1)
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 1
    cycles, whitted = render_both(scene, tmp_path)
    lit, ratio = lit_ratio(cycles, whitted, 1e-2)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    energy = whitted[lit][:, 0].sum() / cycles[lit][:, 0].sum()
    print(
        f"\nplastic {roughness}: Whitted / Cycles {low:.4f} {median:.4f} {high:.4f}, "
        f"summed {energy:.4f}"
    )
    assert 0.95 < energy < 1.05


@pytest.mark.parametrize("roughness", [0.3, 0.5])
def test_a_clear_coats_highlight_under_a_sun_is_cycles(roughness, empty_scene, tmp_path, native):
    # A black Principled without specular under a full coat (3.x Clearcoat, 4.x+ Coat
    # Weight) of `roughness`: the sun's highlight is the coat's lobe alone, which Cycles
    # evaluates at the light sample (its rays cannot find the sun's tiny disc). 3.x:
    # Cycles 3.x's GTR1 clearcoat (coat_model GTR1), 1.000 of Cycles 3.4 per pixel (as a
    # GGX lobe the median pixel was 0.12 and 0.43 of Cycles'); 4.x+: a GGX dielectric
    # layer, bpy 5.0 summed 0.999 and 0.991.
    material = principled_sphere_material("Coated", (0.0, 0.0, 0.0), 0.5, specular=0.0)
    bsdf = material.node_tree.nodes["Principled BSDF"]
    weight = "Clearcoat" if "Clearcoat" in bsdf.inputs else "Coat Weight"
    bsdf.inputs[weight].default_value = 1.0
    bsdf.inputs[weight.replace("Weight", "").strip() + " Roughness"].default_value = roughness
    cycles, whitted, lit, ratio = lobe_under_sun(empty_scene, material, tmp_path)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    energy = whitted[lit][:, 0].sum() / cycles[lit][:, 0].sum()
    print(
        f"\ncoat {roughness}: Whitted / Cycles {low:.4f} {median:.4f} {high:.4f}, "
        f"summed {energy:.4f}, {int(lit.sum())} px"
    )
    assert 0.98 < energy < 1.02
    assert 0.97 < median < 1.03


@pytest.mark.parametrize("roughness", [0.2, 0.5])
def test_rough_black_plastic_reflects_the_sky_as_cycles(roughness, empty_scene, tmp_path, native):
    # Black plastic under a grey sky that lights nothing diffuse: all it shows is its
    # specular layer's reflection of the sky (shadowed sides of real glTF files were
    # black where Cycles shows this).
    from whitted_tools.material_scenes import grey_world, side_camera, smooth_sphere

    scene = empty_scene
    scene.render.resolution_x = scene.render.resolution_y = 32
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    grey_world(scene, 0.5)
    smooth_sphere(
        "Ball",
        (0.0, 0.0, 0.0),
        1.0,
        principled_sphere_material("Black", (0.0, 0.0, 0.0), roughness),
    )
    side_camera(scene, 2.2)
    set_cycles_direct_light(scene, samples=256)
    scene.cycles.max_bounces = scene.cycles.glossy_bounces = 1
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_samples = 2
    scene.whitted.glossy_samples = 6
    scene.whitted.max_depth = 1
    scene.whitted.ambient_strength = 0.0
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    ball = (cycles[..., 3] > 0.99) & (whitted[..., 3] > 0.99)
    energy = whitted[ball][:, 0].sum() / cycles[ball][:, 0].sum()
    centre = whitted[16, 16, 0] / cycles[16, 16, 0]
    print(f"\nblack plastic {roughness}: summed Whitted / Cycles {energy:.4f}, centre {centre:.4f}")
    assert 0.9 < energy < 1.1


@pytest.mark.parametrize("roughness", [0.1, 0.25])
def test_frosted_glass_as_cycles(roughness, empty_scene, tmp_path, native):
    # A Glass BSDF sphere, rough, on the sunlit floor under the grey sky: before rough
    # transmission it rendered as clear glass.
    from whitted_tools.metrics import subject_figures

    scene = empty_scene
    material = glass_bsdf_material("Frosted", roughness)
    metal_reflecting_surroundings(scene, material)
    set_cycles_direct_light(scene, samples=512)
    cycles_settings = scene.cycles
    cycles_settings.max_bounces = 8
    cycles_settings.glossy_bounces = cycles_settings.transmission_bounces = 8
    cycles_settings.light_sampling_threshold = 0.0
    cycles_settings.caustics_reflective = cycles_settings.caustics_refractive = False
    scene.whitted.aa_samples = 3
    scene.whitted.glossy_samples = 4
    scene.whitted.max_depth = 8
    cycles, whitted = render_both(scene, tmp_path)
    ball = sphere_disc(cycles, whitted)
    height, width = ball.shape
    value, ratio = subject_figures(whitted, cycles, ball)
    # The Lecture model renders it as clear glass, as Whitted did before. Compared after
    # a 3 x 3 box blur (Cycles' noise in rough glass at 512 samples is most of SSIM's
    # difference): the mean absolute difference over the sphere.
    scene.whitted.local_model = "LECTURE"
    clear = render_rgba(scene, "WHITTED", str(tmp_path / "clear.exr"))

    def blurred_error(image):
        def blur(a):
            padded = np.pad(a[..., :3], ((1, 1), (1, 1), (0, 0)), mode="edge")
            return (
                sum(padded[dy : dy + height, dx : dx + width] for dy in range(3) for dx in range(3))
                / 9.0
            )

        return float(np.abs(blur(image) - blur(cycles))[ball].mean())

    frosted_error, clear_error = blurred_error(whitted), blurred_error(clear)
    print(
        f"\nfrosted glass {roughness}: SSIM {value:.4f}, luminance ratio {ratio:.4f}, blurred "
        f"|difference| {frosted_error:.4f} (as clear glass {clear_error:.4f})"
    )
    assert abs(ratio - 1.0) < 0.1
    assert value > 0.84
    assert frosted_error < clear_error


def velvet_node(tree, sigma, color):
    """Blender 3.x's Velvet BSDF or 4.x's Sheen BSDF (Ashikhmin) of `sigma` and `color`."""
    if bpy.app.version < (4, 0, 0):
        velvet = tree.nodes.new("ShaderNodeBsdfVelvet")
        velvet.inputs["Sigma"].default_value = sigma
    else:
        velvet = tree.nodes.new("ShaderNodeBsdfSheen")
        velvet.distribution = "ASHIKHMIN"
        velvet.inputs["Roughness"].default_value = sigma
    velvet.inputs["Color"].default_value = (*color, 1.0)
    return velvet


@pytest.mark.parametrize("sigma", [0.3, 1.0])
def test_velvet_under_a_sun_as_cycles(sigma, empty_scene, tmp_path, native):
    # Blender 3.x's Velvet BSDF, 4.x's Sheen BSDF (Ashikhmin): Ashikhmin's velvet lobe of
    # its sigma; it was read as Lambert (up to 1.9x too bright) with the sigma dropped.
    material = empty_node_material("Velvet")
    tree = material.node_tree
    velvet = velvet_node(tree, sigma, (0.6, 0.2, 0.3))
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(velvet.outputs[0], output.inputs["Surface"])
    _, _, _, ratio = lobe_under_sun(empty_scene, material, tmp_path)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    print(f"\nvelvet {sigma}: Whitted / Cycles {low:.4f} {median:.4f} {high:.4f}")
    assert 0.99 < median < 1.01
    assert low > 0.97 and high < 1.03


def test_a_principled_plus_velvet_keeps_both_lobes_as_cycles(empty_scene, tmp_path, native):
    # Add Shader of a Principled BSDF (no specular: its diffuse lobe, 3.x's Burley) and a
    # velvet: Cycles sums the two closures, each of its own shape. Whitted once folded
    # them into one diffuse lobe of the first shape, the velvet colour lit as a diffuse
    # one (a third-party cloth file rendered 1.21 of Cycles).
    material = empty_node_material("Cloth")
    tree = material.node_tree
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (0.5, 0.3, 0.2, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.8
    specular = "Specular" if bpy.app.version < (4, 0, 0) else "Specular IOR Level"
    bsdf.inputs[specular].default_value = 0.0
    velvet = velvet_node(tree, 0.5, (0.2, 0.3, 0.6))
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(bsdf.outputs[0], add.inputs[0])
    tree.links.new(velvet.outputs[0], add.inputs[1])
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(add.outputs[0], output.inputs["Surface"])
    cycles, whitted, lit, ratio = lobe_under_sun(empty_scene, material, tmp_path)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    energy = whitted[lit][:, :3].sum() / cycles[lit][:, :3].sum()
    print(
        f"\nprincipled + velvet: Whitted / Cycles {low:.4f} {median:.4f} {high:.4f}, "
        f"summed {energy:.4f}"
    )
    assert 0.99 < energy < 1.01
    assert 0.99 < median < 1.01
    assert low > 0.97 and high < 1.03


# Blender 4.0+'s default surface is a Principled BSDF, whose specular lobe Cycles 4.x+
# lifts alone (maybe_ensure_valid_specular_reflection); Whitted does not (docs/SUPPORT.md).
# Measured in bpy 5.0.1: 1.103 and 0.613 of Cycles' (median).
SPECULAR_LIFT = pytest.mark.xfail(
    bpy.app.version >= (4, 0, 0),
    reason="Cycles 4.x+ lifts the specular lobe's normal only: not modelled",
    strict=True,
)


def tilted_plane(scene, with_material, sun_rotation):
    """A plane whose custom normals lean away from a camera at a grazing view on its -x
    side, under a sun, black world: with a Diffuse BSDF material or with none (Cycles'
    default surface)."""
    import bmesh
    from whitted_tools.material_scenes import add_camera, add_sun, black_world

    scene.render.resolution_x, scene.render.resolution_y = 48, 32
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    black_world(scene)
    mesh = bpy.data.meshes.new("Tilted")
    built = bmesh.new()
    bmesh.ops.create_grid(built, x_segments=8, y_segments=8, size=2.0)
    built.to_mesh(mesh)
    built.free()
    if bpy.app.version < (4, 1, 0):
        mesh.use_auto_smooth = True
    lean = np.array([0.8, 0.0, 0.6])  # leaning away from a camera on the -x side
    mesh.normals_split_custom_set_from_vertices([tuple(lean)] * len(mesh.vertices))
    if with_material:
        material = bpy.data.materials.new("Matte")
        if bpy.app.version < (5, 0, 0):
            material.use_nodes = True
        tree = material.node_tree
        tree.nodes.remove(tree.nodes["Principled BSDF"])
        diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
        tree.links.new(diffuse.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
        mesh.materials.append(material)
    plane = bpy.data.objects.new("Tilted", mesh)
    scene.collection.objects.link(plane)
    add_camera(scene, (-6.0, 0.0, 0.8), (0.0, 0.0, 0.0), lens=35.0)
    add_sun(scene, rotation=sun_rotation, strength=3.0)


@pytest.mark.parametrize(
    ("with_material", "sun"),
    [
        pytest.param(True, (30.0, 0.0, 90.0), id="diffuse"),
        *(
            pytest.param(False, sun, marks=SPECULAR_LIFT, id=name)
            for name, sun in (
                ("default", (30.0, 0.0, 90.0)),
                ("default, low sun", (70.0, 0.0, 90.0)),
            )
        ),
    ],
)
def test_tilted_custom_normals_at_a_grazing_view_as_cycles(
    with_material, sun, empty_scene, tmp_path, native
):
    # Blender 3.x's Cycles turns every closure's shading normal, the interpolated one
    # too, towards the geometric normal where the view's mirror would fall below the
    # surface (ensure_valid_reflection); Whitted did so only for normals a graph
    # computes, so a plane whose custom normals lean away from a grazing view rendered
    # flat where Cycles 3.4 shows a gradient. 4.x+ lifts specular lobes only (a Diffuse
    # BSDF keeps its normal there, as Whitted does). Cycles 3.x then fades the diffuse
    # lobe of a turned normal by its bump shadowing term (Chiang et al.), and does both
    # for an object without a material too (Whitted's default material did neither:
    # 0.83 of Cycles' on a third-party file; the lift alone overshot to 1.08).
    scene = empty_scene
    tilted_plane(scene, with_material, sun)
    set_cycles_direct_light(scene, samples=1)
    scene.cycles.light_sampling_threshold = 0.0
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 0
    scene.whitted.ambient_strength = 0.0
    cycles, whitted = render_both(scene, tmp_path)
    lit, ratio = lit_ratio(cycles, whitted, 1e-3)
    assert lit.sum() > 100
    low, median, high = np.percentile(ratio, [2, 50, 98])
    energy = whitted[lit][:, 0].sum() / cycles[lit][:, 0].sum()
    print(f"\ntilted normals: Whitted / Cycles {low:.4f} {median:.4f} {high:.4f}, sum {energy:.4f}")
    assert 0.98 < median < 1.02
    assert low > 0.95 and high < 1.05


def anisotropic_material(name, kind, amount, rotation=0.0, tangent_axis=None):
    """Brushed gold: a Glossy BSDF of Anisotropy `amount` (3.x's Anisotropic BSDF, the
    same node id as 4.0+'s Glossy) or a Principled metal of Anisotropic `amount`, its
    tangent Cycles' default or a Tangent node's radial one about `tangent_axis`."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    colour = (1.0, 0.78, 0.34, 1.0)
    if kind == "glossy":
        tree.nodes.remove(tree.nodes["Principled BSDF"])
        bsdf = tree.nodes.new("ShaderNodeBsdfAnisotropic")
        bsdf.distribution = "GGX"
        bsdf.inputs["Color"].default_value = colour
        bsdf.inputs["Anisotropy"].default_value = amount
        bsdf.inputs["Rotation"].default_value = rotation
        tree.links.new(bsdf.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    else:
        bsdf = tree.nodes["Principled BSDF"]
        bsdf.distribution = "GGX"
        bsdf.inputs["Base Color"].default_value = colour
        bsdf.inputs["Metallic"].default_value = 1.0
        bsdf.inputs["Anisotropic"].default_value = amount
        bsdf.inputs["Anisotropic Rotation"].default_value = rotation
    bsdf.inputs["Roughness"].default_value = 0.35
    if tangent_axis is not None:
        tangent = tree.nodes.new("ShaderNodeTangent")
        tangent.direction_type = "RADIAL"
        tangent.axis = tangent_axis
        tree.links.new(tangent.outputs["Tangent"], bsdf.inputs["Tangent"])
    return material


ANISOTROPIC = [
    ("glossy", 0.7, 0.0, None),
    ("glossy", -0.6, 0.15, None),
    ("glossy", 0.5, 0.0, "X"),
    ("principled", 0.9, 0.0, None),
    ("principled", 0.6, 0.3, "Y"),
]


@pytest.mark.parametrize(("kind", "amount", "rotation", "axis"), ANISOTROPIC)
def test_an_anisotropic_highlight_is_cycles(
    kind, amount, rotation, axis, empty_scene, tmp_path, native
):
    # Brushed metal: the sun's highlight stretched along the tangent (radial about the
    # object's Z by default, turned by Rotation, or a Tangent node's), pixel by pixel
    # against Cycles' exact direct light. Before, the lobe was round (and warned).
    material = anisotropic_material("Brushed", kind, amount, rotation, axis)
    cycles, _, _, ratio = lobe_under_sun(empty_scene, material, tmp_path)
    low, median, high = np.percentile(ratio, [5, 50, 95])
    print(f"\nanisotropic {kind} {amount} {rotation} {axis}: {low:.4f} {median:.4f} {high:.4f}")
    assert 0.99 < median < 1.01
    assert low > 0.97 and high < 1.03
    # The round lobe of the same roughness is another highlight: the test sees the shape.
    round_lobe = anisotropic_material("Round", kind, 0.0)
    empty_scene.objects["Ball"].data.materials[0] = round_lobe
    rounded = render_rgba(empty_scene, "WHITTED", str(tmp_path / "round.exr"))
    _, round_ratio = lit_ratio(cycles, rounded, 1e-3)
    assert np.percentile(np.abs(round_ratio - 1.0), 95) > 0.2


@pytest.mark.parametrize("kind", ["glossy", "principled"])
def test_brushed_metal_reflects_its_surroundings_as_cycles(kind, empty_scene, tmp_path, native):
    # The glossy rays drawn from the anisotropic lobe (and their MIS weights against the
    # sun's feelers): the rough metal scene of the isotropic test, its lobe stretched.
    scene = empty_scene
    material = anisotropic_material("Brushed", kind, 0.8 if kind == "glossy" else 0.9, 0.1)
    value, ratio = metal_figures(scene, material, tmp_path)
    print(f"\nbrushed {kind} metal: SSIM {value:.4f}, luminance ratio {ratio:.4f}")
    assert abs(ratio - 1.0) < 0.05
    assert value > 0.9
