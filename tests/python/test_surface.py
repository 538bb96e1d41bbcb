"""Surface layers of the integrator without Blender: the coat."""

import math

import pytest
import whitted_native as wn
from test_scene import finish, lit_floor_scene

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
