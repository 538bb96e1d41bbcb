"""The Principled BSDF as a closure of Whitted fields: its base (diffuse, metallic,
transmission), its specular layer, its coat and its sheen, with the socket names of every
Blender version."""

from dataclasses import dataclass

from . import ops
from .graph import socket_type, source
from .ir import COLOR, FLOAT
from .shader_fields import LUMINANCE, fresnel_f0, is_zero, sharpness, shininess_of, whitted_fields
from .sockets import find_socket

# Principled BSDF inputs by name, newest name first (Blender 4.0 renamed some).
PRINCIPLED_INPUTS = {
    "base_color": ("Base Color",),
    "metallic": ("Metallic",),
    "roughness": ("Roughness",),
    "specular": ("Specular IOR Level", "Specular"),
    "specular_tint": ("Specular Tint",),
    "transmission": ("Transmission Weight", "Transmission"),
    "ior": ("IOR",),
    "emission_color": ("Emission Color", "Emission"),
    "emission_strength": ("Emission Strength",),
    "alpha": ("Alpha",),
    "normal": ("Normal",),
    "diffuse_roughness": ("Diffuse Roughness",),  # 4.3+
}


# Values for inputs a node lacks, Blender 3.4's defaults.
PRINCIPLED_DEFAULTS = {
    "base_color": (0.8, 0.8, 0.8, 1.0),
    "metallic": 0.0,
    "roughness": 0.5,
    "specular": 0.5,
    "specular_tint": 0.0,
    "transmission": 0.0,
    "ior": 1.45,
    "emission_color": (0.0, 0.0, 0.0, 1.0),
    "emission_strength": 1.0,
    "alpha": 1.0,
}


# Principled lobes Whitted does not have: warned when their weight is above 0.
PRINCIPLED_IGNORED_WEIGHTS = (
    ("Subsurface Weight", "Subsurface"),
    ("Thin Film Thickness",),
)


# The coat (Blender 4.0+; 3.x's Clearcoat) and sheen inputs, newest name first.
COAT_INPUTS = {
    "weight": ("Coat Weight", "Clearcoat"),
    "roughness": ("Coat Roughness", "Clearcoat Roughness"),
    "ior": ("Coat IOR",),
    "tint": ("Coat Tint",),
    "normal": ("Coat Normal", "Clearcoat Normal"),
}


SHEEN_INPUTS = {"weight": ("Sheen Weight", "Sheen"), "tint": ("Sheen Tint",)}

# The anisotropy of the glossy lobe (every version's names).
ANISOTROPY_INPUTS = {"amount": ("Anisotropic",), "rotation": ("Anisotropic Rotation",)}


PRINCIPLED_READ = {
    name
    for table in (PRINCIPLED_INPUTS, COAT_INPUTS, SHEEN_INPUTS, ANISOTROPY_INPUTS)
    for names in table.values()
    for name in names
} | {"Tangent"}


