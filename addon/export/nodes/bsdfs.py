"""Every other shader node as a closure of Whitted fields: Diffuse, Glossy, Glass,
Refraction, Transparent, Emission, Holdout, Translucent, Velvet/Sheen, Toon, the hair
BSDFs (by their colour), and Add and Mix Shader."""

import math

from .graph import socket_type, source
from .ir import COLOR
from .shader_fields import (
    fresnel_f0,
    is_zero,
    whitted_fields,
)


def _diffuse(s, out):
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    roughness = s.scalar(out, ("Roughness",), 0.0)
    if is_zero(roughness):
        # A Lambertian reflector of albedo `color` is exactly Whitted's diffuse term.
        return s.closure(diffuse=color, normal=s.normal(out))
    # Roughness makes it Oren-Nayar's (Fujii's form, as Cycles evaluates it).
    return s.closure(
        diffuse=color,
        normal=s.normal(out),
        diffuse_model="OREN_NAYAR",
        diffuse_roughness=s.b.clamp01(roughness),
    )


def _glossy(s, out):
    b = s.b
    node = out.node
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    # Blender 3.x's Sharp distribution is a perfect mirror whatever the roughness.
    roughness = b.f(0.0) if node.distribution == "SHARP" else s.scalar(out, ("Roughness",), 0.5)
    _warn_microfacet_distribution(s, node)
    # Blender 3.x's Anisotropic BSDF and 4.0+'s Glossy BSDF: Anisotropy, Rotation, Tangent.
    anisotropy = s.scalar(out, ("Anisotropy",), 0.0)
    multiscatter = s.glossy and node.distribution == "MULTI_GGX"
    return _metal(s, out, color, roughness, multiscatter, anisotropy)


def _metal(s, out, color, roughness, multiscatter=False, anisotropy=None):
    # A glossy reflector of colour C is a metal of base colour C.
    b = s.b
    fields = whitted_fields(
        b,
        base=color,
        metallic=b.f(1.0),
        roughness=roughness,
        f0=b.const((0.0, 0.0, 0.0), COLOR),
        transmission=b.f(0.0),
        glossy=s.glossy,
    )
    normal = s.normal(out)
    if anisotropy is not None and "roughness" in fields:
        fields.update(s.anisotropic(out, anisotropy, normal))
    return s.closure(normal=normal, highlight=True, multiscatter=multiscatter, **fields)


def _warn_microfacet_distribution(s, node):
    """Whitted's glossy lobe is GGX's: say so where the node asks for another."""
    if s.glossy and node.distribution in ("BECKMANN", "ASHIKHMIN_SHIRLEY"):
        s.c.warn(node, f"the {node.distribution.title()} distribution is rendered as GGX")


def _glass(s, out):
    b = s.b
    color = s.color(out, ("Color",), (1.0, 1.0, 1.0, 1.0))
    roughness = s.scalar(out, ("Roughness",), 0.0)
    ior = s.scalar(out, ("IOR",), 1.45)
    # A Principled BSDF of full transmission with a highlight of the IOR's F0.
    f0 = fresnel_f0(b, ior)
    fields = whitted_fields(
        b,
        base=color,
        metallic=b.f(0.0),
        roughness=roughness,
        f0=b.vmul(f0, b.const((1.0, 1.0, 1.0), COLOR)),
        transmission=b.f(1.0),
        glossy=s.glossy,
    )
    return s.closure(normal=s.normal(out), highlight=True, refracts=True, ior=ior, **fields)


def _refraction(s, out):
    color = s.color(out, ("Color",), (1.0, 1.0, 1.0, 1.0))
    ior = s.scalar(out, ("IOR",), 1.45)
    # Refraction only: no highlight.
    return s.closure(normal=s.normal(out), refracts=True, transmissivity=color, ior=ior)


