"""Surface layers of the integrator without Blender: the coat, the lifted normal."""

import math

import numpy as np
import pytest
import whitted_native as wn
from test_scene import finish, lit_floor_scene, quad

# Exact dielectric reflectance of IOR 1.5 at normal incidence.
F0 = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2


def centre(material, background=(0.0, 0.0, 0.0)):
    """The pixel looking straight down at the floor point under the light (irradiance
    40 / 2^2 there) of a floor of `material` under a sky of `background`."""
    scene = lit_floor_scene()
    scene.set_material("white", material)
    scene.background = background
    image = finish(wn.RenderJob(scene, wn.Settings(width=33, height=33)))
    return image[16, 16, :3]


def test_coat_mirror_is_fresnel_weighted_and_dims_the_base():
    base = 0.5 / math.pi * 10.0
    material = wn.Material(diffuse=(0.5,) * 3, ambient=0.0, coat_reflectivity=1.0, coat_ior=1.5)
    # Head-on the coat reflects F0 of the white sky and lets 1 - F0 light the base.
    expected = (1.0 - F0) * base + F0 * 1.0
    assert centre(material, (1.0, 1.0, 1.0)) == pytest.approx([expected] * 3, rel=1e-4)
    uncoated = wn.Material(diffuse=(0.5,) * 3, ambient=0.0)
    assert centre(uncoated, (1.0, 1.0, 1.0)) == pytest.approx([base] * 3, rel=1e-4)


def test_coat_highlight_is_a_normalised_phong_lobe_of_its_own():
    material = wn.Material(
        diffuse=(0.5,) * 3, ambient=0.0, coat_specular=1.0, coat_shininess=1.0, coat_ior=1.5
    )
    # Light, view and coat normal all along z: (v.r)^f = 1, lobe (f + 2) / (2 pi).
    base = 0.5 / math.pi * 10.0
    expected = (1.0 - F0) * base + F0 * 3.0 / (2.0 * math.pi) * 10.0
    assert centre(material) == pytest.approx([expected] * 3, rel=1e-4)


def tilted_normal_material(valid_reflection):
    # A program whose normal is the world-space Normal Map of a constant colour: 60
    # degrees from +Z towards +X, so the straight-down view mirrors below the floor.
    unused = 0xFFFFFFFF
    s, c = math.sin(math.radians(60.0)), math.cos(math.radians(60.0))
    code = np.array([[29, 2, 2, 0, 1, unused, unused, unused]], dtype=np.uint32)
    registers = np.array(
        [[1.0] * 4, [0.5 + 0.5 * s, 0.5, 0.5 + 0.5 * c, 1.0], [0.0] * 4], dtype=np.float32
    )
    program = wn.Program(code, registers, np.zeros(0, np.float32), [])
    return wn.Material(
        diffuse=(0.5,) * 3,
        ambient=0.0,
        program=program,
        outputs={"normal": 2},
        valid_reflection=valid_reflection,
    )


def test_valid_reflection_lifts_a_mapped_normal_as_cycles_3():
    base = 0.5 / math.pi * 10.0  # the diffuse term for a normal along the light
    # Unlifted: cos 60 to the light overhead.
    assert centre(tilted_normal_material(False)) == pytest.approx([0.5 * base] * 3, rel=1e-4)
    # Lifted until the view's mirror leaves at height 0.01: 2 z^2 - 1 = 0.01.
    z = math.sqrt(0.505)
    assert centre(tilted_normal_material(True)) == pytest.approx([z * base] * 3, rel=1e-4)


def test_valid_reflection_lifts_a_mapped_coat_normal_as_cycles_3():
    # The 60-degree normal as the coat's normal, a sharp coat mirroring a white sky:
    # unlifted, the straight-down view's mirror falls below the floor and the coat shows
    # no sky; lifted (Cycles 3.x lifts Clearcoat Normal as Normal) it is the coat of the
    # normal whose mirror leaves at height 0.01, given directly.
    def coated(normal_material, valid_reflection):
        return wn.Material(
            diffuse=(0.5,) * 3,
            ambient=0.0,
            coat_reflectivity=1.0,
            coat_ior=1.5,
            program=normal_material.program,
            outputs={"coat_normal": 2},
            valid_reflection=valid_reflection,
        )

    tilted = tilted_normal_material(False)
    z = math.sqrt(0.505)
    unused = 0xFFFFFFFF
    code = np.array([[29, 2, 2, 0, 1, unused, unused, unused]], dtype=np.uint32)
    lifted_colour = [0.5 + 0.5 * math.sqrt(1.0 - z * z), 0.5, 0.5 + 0.5 * z, 1.0]
    registers = np.array([[1.0] * 4, lifted_colour, [0.0] * 4], dtype=np.float32)
    lifted = wn.Material(program=wn.Program(code, registers, np.zeros(0, np.float32), []))
    sky = (1.0, 1.0, 1.0)
    as_lifted = centre(coated(lifted, False), sky)
    assert centre(coated(tilted, True), sky) == pytest.approx(as_lifted, rel=1e-4)
    assert not np.allclose(centre(coated(tilted, False), sky), as_lifted, rtol=1e-2)