def _principled(s, out):
    b = s.b
    node = out.node
    base = s.color(out, ("Base Color",), (0.8, 0.8, 0.8, 1.0))
    metallic = b.clamp01(s.scalar(out, ("Metallic",), 0.0))
    roughness = s.scalar(out, ("Roughness",), 0.5)
    transmission = b.clamp01(s.scalar(out, PRINCIPLED_INPUTS["transmission"], 0.0))
    ior = s.scalar(out, ("IOR",), 1.45)
    specular = s.scalar(out, PRINCIPLED_INPUTS["specular"], 0.5)
    alpha = b.clamp01(s.scalar(out, ("Alpha",), 1.0))
    # Dielectric reflectance at normal incidence, F0 (the highlight's weight).
    specular_socket = find_socket(node.inputs, PRINCIPLED_INPUTS["specular"])
    level = b.maximum(b.f(0.0), specular)
    if specular_socket is not None and specular_socket.name == "Specular IOR Level":
        # 4.x: F0 follows the IOR, ((n-1)/(n+1))^2, scaled by 2 * level (0.5 = as is).
        f0 = b.mul(b.mul(fresnel_f0(b, ior), b.f(2.0)), level)
    else:
        # 3.x: F0 = 0.08 * Specular, whatever the IOR (0.5 -> 0.04, as for IOR 1.5).
        f0 = b.mul(b.f(0.08), level)
    tint_socket = find_socket(node.inputs, ("Specular Tint",))
    if tint_socket is None or socket_type(tint_socket) in ("VALUE", "FLOAT"):
        # 3.x: Specular Tint blends white towards the base colour's hue (the base
        # colour over its luminance; white for black).
        tint = s.scalar(out, ("Specular Tint",), 0.0)
        white = b.const((1.0, 1.0, 1.0), COLOR)
        if base.is_const:
            r, g, bb = base.value[:3]
            luminance = LUMINANCE[0] * r + LUMINANCE[1] * g + LUMINANCE[2] * bb
            hue = white
            if luminance > 0.0:
                hue = b.const((r / luminance, g / luminance, bb / luminance))
        else:
            hue = b.vdiv(base, b.maximum(b.luminance(base), b.f(1e-8)))
        tint = b.vlerp(tint, white, hue)
    else:
        # 4.x: a colour that multiplies the dielectric reflection.
        tint = s.color(out, ("Specular Tint",), (1.0, 1.0, 1.0, 1.0))
    _warn_ignored_principled_inputs(s, out)
    coat = _coat(s, out)
    strength = s.scalar(out, ("Emission Strength",), 1.0)
    emission_color = s.color(out, PRINCIPLED_INPUTS["emission_color"], (0.0, 0.0, 0.0, 1.0))
    highlight_f0 = b.vmul(f0, tint)
    layer = _specular_layer(s, out, f0, tint, metallic, roughness, transmission)
    if layer is not None:
        # The highlight keeps the glass part's share and the rough one's.
        opaque = b.sub(b.f(1.0), transmission)
        kept = b.sub(b.f(1.0), b.mul(opaque, sharpness(b, roughness, s.glossy)))
        highlight_f0 = b.vmul(b.mul(f0, kept), tint)
        if coat is None:
            # Without a coat the specular layer is the top layer: the coat fields hold it
            # (a GGX lobe, of the base's roughness).
            coat, layer = layer, None
    fields = whitted_fields(
        b,
        base_diffuse=base,
        base=base,
        metallic=metallic,
        roughness=roughness,
        f0=highlight_f0,
        transmission=transmission,
        glossy=s.glossy,
    )
    sheen = _sheen(s, out, base)
    if sheen is not None:
        fields["diffuse"] = b.vadd(fields["diffuse"], sheen)
    coat_normal = None
    coat_model = None
    if layer is not None:
        # Beneath a coat, the specular layer is the layer fields: a clear layer about the
        # base's normal, whose rough lobe is the base's (its roughness and anisotropy).
        layer_fields = layer[0]
        fields["layer_reflectivity"] = layer_fields["coat_reflectivity"]
        fields["layer_ior"] = layer_fields["coat_ior"]
        if s.glossy and "roughness" not in fields:
            fields["roughness"] = b.clamp01(roughness)
    if coat is not None:
        coat_fields, beneath, coat_normal, coat_model = coat
        # What lies beneath the coat is seen through its tint (at normal incidence).
        for name in ("diffuse", "specular", "reflectivity", "transmissivity", "layer_reflectivity"):
            if name in fields:
                fields[name] = b.vmul(fields[name], beneath)
        fields.update(coat_fields)
    # The Principled BSDF emits Emission Color * Emission Strength as radiance.
    fields["emission"] = b.vmul(emission_color, strength)
    fields["ior"] = ior
    # Cycles 3.x shapes the Principled diffuse lobe by roughness (Burley's diffuse with
    # retro-reflection); 4.0 on, it is Lambert's.
    diffuse_model = None
    if specular_socket is None or specular_socket.name == "Specular":
        diffuse_model = "BURLEY"
        fields["diffuse_roughness"] = b.clamp01(roughness)
    else:
        # 4.3+: Diffuse Roughness makes the diffuse lobe Oren-Nayar's (as a Diffuse BSDF's).
        diffuse_roughness = s.scalar(out, PRINCIPLED_INPUTS["diffuse_roughness"], 0.0)
        if not is_zero(diffuse_roughness):
            diffuse_model = "OREN_NAYAR"
            fields["diffuse_roughness"] = b.clamp01(diffuse_roughness)
    normal = s.normal(out)
    anisotropy = {}
    if "roughness" in fields:
        anisotropy = s.anisotropic(
            out, _anisotropy(s, out), normal, rotation=ANISOTROPY_INPUTS["rotation"]
        )
    return s.closure(
        coverage=alpha,
        normal=normal,
        highlight=True,
        refracts=True,
        coat=coat is not None,
        coat_normal=coat_normal,
        coat_model=coat_model,
        diffuse_model=diffuse_model,
        multiscatter="roughness" in fields and node.distribution == "MULTI_GGX",
        **anisotropy,
        **fields,
    )