def _transparent(s, out):
    b = s.b
    color = s.color(out, ("Color",), (1.0, 1.0, 1.0, 1.0))
    # Transparent BSDF = coverage: light passes straight through, unbent, with
    # weight `color`. Whitted's alpha does that exactly for a grey colour.
    if color.is_const:
        r, g, bb = color.value[:3]
        if max(r, g, bb) - min(r, g, bb) > 1e-6:
            s.c.warn(out.node, "a coloured Transparent BSDF is approximated by its mean grey")
    grey = b.clamp01(b.average(color))
    return s.closure(coverage=b.sub(b.f(1.0), grey))


def _emission(s, out):
    color = s.color(out, ("Color",), (1.0, 1.0, 1.0, 1.0))
    strength = s.scalar(out, ("Strength",), 1.0)
    # Emission emits Color * Strength as radiance and reflects nothing.
    return s.closure(emission=s.b.vmul(color, strength))


def _holdout(s, out):
    s.c.warn(out.node, "a Holdout shader is approximated as black (use the object's Holdout)")
    return s.black()


def _lambert_of_color(description):
    def convert(s, out):
        s.c.warn(out.node, f"{description} is approximated as a Lambertian diffuse of its colour")
        color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
        return s.closure(diffuse=color, normal=s.normal(out))

    return convert


def _velvet(s, out):
    """Blender 3.x's Velvet BSDF and 4.x's Sheen BSDF of the Ashikhmin distribution:
    Ashikhmin's velvet lobe of its sigma (3.x Sigma, 4.x Roughness), as Cycles evaluates
    it: the material's sheen lobe, beside any diffuse lobe an Add or Mix Shader brings
    (native Material.sheen). 4.x's Microfiber distribution is approximated by it."""
    node = out.node
    sigma_names = ("Sigma", "Roughness")
    if getattr(node, "distribution", "ASHIKHMIN") != "ASHIKHMIN":
        s.c.warn(node, "the Microfiber sheen is approximated by Ashikhmin's velvet lobe")
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    sigma = s.b.clamp01(s.scalar(out, sigma_names, 1.0))
    return s.closure(sheen=color, normal=s.normal(out), sheen_roughness=sigma)


def _toon(s, out):
    node = out.node
    if node.component == "DIFFUSE":
        return _lambert_of_color("a diffuse Toon BSDF")(s, out)
    s.c.warn(node, "a glossy Toon BSDF is approximated as a Glossy BSDF of roughness Size")
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    return _metal(s, out, color, s.scalar(out, ("Size",), 0.5))


def _mix_shader(s, out):
    node = out.node
    shaders = [x for x in node.inputs if socket_type(x) == "SHADER"]
    first = s.shader(shaders[0], out.scope)
    second = s.shader(shaders[1], out.scope)
    factor = s.b.clamp01(s.scalar(out, ("Fac", "Factor"), 0.5))
    return s.mix(factor, first, second, node)


def _add_shader(s, out):
    shaders = [x for x in out.node.inputs if socket_type(x) == "SHADER"]
    first = s.shader(shaders[0], out.scope)
    second = s.shader(shaders[1], out.scope)
    return s.add(first, second, out.node)


# Hair's absorption (Principled Hair BSDF): the coefficients per unit of eumelanin and
# of pheomelanin (d'Eon et al. 2011, as Cycles uses them), and the polynomial in Radial
# Roughness r by which Cycles turns a colour into an absorption, sigma = (ln(colour) /
# poly(r))^2 (Chiang et al. 2016); its inverse gives the colour of an absorption.
EUMELANIN = (0.506, 0.841, 1.653)


PHEOMELANIN = (0.343, 0.733, 1.924)


HAIR_POLYNOMIAL = (5.969, -0.215, 2.532, -10.73, 5.574, 0.245)


def _hair_poly(r):
    return sum(c * r**k for k, c in enumerate(HAIR_POLYNOMIAL))


