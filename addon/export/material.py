"""Blender materials as Whitted parameters: a Phong local term, a mirror and glass.

Colours are linear RGB (Blender's scene linear), as the tracer uses them.
"""

from dataclasses import dataclass

from .nodes import input_value, surface_node, uses_nodes

Color = tuple[float, float, float]

# Principled BSDF inputs by name, newest name first: Blender 4.0 renamed
# Specular -> Specular IOR Level, Transmission -> Transmission Weight and
# Emission -> Emission Color. Never by index: the order changed too.
PRINCIPLED_INPUTS = {
    "base_color": ("Base Color",),
    "metallic": ("Metallic",),
    "roughness": ("Roughness",),
    "specular": ("Specular IOR Level", "Specular"),
    "transmission": ("Transmission Weight", "Transmission"),
    "ior": ("IOR",),
    "emission_color": ("Emission Color", "Emission"),
    "emission_strength": ("Emission Strength",),
}

# Values for inputs a node lacks, Blender 3.4's defaults. Emission is black by
# default in 3.x; in 4.x the colour is white but the strength is 0.
PRINCIPLED_DEFAULTS = {
    "base_color": (0.8, 0.8, 0.8, 1.0),
    "metallic": 0.0,
    "roughness": 0.5,
    "specular": 0.5,
    "transmission": 0.0,
    "ior": 1.45,
    "emission_color": (0.0, 0.0, 0.0, 1.0),
    "emission_strength": 1.0,
}

# Phong exponents past this make highlights smaller than a pixel anyway.
MAX_SHININESS = 10000.0


@dataclass(frozen=True)
class MaterialData:
    diffuse: Color  # kd, the albedo of the diffuse term kd/pi * E
    specular: Color  # ks of the normalised Phong highlight
    shininess: float  # Phong exponent
    ambient: float  # weight of the ambient term ka * Ia * kd
    reflectivity: Color  # weight of the mirror ray
    transmissivity: Color  # weight of the refracted ray
    ior: float
    emission: Color  # radiance added as is, W/(m^2 sr)


# What a material without a surface shader renders as in Cycles.
_BLACK = MaterialData(
    diffuse=(0.0, 0.0, 0.0),
    specular=(0.0, 0.0, 0.0),
    shininess=1.0,
    ambient=1.0,
    reflectivity=(0.0, 0.0, 0.0),
    transmissivity=(0.0, 0.0, 0.0),
    ior=1.45,
    emission=(0.0, 0.0, 0.0),
)


def convert_material(material, warnings):
    """Convert one material. Its Principled BSDF is read when the material uses
    nodes; otherwise (or for another shader, with a warning) its viewport
    colour, specular, roughness and metallic values."""
    owner = f"material '{material.name}'"
    if not uses_nodes(material):
        return _viewport_material(material)
    node = surface_node(material.node_tree)
    if node is None:
        warnings.append(f"Whitted: {owner} has no surface shader; it renders black, as in Cycles")
        return _BLACK
    if node.bl_idname != "ShaderNodeBsdfPrincipled":
        warnings.append(
            f"Whitted: {owner}: the surface shader '{node.name}' is not a Principled BSDF; "
            "using the material's viewport display colour"
        )
        return _viewport_material(material)
    values = {
        key: input_value(node, names, PRINCIPLED_DEFAULTS[key], owner, warnings)
        for key, names in PRINCIPLED_INPUTS.items()
    }
    strength = values.pop("emission_strength")
    emission = values.pop("emission_color")
    values["emission"] = tuple(c * strength for c in emission[:3])
    values["base_color"] = values["base_color"][:3]
    return _whitted_material(**values)


def _viewport_material(material):
    # Material > Viewport Display: what a material without nodes renders with.
    return _whitted_material(
        base_color=tuple(material.diffuse_color[:3]),
        metallic=material.metallic,
        roughness=material.roughness,
        specular=material.specular_intensity,
        transmission=0.0,
        ior=1.45,
        emission=(0.0, 0.0, 0.0),
    )


def _whitted_material(base_color, metallic, roughness, specular, transmission, ior, emission):
    """Principled-style parameters -> Whitted parameters."""
    metallic = _clamp(metallic, 0.0, 1.0)
    roughness = _clamp(roughness, 0.0, 1.0)
    transmission = _clamp(transmission, 0.0, 1.0)
    # A Whitted tracer cannot blur a reflection, so a metal's mirror fades out as
    # roughness goes from 0 to 0.25, and the Phong highlight takes its place.
    sharp = max(0.0, 1.0 - 4.0 * roughness)
    # Only what is neither metal nor glass scatters diffusely.
    diffuse_weight = (1.0 - metallic) * (1.0 - transmission)
    # Highlight weight: a dielectric reflects F0 = 0.08 * specular at normal
    # incidence (the Principled BSDF's definition; 0.5 -> 0.04, IOR 1.5); a metal
    # reflects its base colour, of which the sharp part already went to the mirror.
    dielectric_specular = (1.0 - metallic) * 0.08 * max(0.0, specular)
    # Phong exponent of about the same lobe as a microfacet roughness: alpha =
    # roughness^2 and n = 2/alpha^2 - 2 (Walter et al. 2007, Beckmann <-> Phong).
    alpha = roughness * roughness
    shininess = MAX_SHININESS if alpha == 0.0 else 2.0 / (alpha * alpha) - 2.0
    return MaterialData(
        diffuse=tuple(diffuse_weight * c for c in base_color),
        specular=tuple(dielectric_specular + metallic * (1.0 - sharp) * c for c in base_color),
        shininess=_clamp(shininess, 1.0, MAX_SHININESS),
        ambient=1.0,
        reflectivity=tuple(metallic * sharp * c for c in base_color),
        transmissivity=tuple(transmission * (1.0 - metallic) * c for c in base_color),
        ior=ior,
        emission=tuple(emission),
    )


def _clamp(value, low, high):
    return min(max(value, low), high)