def test_bump_shadowing_fades_the_diffuse_lobe_of_a_mapped_normal_as_cycles():
    # The 60-degree normal under a sun 20 degrees above the floor on the side it leans
    # to (n.l = cos 10), and under one 5 degrees below the floor, which only the mapped
    # normal sees: Cycles fades the first (3.x: Chiang et al.'s cubic; 4.x+: the GGX
    # masking of Conty Estevez et al.) and cuts the second.
    def render(bump_shadowing, elevation, passes=()):
        scene = lit_floor_scene()
        e = math.radians(elevation)
        direction = (-math.cos(e), 0.0, -math.sin(e))  # the way the light travels
        scene.set_light(
            "key", wn.Light(type=wn.LightType.SUN, color=(1.0,) * 3, direction=direction)
        )
        program = tilted_normal_material(False)
        material = wn.Material(
            diffuse=(0.5,) * 3,
            ambient=0.0,
            program=program.program,
            outputs=program.outputs,
            bump_shadowing=bump_shadowing,
        )
        scene.set_material("white", material)
        job = wn.RenderJob(scene, wn.Settings(width=33, height=33, passes=list(passes)))
        return finish(job), job

    def lit(bump_shadowing, elevation):
        return render(bump_shadowing, elevation)[0][16, 16, 0]

    base = 0.5 / math.pi * math.cos(math.radians(10.0))
    modes = wn.BumpShadowing
    assert lit(modes.NONE, 20.0) == pytest.approx(base, rel=1e-4)
    cos_si, cos_sn, cos_ni = math.sin(math.radians(20.0)), 0.5, math.cos(math.radians(10.0))
    g = cos_si / (cos_ni * cos_sn)
    assert lit(modes.CHIANG, 20.0) == pytest.approx(base * (g + g * g - g**3), rel=1e-4)
    alpha2 = 0.125 * (1.0 / cos_sn**2 - 1.0)
    masking = 2.0 / (1.0 + math.sqrt(1.0 + alpha2 * (1.0 / cos_si**2 - 1.0)))
    assert lit(modes.MICROFACET, 20.0) == pytest.approx(base * masking, rel=1e-4)
    assert lit(modes.SMOOTH_SIDE, 20.0) == pytest.approx(base, rel=1e-4)
    assert lit(modes.NONE, -5.0) > 0.1 * base
    for mode in (modes.SMOOTH_SIDE, modes.CHIANG, modes.MICROFACET):
        assert lit(mode, -5.0) == 0.0
    # The Diffuse passes carry the fade: Color x Direct is the image.
    image, job = render(modes.CHIANG, 20.0, ("diffuse_direct", "diffuse_color"))
    rebuilt = job.pass_image("diffuse_color") * job.pass_image("diffuse_direct")
    np.testing.assert_allclose(rebuilt, image[..., :3], atol=1e-6)


def test_glass_casts_a_full_shadow_unless_its_shadows_are_tinted():
    # A glass pane at height 1 between the light and the floor point (0.909, 0) that
    # pixel (16, 19) sees past the pane's edge: the feeler meets the glass, the camera
    # ray does not. Opaque (the default, as Cycles): no light; tinted: its transmissivity.
    scene = lit_floor_scene()
    scene.set_mesh("pane", *quad(-0.5, 0.5, -0.5, 0.5, 1))
    glass = wn.Material(diffuse=(0, 0, 0), ambient=0.0, transmissivity=(0.8, 0.6, 0.4))
    scene.set_material("glass", glass)
    scene.set_instance("pane", "pane", np.eye(4), ["glass"])
    x = (19.5 / 33.0) * 10.0 - 5.0
    r2 = x * x + 4.0
    lit = 0.5 / math.pi * 40.0 * (2.0 / math.sqrt(r2)) / r2

    def pixel(**settings):
        job = wn.RenderJob(scene, wn.Settings(width=33, height=33, **settings))
        return finish(job)[16, 19, :3], job.stats()["effects"]

    opaque, effects = pixel()
    assert np.all(opaque == 0.0)
    # Nothing lets a feeler through: the one-query shadow test is traced.
    assert not next(e for e in effects if e["name"] == "translucency")["on"]
    tinted, _ = pixel(glass_shadows=wn.GlassShadows.TINTED)
    assert tinted == pytest.approx([0.8 * lit, 0.6 * lit, 0.4 * lit], rel=1e-4)


