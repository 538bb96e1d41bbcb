"""Per-material settings stored as `material.whitted`: the Whitted override.

When `use_override` is switched on, the fields start from what the node
mapping derived for this material (export.material.map_material), so the
artist sees, and edits, the values the engine used.
"""

import bpy
from bpy.props import BoolProperty, FloatProperty, FloatVectorProperty, PointerProperty

from ..export.material import MAX_SHININESS, map_material


def _split(color):
    """A colour as (weight, colour of largest component 1); black is (0, white)."""
    weight = max(color)
    if weight <= 0.0:
        return 0.0, (1.0, 1.0, 1.0)
    return weight, tuple(c / weight for c in color)


def _initialise_from_mapping(settings, context):
    if not settings.use_override:
        return
    # The warnings of the mapping are reported when the material is rendered.
    data = map_material(settings.id_data, []).data
    settings.diffuse_weight, settings.diffuse_color = _split(data.diffuse)
    settings.specular_weight, settings.specular_color = _split(data.specular)
    settings.shininess = data.shininess
    settings.ambient = data.ambient
    settings.reflectivity = data.reflectivity
    settings.transmissivity = data.transmissivity
    settings.ior = data.ior


def _color(name, description, default):
    return FloatVectorProperty(
        name=name,
        description=description,
        subtype="COLOR",
        size=3,
        default=default,
        min=0.0,
        soft_max=1.0,
    )


class WhittedMaterialProperties(bpy.types.PropertyGroup):
    use_override: BoolProperty(
        name="Override Nodes",
        description="Render with these Whitted parameters instead of those derived from "
        "the material's nodes (switching on copies the derived values); emission, alpha "
        "and textures still come from the nodes",
        default=False,
        update=_initialise_from_mapping,
    )
    ambient: FloatProperty(
        name="Ambient",
        description="Weight of the ambient term ka * Ia * kd",
        default=1.0,
        min=0.0,
        soft_max=1.0,
    )
    diffuse_weight: FloatProperty(
        name="Diffuse Weight",
        description="Weight of the diffuse colour: kd = weight * colour",
        default=0.8,
        min=0.0,
        soft_max=1.0,
    )
    diffuse_color: _color("Diffuse Color", "Colour of the Lambertian term kd/pi * E", (1, 1, 1))
    specular_weight: FloatProperty(
        name="Specular Weight",
        description="Weight of the specular colour: ks = weight * colour",
        default=0.04,
        min=0.0,
        soft_max=1.0,
    )
    specular_color: _color("Specular Color", "Colour of the Phong highlight", (1, 1, 1))
    shininess: FloatProperty(
        name="Phong Exponent",
        description="Exponent of the normalised Phong highlight (higher is sharper)",
        default=30.0,
        min=1.0,
        max=MAX_SHININESS,
    )
    reflectivity: _color("Reflectivity", "Weight of the mirror-reflected ray", (0, 0, 0))
    transmissivity: _color("Transmissivity", "Weight of the refracted ray", (0, 0, 0))
    ior: FloatProperty(
        name="IOR",
        description="Index of refraction of the refracted ray",
        default=1.45,
        min=1.0,
        soft_max=3.0,
    )

    @classmethod
    def register(cls):
        bpy.types.Material.whitted = PointerProperty(
            name="Whitted", description="Whitted material settings", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.Material.whitted