def _anisotropy(s, out):
    """The Principled Anisotropic A in [0, 1] as the Glossy BSDF's anisotropy: Cycles
    stretches the lobe along the tangent by aspect = sqrt(1 - 0.9 A) (alpha / aspect
    along it, alpha * aspect across), the Glossy convention's a = aspect - 1 <= 0."""
    b = s.b
    amount = b.clamp01(s.scalar(out, ANISOTROPY_INPUTS["amount"], 0.0))
    if is_zero(amount):
        return amount
    aspect = b.math("SQRT", b.sub(b.f(1.0), b.mul(b.f(0.9), amount)))
    return b.sub(aspect, b.f(1.0))


def _coat(s, out):
    """The Principled coat as Whitted coat fields: (fields, the tint beneath, the coat's
    normal or None, its rough lobe's distribution: "GTR1" or None for GGX's), or None
    without a coat. Cycles' coat is a dielectric microfacet layer of its own roughness
    and IOR (3.x's Clearcoat: a quarter of its weight, IOR 1.5, and a GTR1 lobe); here
    it is that lobe (the Blender model) or a Phong highlight and a mirror split by
    roughness as a metal's are (the Lecture's), weighted per hit by the exact Fresnel
    factor of the IOR (native)."""
    b = s.b
    node = out.node
    weight_socket = find_socket(node.inputs, COAT_INPUTS["weight"])
    if weight_socket is None:
        return None
    weight = b.clamp01(s.scalar(out, COAT_INPUTS["weight"], 0.0))
    if is_zero(weight):
        return None
    roughness = b.clamp01(s.scalar(out, COAT_INPUTS["roughness"], 0.03))
    model = None
    if weight_socket.name == "Clearcoat":
        # 3.x: Cycles scales the clearcoat lobe by a quarter, fixes its IOR at 1.5 and
        # gives it the GTR1 distribution (native CoatModel).
        weight = b.mul(b.f(0.25), weight)
        ior = b.f(1.5)
        beneath = b.const((1.0, 1.0, 1.0), COLOR)
        model = "GTR1"
    else:
        ior = s.scalar(out, COAT_INPUTS["ior"], 1.5)
        tint = s.color(out, COAT_INPUTS["tint"], (1.0, 1.0, 1.0, 1.0))
        beneath = b.vlerp(weight, b.const((1.0, 1.0, 1.0), COLOR), tint)
    shape = (
        f"a {model or 'GGX'} lobe of the coat's roughness"
        if s.glossy
        else "a Phong highlight and a mirror of the coat's roughness"
    )
    s.c.warn(
        node,
        f"'{weight_socket.name}' is approximated: {shape}, weighted by its Fresnel factor "
        "at the view (docs/SUPPORT.md)",
    )
    sharp = sharpness(b, roughness, s.glossy)
    fields = {
        "coat_specular": b.mul(weight, b.sub(b.f(1.0), sharp)),
        "coat_reflectivity": b.mul(weight, sharp),
        "coat_shininess": shininess_of(b, roughness),
        "coat_ior": ior,
        **({"coat_roughness": roughness} if s.glossy else {}),
    }
    return fields, beneath, s.normal(out, COAT_INPUTS["normal"]), model


def _specular_layer(s, out, f0, tint, metallic, roughness, transmission):
    """The sharp share (1 - 4 roughness) of the opaque dielectric part's specular as
    a clear layer's mirror, in the coat fields (as _coat returns them), or None when
    there is none or it is tinted: the top layer without a coat; beneath a coat, the
    caller moves it to the layer fields (layer_reflectivity, layer_ior), whose lobe
    is the base's. Cycles reflects the surroundings there,
    Fresnel-weighted; a highlight alone left glossy plastic black where Cycles
    mirrors. The layer's IOR is the one whose F0 is the Principled's, so at normal
    incidence its weight is that of the highlight share it replaces (3.x Cycles takes
    that IOR for its Fresnel curve too). The rough share stays the base's highlight:
    an exact Fresnel factor would dim the diffuse beneath far more at grazing angles
    than a rough lobe's albedo does in Cycles 4.x+ (and 3.x does not dim it at all)."""
    b = s.b
    if not (tint.is_const and all(v == 1.0 for v in tint.value[:3])):
        return None
    opaque = b.mul(b.sub(b.f(1.0), metallic), b.sub(b.f(1.0), transmission))
    sharp = sharpness(b, roughness, s.glossy)
    if is_zero(opaque) or is_zero(f0) or is_zero(sharp):
        return None
    # n = (1 + sqrt(F0)) / (1 - sqrt(F0)), F0 kept below 1.
    root = b.math("SQRT", b.clamp(f0, 0.0, 0.99))
    layer = {
        "coat_specular": b.f(0.0),
        "coat_reflectivity": b.mul(opaque, sharp),
        "coat_shininess": shininess_of(b, b.clamp01(roughness)),
        "coat_ior": b.div(b.add(b.f(1.0), root), b.sub(b.f(1.0), root)),
        **({"coat_roughness": b.clamp01(roughness)} if s.glossy else {}),
    }
    return layer, b.const((1.0, 1.0, 1.0), COLOR), s.normal(out), None