def test_unlayered_coat_is_added_on_top_of_the_base():
    # Cycles 3.x's Principled adds its specular layer and Clearcoat without dimming the
    # base: head-on, the base keeps all of its light and the coat adds F0 of the sky.
    base = 0.5 / math.pi * 10.0
    material = wn.Material(
        diffuse=(0.5,) * 3, ambient=0.0, coat_reflectivity=1.0, coat_ior=1.5, coat_layered=False
    )
    assert centre(material, (1.0, 1.0, 1.0)) == pytest.approx([base + F0] * 3, rel=1e-4)


def floor_image(material):
    scene = lit_floor_scene()
    scene.set_material("white", material)
    return finish(wn.RenderJob(scene, wn.Settings(width=33, height=33)))


def test_burley_diffuse_roughness_from_a_program_as_from_a_constant():
    # A program with no instruction whose register 0 holds roughness 0.7 drives the
    # Burley lobe's roughness as the constant does; Lambert's lobe differs away from the
    # pixel under the light.
    program = wn.Program(
        np.zeros((0, 8), np.uint32),
        np.array([[0.7, 0.0, 0.0, 0.0]], np.float32),
        np.zeros(0, np.float32),
        [],
    )
    burley = {"diffuse": (0.5,) * 3, "ambient": 0.0, "diffuse_model": wn.DiffuseModel.BURLEY}
    constant = floor_image(wn.Material(diffuse_roughness=0.7, **burley))
    driven = floor_image(wn.Material(program=program, outputs={"diffuse_roughness": 0}, **burley))
    lambert = floor_image(wn.Material(diffuse=(0.5,) * 3, ambient=0.0))
    np.testing.assert_array_equal(driven, constant)
    assert not np.allclose(constant, lambert, rtol=1e-3)
    assert wn.Material(diffuse_roughness=3.0).diffuse_roughness == 1.0


def test_a_sheen_lobe_adds_to_a_burley_diffuse_lobe_of_its_own():
    # The sheen is a lobe beside the diffuse one, each keeping its shape: a Burley
    # diffuse and a velvet sheen together render the sum of each alone (Cycles' Add
    # Shader of a Principled and a Velvet BSDF), and a program drives the sheen as the
    # constants do.
    burley = {"diffuse_model": wn.DiffuseModel.BURLEY, "diffuse_roughness": 0.5}
    velvet = {"sheen": (0.3, 0.6, 0.9), "sheen_roughness": 0.4}
    both = floor_image(wn.Material(diffuse=(0.5,) * 3, ambient=0.0, **burley, **velvet))
    diffuse = floor_image(wn.Material(diffuse=(0.5,) * 3, ambient=0.0, **burley))
    sheen = floor_image(wn.Material(diffuse=(0.0,) * 3, ambient=0.0, **velvet))
    np.testing.assert_allclose(both[..., :3], diffuse[..., :3] + sheen[..., :3], rtol=1e-5)
    assert sheen[..., :3].max() > 0.01 and not np.allclose(sheen[..., 0], sheen[..., 2])
    program = wn.Program(
        np.zeros((0, 8), np.uint32),
        np.array([[0.3, 0.6, 0.9, 0.0], [0.4, 0.0, 0.0, 0.0]], np.float32),
        np.zeros(0, np.float32),
        [],
    )
    driven = floor_image(
        wn.Material(
            diffuse=(0.0,) * 3,
            ambient=0.0,
            program=program,
            outputs={"sheen": 0, "sheen_roughness": 1},
        )
    )
    np.testing.assert_array_equal(driven, sheen)
    material = wn.Material(sheen=(-1.0, 0.5, 2.0), sheen_roughness=3.0)
    assert tuple(material.sheen) == (0.0, 0.5, 2.0) and material.sheen_roughness == 1.0
