"""From a BSDF's parameters to Whitted's fields: F0 from the IOR, the Phong exponent of a
roughness, the diffuse, specular, reflectivity and transmissivity of a dielectric or metal."""

from .ir import COLOR

# Phong exponents past this make highlights smaller than a pixel anyway.
MAX_SHININESS = 10000.0


# Rec. 709 luminance weights (Blender's default scene linear space).
LUMINANCE = (0.2126, 0.7152, 0.0722)


def is_zero(expr):
    return expr.is_const and all(v == 0.0 for v in expr.value[:3])


def is_one(expr):
    return expr.is_const and expr.value[0] == 1.0


def fresnel_f0(b, ior):
    """((n - 1) / (n + 1))^2, 0 for a non-positive IOR."""
    if ior.is_const:
        n = ior.value[0]
        return b.f(((n - 1.0) / (n + 1.0)) ** 2 if n > 0.0 else 0.0)
    ratio = b.div(b.sub(ior, b.f(1.0)), b.add(ior, b.f(1.0)))
    positive = b.math("GREATER_THAN", ior, b.f(0.0))
    return b.mul(b.mul(ratio, ratio), positive)


def phong_exponent(roughness):
    """The Phong exponent of about the same highlight as a microfacet lobe of this
    roughness (alpha = roughness^2), in [1, MAX_SHININESS]. Walter et al. (2007) match
    Beckmann's alpha with a Blinn-Phong exponent s = 2/alpha^2 - 2 about the half
    vector; Whitted's Phong lobe (v.r)^n is about the mirror direction, whose angle to
    the view is twice the half vector's to the normal, so it has that width at n = s/4
    (cos(2t)^n ~ exp(-2 n t^2) against cos(t)^s ~ exp(-s t^2 / 2))."""
    alpha2 = (roughness * roughness) ** 2
    n = MAX_SHININESS if alpha2 == 0.0 else 0.5 / alpha2 - 0.5
    return min(max(n, 1.0), MAX_SHININESS)


def shininess_of(b, roughness):
    """phong_exponent as an Expr of a roughness Expr."""
    if roughness.is_const:
        return b.f(phong_exponent(roughness.value[0]))
    alpha = b.mul(roughness, roughness)
    # alpha^2 floored where 0.5/alpha^2 - 0.5 reaches the maximum: the same clamp.
    floor = 0.5 / (MAX_SHININESS + 0.5)
    alpha2 = b.maximum(b.mul(alpha, alpha), b.f(floor))
    return b.clamp(b.sub(b.div(b.f(0.5), alpha2), b.f(0.5)), 1.0, MAX_SHININESS)


def whitted_fields(b, base, metallic, roughness, f0, transmission, base_diffuse=None, glossy=False):
    """Principled-style parameters -> Whitted fields (Exprs); `f0` the dielectric
    reflectance at normal incidence (RGB, tint included). The formulas of the
    constant mapping, emitted as ops where the inputs vary. `glossy` (the Blender
    local model): the metal's reflection is its GGX lobe of this roughness (the field
    `roughness`), for rays and lamps alike."""
    base_diffuse = base if base_diffuse is None else base_diffuse
    metallic = b.clamp01(metallic)
    roughness = b.clamp01(roughness)
    transmission = b.clamp01(transmission)
    one = b.f(1.0)
    # The lobe of the metal's reflection and of the glass's reflection and refraction.
    glossy = glossy and not (is_zero(metallic) and is_zero(transmission))
    # Lecture model: a Whitted tracer cannot blur a reflection, so a metal's mirror
    # fades out as roughness goes from 0 to 0.25, and the Phong highlight takes its
    # place. Blender model: all of it is the lobe's, which the native core blurs.
    sharp = one if glossy else b.maximum(b.f(0.0), b.sub(one, b.mul(b.f(4.0), roughness)))
    dielectric = b.sub(one, metallic)
    # Only what is neither metal nor glass scatters diffusely.
    diffuse_weight = b.mul(dielectric, b.sub(one, transmission))
    zero3 = b.const((0.0, 0.0, 0.0), COLOR)
    return {
        "diffuse": b.vmul(diffuse_weight, base_diffuse),
        # Highlight weight: the dielectric part reflects F0; a metal reflects its
        # base colour, of which the sharp part already went to the mirror.
        "specular": b.vadd(
            b.vmul(dielectric, b.vmath("MAXIMUM", f0, zero3, kind=COLOR)),
            b.vmul(b.mul(metallic, b.sub(one, sharp)), base),
        ),
        "shininess": shininess_of(b, roughness),
        "reflectivity": b.vmul(b.mul(metallic, sharp), base),
        "transmissivity": b.vmul(b.mul(transmission, dielectric), base),
        **({"roughness": roughness} if glossy else {}),
    }


def sharpness(b, roughness, glossy=False):
    """The share of a specular lobe that is the layer's reflection: in the Lecture model
    1 - 4 roughness, at least 0 (a mirror cannot be blurred, so it fades into the Phong
    highlight by 0.25); in the Blender model (`glossy`) all of it, its GGX lobe."""
    if glossy:
        return b.f(1.0)
    return b.maximum(b.f(0.0), b.sub(b.f(1.0), b.mul(b.f(4.0), b.clamp01(roughness))))