def _sheen(s, out, base):
    """The Principled sheen as a grazing-angle brightening of the diffuse colour:
    weight * tint * (1 - |n.v|)^5 (Disney's sheen shape in the view angle alone), or
    None without one. It needs the shader program (the view angle varies per hit)."""
    b = s.b
    node = out.node
    weight_socket = find_socket(node.inputs, SHEEN_INPUTS["weight"])
    if weight_socket is None:
        return None
    weight = b.maximum(b.f(0.0), s.scalar(out, SHEEN_INPUTS["weight"], 0.0))
    if is_zero(weight):
        return None
    white = b.const((1.0, 1.0, 1.0), COLOR)
    tint_socket = find_socket(node.inputs, SHEEN_INPUTS["tint"])
    if tint_socket is not None and socket_type(tint_socket) in ("VALUE", "FLOAT"):
        # 3.x: Sheen Tint blends white towards the base colour's hue.
        hue = b.vdiv(base, b.maximum(b.luminance(base), b.f(1e-8)))
        color = b.vlerp(s.scalar(out, SHEEN_INPUTS["tint"], 0.5), white, hue)
    else:
        color = s.color(out, SHEEN_INPUTS["tint"], (1.0, 1.0, 1.0, 1.0))
    s.c.warn(
        node,
        f"'{weight_socket.name}' is approximated: the diffuse colour brightened towards "
        "grazing views by weight * tint * (1 - |n.v|)^5 (docs/SUPPORT.md)",
    )
    # Layer Weight's Facing at blend 0.5 is 1 - |n.v|.
    mode = ops.pack("LAYER_WEIGHT", output="FACING")
    facing = b.op(ops.LAYER_WEIGHT, mode, (b.f(0.5),), kind=FLOAT)
    grazing = b.math("POWER", facing, b.f(5.0))
    return b.vmul(b.mul(weight, grazing), color)


def _warn_ignored_principled_inputs(s, out):
    for names in PRINCIPLED_IGNORED_WEIGHTS:
        socket = find_socket(out.node.inputs, names)
        if socket is None or source(socket, out.scope)[0] is not None:
            continue
        if socket.default_value > 0.0:
            s.c.warn(out.node, f"'{socket.name}' has no Whitted equivalent; it is ignored")


PRINCIPLED_SHADERS = {
    "ShaderNodeBsdfPrincipled": (_principled, PRINCIPLED_READ | {"Weight"}),
}


@dataclass(frozen=True)
class _Unlinked:
    """An input socket of a node made here rather than read from Blender: unlinked, of
    a fixed value (graph.source, values.Lowering.default and socket_type read these)."""

    name: str
    default_value: object
    type: str
    is_linked: bool = False
    enabled: bool = True


@dataclass(frozen=True)
class _MadeNode:
    bl_idname: str
    name: str
    inputs: tuple
    distribution: str


# Blender 5.0's default surface, what Cycles renders an object without a material (or an
# empty slot) with: a Principled BSDF of a new material's inputs (5.0's names and
# defaults). Measured in bpy 5.0.1: such a sphere renders as one with a new material, to
# 2e-7; Blender 3.4 and 4.5 render it as a Diffuse BSDF of 0.8, the native default.
DEFAULT_SURFACE = _MadeNode(
    "ShaderNodeBsdfPrincipled",
    "Principled BSDF",
    (
        _Unlinked("Base Color", (0.8, 0.8, 0.8, 1.0), "RGBA"),
        _Unlinked("Metallic", 0.0, "VALUE"),
        _Unlinked("Roughness", 0.5, "VALUE"),
        _Unlinked("IOR", 1.5, "VALUE"),
        _Unlinked("Alpha", 1.0, "VALUE"),
        _Unlinked("Diffuse Roughness", 0.0, "VALUE"),
        _Unlinked("Specular IOR Level", 0.5, "VALUE"),
        _Unlinked("Specular Tint", (1.0, 1.0, 1.0, 1.0), "RGBA"),
        _Unlinked("Transmission Weight", 0.0, "VALUE"),
        _Unlinked("Coat Weight", 0.0, "VALUE"),
        _Unlinked("Sheen Weight", 0.0, "VALUE"),
        _Unlinked("Emission Color", (1.0, 1.0, 1.0, 1.0), "RGBA"),
        _Unlinked("Emission Strength", 0.0, "VALUE"),
    ),
    "MULTI_GGX",
)