def hair_colour(parametrization, values):
    """The colour a Principled Hair BSDF of `parametrization` (COLOR, MELANIN or
    ABSORPTION) looks, from its input values (name -> constant): its Color, or the colour
    whose absorption Cycles would take for its melanin (with Tint) or its Absorption
    Coefficient, exp(-sqrt(sigma) poly(r))."""
    if parametrization == "COLOR":
        return tuple(values["Color"][:3])
    r = values["Radial Roughness"]
    if parametrization == "MELANIN":
        amount = -math.log(max(1.0 - values["Melanin"], 1e-4))
        redness = values["Melanin Redness"]
        tint = [max(c, 1e-4) for c in values["Tint"][:3]]
        sigma = [
            amount * ((1.0 - redness) * e + redness * p) + (math.log(t) / _hair_poly(r)) ** 2
            for e, p, t in zip(EUMELANIN, PHEOMELANIN, tint, strict=True)
        ]
    else:
        sigma = [max(c, 0.0) for c in values["Absorption Coefficient"][:3]]
    return tuple(math.exp(-math.sqrt(c) * _hair_poly(r)) for c in sigma)


def _principled_hair(s, out):
    node = out.node
    parametrization = getattr(node, "parametrization", "COLOR")
    if parametrization == "COLOR":
        s.c.warn(
            node, "a Principled Hair BSDF is approximated as a Lambertian diffuse of its Color"
        )
        return s.closure(diffuse=s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0)))
    names = ("Melanin", "Melanin Redness", "Tint", "Absorption Coefficient", "Radial Roughness")
    values = {}
    for name in names:
        socket = node.inputs.get(name)
        if socket is None:
            continue
        if source(socket, out.scope)[0] is not None:
            s.c.warn(node, f"input '{name}' is linked; Whitted uses its unlinked value")
        value = socket.default_value
        values[name] = tuple(value) if hasattr(value, "__len__") else float(value)
    s.c.warn(
        node,
        f"a Principled Hair BSDF ({parametrization.lower()}) is approximated as a Lambertian "
        "diffuse of the colour of its absorption",
    )
    colour = hair_colour(parametrization, values)
    return s.closure(diffuse=s.b.const((*colour, 1.0), COLOR))


_GLOSSY = (_glossy, {"Color", "Roughness", "Anisotropy", "Rotation", "Tangent", "Normal", "Weight"})


# The shader nodes handled here: (handler, the inputs it reads).
BSDF_SHADERS = {
    "ShaderNodeBsdfDiffuse": (_diffuse, {"Color", "Roughness", "Normal", "Weight"}),
    "ShaderNodeBsdfGlossy": _GLOSSY,
    # Blender 4.0 merged Glossy into Anisotropic: the Glossy BSDF has this id there.
    "ShaderNodeBsdfAnisotropic": _GLOSSY,
    "ShaderNodeBsdfGlass": (_glass, {"Color", "Roughness", "IOR", "Normal", "Weight"}),
    "ShaderNodeBsdfRefraction": (_refraction, {"Color", "IOR", "Normal", "Weight"}),
    "ShaderNodeBsdfTransparent": (_transparent, {"Color", "Weight"}),
    "ShaderNodeBsdfTranslucent": (
        _lambert_of_color("a Translucent BSDF"),
        {"Color", "Normal", "Weight"},
    ),
    "ShaderNodeBsdfVelvet": (_velvet, {"Color", "Sigma", "Normal", "Weight"}),
    "ShaderNodeBsdfSheen": (_velvet, {"Color", "Roughness", "Normal", "Weight"}),
    "ShaderNodeBsdfToon": (_toon, {"Color", "Size", "Smooth", "Normal", "Weight"}),
    # Hair: its colour on a Lambertian diffuse (docs/SUPPORT.md).
    "ShaderNodeBsdfHairPrincipled": (
        _principled_hair,
        {"Color", "Melanin", "Melanin Redness", "Tint", "Absorption Coefficient"}
        | {"Radial Roughness", "Weight"},
    ),
    "ShaderNodeBsdfHair": (_lambert_of_color("a Hair BSDF"), {"Color", "Weight"}),
    "ShaderNodeEmission": (_emission, {"Color", "Strength", "Weight"}),
    "ShaderNodeHoldout": (_holdout, {"Weight"}),
    "ShaderNodeMixShader": (_mix_shader, {"Fac", "Factor", "Shader"}),
    "ShaderNodeAddShader": (_add_shader, {"Shader"}),
}
