"""Shader trees as Whitted surfaces: each BSDF a `Closure` of Whitted fields (Exprs),
Add Shader and Mix Shader combining them.

A closure is what a surface does with the light reaching it: a share `coverage`
of it is shaded with the fields, the rest passes straight through (Whitted's
alpha; a Transparent BSDF is coverage 0). Cycles adds closures; so Mix Shader is
the factor's blend of both closures and Add Shader their sum:

- coverage: mix (1 - f) cA + f cB; add cA + cB - 1 (the light passed straight
  through adds up: (1 - cA) + (1 - cB));
- the linear fields (diffuse, specular, reflectivity, transmissivity, emission):
  the coverage-weighted sum over the coverage, (wA FA + wB FB) / coverage;
- the Phong exponent and the IOR, which are not linear, are means weighted by
  the coverage of the closures that have one (a Diffuse or Emission closure has no
  highlight and no IOR of its own, so it does not pull them towards its
  defaults); without any, the defaults;
- the shading normal: the first closure's that has one (a warning when two differ).

For closures of coverage 1 and a constant factor this is exactly the previous
mapping's blend of the Whitted parameters.
"""

import math
from dataclasses import dataclass, replace

from . import ops
from .graph import socket_type, source
from .ir import COLOR, FLOAT, VECTOR
from .sockets import find_socket

LINEAR_FIELDS = (
    "diffuse",
    "specular",
    "reflectivity",
    "transmissivity",
    "emission",
    "coat_specular",
    "coat_reflectivity",
)
WEIGHTED_FIELDS = (
    "shininess",
    "ior",
    "coat_shininess",
    "coat_ior",
    "diffuse_roughness",
    "roughness",
    "coat_roughness",
)
DEFAULTS = {
    "shininess": 1.0,
    "ior": 1.45,
    "coat_shininess": 1.0,
    "coat_ior": 1.5,
    "diffuse_roughness": 0.0,
    "roughness": 0.0,
    "coat_roughness": 0.0,
}

# Phong exponents past this make highlights smaller than a pixel anyway.
MAX_SHININESS = 10000.0

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
    ("Anisotropic",),
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

PRINCIPLED_READ = {
    name
    for table in (PRINCIPLED_INPUTS, COAT_INPUTS, SHEEN_INPUTS)
    for names in table.values()
    for name in names
}

# Nodes whose output a shader's Normal input reads.
NORMAL_NODES = ("ShaderNodeNormalMap", "ShaderNodeBump")

# Rec. 709 luminance weights (Blender's default scene linear space).
LUMINANCE = (0.2126, 0.7152, 0.0722)


@dataclass(frozen=True)
class Closure:
    coverage: object  # Expr, float
    fields: dict  # field -> Expr (colours; shininess and ior floats)
    weights: dict  # a WEIGHTED_FIELDS name -> Expr: the coverage that has an opinion
    normal: object = None  # Expr (world vector) or None: the interpolated normal
    coat_normal: object = None  # the coat's, likewise
    # The shape of its diffuse lobe where not Lambert's (native DiffuseModel's name:
    # "BURLEY", "OREN_NAYAR"), shaped by the field diffuse_roughness; None: Lambert's.
    diffuse_model: object = None
    # Its glossy lobe is Cycles' Multiscatter GGX (the energy of the facets'
    # inter-reflections kept).
    multiscatter: bool = False


class ShaderLowering:
    """Walks the shader tree of one material with a values.Lowering `c`.

    `local_model`: BLENDER gives a rough metal's reflection its glossy lobe (the field
    `roughness`); LECTURE keeps the seed's mirror and Phong highlight.
    """

    def __init__(self, c, local_model="BLENDER"):
        self.c = c
        self.b = c.b
        self.glossy = local_model == "BLENDER"

    def black(self):
        zero = self.b.const((0.0, 0.0, 0.0), COLOR)
        return Closure(
            coverage=self.b.f(1.0),
            fields={
                **{name: zero for name in LINEAR_FIELDS},
                **{name: self.b.f(v) for name, v in DEFAULTS.items()},
            },
            weights={name: self.b.f(0.0) for name in WEIGHTED_FIELDS},
        )

    def shader(self, socket, scope):
        """The closure Blender feeds shader input `socket`; black when unlinked."""
        output, _ = source(socket, scope)
        if output is None:
            return self.black()
        node = output.node
        entry = _SHADERS.get(node.bl_idname)
        if entry is None:
            return self._unsupported(output)
        convert, read = entry
        for input_socket in node.inputs:
            if input_socket.name in read or socket_type(input_socket) == "SHADER":
                continue
            if source(input_socket, output.scope)[0] is not None:
                self.c.warn(node, f"input '{input_socket.name}' is linked; Whitted ignores it")
        return convert(self, output)

    def _unsupported(self, output):
        node = output.node
        color_socket = find_socket(node.inputs, ("Color", "Base Color"))
        if color_socket is None:
            self.c.warn(node, f"shader '{node.bl_idname}' is not supported; it renders black")
            return self.black()
        self.c.warn(
            node,
            f"shader '{node.bl_idname}' is not supported; approximated as a Diffuse BSDF "
            f"of its '{color_socket.name}'",
        )
        color = self.color(output, (color_socket.name,), (0.8, 0.8, 0.8))
        return self.closure(diffuse=color)

    # --- inputs ------------------------------------------------------------------

    def _input(self, output, names, kind, default):
        socket = find_socket(output.node.inputs, names)
        if socket is None:
            return self.b.const(default, kind) if kind != FLOAT else self.b.f(default)
        return self.c.value(socket, output.scope, kind)

    def scalar(self, output, names, default):
        return self._input(output, names, FLOAT, default)

    def color(self, output, names, default):
        return self._input(output, names, COLOR, default)

    def normal(self, output, names=("Normal",)):
        socket = find_socket(output.node.inputs, names)
        fed = None if socket is None else source(socket, output.scope)[0]
        if fed is None:
            return None
        if fed.node.bl_idname not in NORMAL_NODES:
            # Only a Normal Map or a Bump gives a normal.
            self.c.warn(output.node, f"input '{socket.name}' is linked; Whitted ignores it")
            return None
        normal = self.c.value(socket, output.scope, VECTOR)
        if normal.op == ops.INPUT and normal.mode == ops.IN_NORMAL:
            return None  # the interpolated normal, as without the link
        return normal

    def closure(
        self,
        coverage=None,
        normal=None,
        highlight=False,
        refracts=False,
        coat=False,
        coat_normal=None,
        diffuse_model=None,
        multiscatter=False,
        **fields,
    ):
        base = self.black()
        coverage = coverage if coverage is not None else self.b.f(1.0)
        values = dict(base.fields)
        for name, value in fields.items():
            values[name] = value if not isinstance(value, (int, float)) else self.b.f(value)
        weights = {
            "shininess": coverage if highlight else self.b.f(0.0),
            "ior": coverage if refracts else self.b.f(0.0),
            "coat_shininess": coverage if coat else self.b.f(0.0),
            "coat_ior": coverage if coat else self.b.f(0.0),
            "coat_roughness": coverage if coat else self.b.f(0.0),
            # A diffuse lobe of another shape than Lambert's, by its roughness.
            "diffuse_roughness": coverage if diffuse_model else self.b.f(0.0),
            # A glossy lobe, by its roughness.
            "roughness": coverage if "roughness" in fields else self.b.f(0.0),
        }
        return Closure(coverage, values, weights, normal, coat_normal, diffuse_model, multiscatter)

    # --- combining -----------------------------------------------------------------

    def mix(self, factor, a, b, node):
        """(1 - factor) a + factor b."""
        B = self.b
        if factor.is_const and factor.value[0] <= 0.0:
            return a
        if factor.is_const and factor.value[0] >= 1.0:
            return b
        one_minus = B.sub(B.f(1.0), factor)
        wa = B.mul(one_minus, a.coverage)
        wb = B.mul(factor, b.coverage)
        coverage = B.lerp(factor, a.coverage, b.coverage)
        return self._combine(a, b, wa, wb, coverage, one_minus, factor, node, mix_factor=factor)

    def add(self, a, b, node):
        B = self.b
        coverage = B.sub(B.add(a.coverage, b.coverage), B.f(1.0))
        one = B.f(1.0)
        return self._combine(a, b, a.coverage, b.coverage, coverage, one, one, node)

    def _combine(self, a, b, wa, wb, coverage, share_a, share_b, node, mix_factor=None):
        B = self.b
        fields = {}
        for name in LINEAR_FIELDS:
            fa, fb = a.fields[name], b.fields[name]
            if _zero(wa) or (_zero(fa) and _zero(fb)):
                fields[name] = fb if _zero(wa) else fa
            elif _zero(wb) or (fa is fb and mix_factor is not None):
                fields[name] = fa
            elif mix_factor is not None and _one(a.coverage) and _one(b.coverage):
                fields[name] = B.vlerp(mix_factor, fa, fb)
            else:
                total = B.vadd(B.vmul(wa, fa), B.vmul(wb, fb))
                fields[name] = total if _one(coverage) else B.vdiv(total, coverage)
        weights = {}
        for name in WEIGHTED_FIELDS:
            oa = B.mul(share_a, a.weights[name])
            ob = B.mul(share_b, b.weights[name])
            weights[name] = B.add(oa, ob)
            va, vb = a.fields[name], b.fields[name]
            if _zero(ob) and _zero(oa):
                # Neither has one: the coverage-weighted mean of the defaults.
                fields[name] = (
                    va if va is vb else B.div(B.add(B.mul(wa, va), B.mul(wb, vb)), B.add(wa, wb))
                )
            elif _zero(ob) or va is vb:
                fields[name] = va
            elif _zero(oa):
                fields[name] = vb
            else:
                fields[name] = B.div(B.add(B.mul(oa, va), B.mul(ob, vb)), weights[name])
        normal = a.normal if a.normal is not None else b.normal
        if a.normal is not None and b.normal is not None and a.normal is not b.normal:
            self.c.warn(node, "combines two different normals; the first one is used")
        coat_normal = a.coat_normal if a.coat_normal is not None else b.coat_normal
        # One shape for the material's whole diffuse lobe (a Lambertian part takes the
        # other's shape).
        model = a.diffuse_model or b.diffuse_model
        if a.diffuse_model and b.diffuse_model and a.diffuse_model != b.diffuse_model:
            self.c.warn(node, "combines two diffuse models; the first one is used")
        multiscatter = a.multiscatter or b.multiscatter
        return Closure(coverage, fields, weights, normal, coat_normal, model, multiscatter)


def _zero(expr):
    return expr.is_const and all(v == 0.0 for v in expr.value[:3])


def _one(expr):
    return expr.is_const and expr.value[0] == 1.0


def fixed_texture(expr):
    """An IMAGE (flat) or CHECKER (constant colours and scale) op read at UV,
    Generated or Object coordinates: what the native ImageTexture and CheckerTexture
    compute by themselves. None otherwise."""
    if (expr.op == ops.IMAGE and expr.mode == 0) or (
        expr.op == ops.CHECKER and all(a.is_const for a in expr.args[1:])
    ):
        vector = expr.args[0]
    else:
        return None
    if vector.op != ops.INPUT or not (
        vector.mode in (ops.IN_GENERATED, ops.IN_OBJECT) or ops.IN_UV <= vector.mode < 128
    ):
        return None
    return expr


# --- the shaders ---------------------------------------------------------------------


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
    if coat is None:
        coat = _specular_layer(s, out, f0, tint, metallic, roughness, transmission)
        if coat is not None:
            # The highlight keeps the glass part's share and the rough one's.
            opaque = b.sub(b.f(1.0), transmission)
            kept = b.sub(b.f(1.0), b.mul(opaque, _sharpness(b, roughness, s.glossy)))
            highlight_f0 = b.vmul(b.mul(f0, kept), tint)
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
    if coat is not None:
        coat_fields, beneath, coat_normal = coat
        # What lies beneath the coat is seen through its tint (at normal incidence).
        for name in ("diffuse", "specular", "reflectivity", "transmissivity"):
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
        if not _zero(diffuse_roughness):
            diffuse_model = "OREN_NAYAR"
            fields["diffuse_roughness"] = b.clamp01(diffuse_roughness)
    return s.closure(
        coverage=alpha,
        normal=s.normal(out),
        highlight=True,
        refracts=True,
        coat=coat is not None,
        coat_normal=coat_normal,
        diffuse_model=diffuse_model,
        multiscatter="roughness" in fields and node.distribution == "MULTI_GGX",
        **fields,
    )


def _coat(s, out):
    """The Principled coat as Whitted coat fields: (fields, the tint beneath, the coat's
    normal or None), or None without a coat. Cycles' coat is a dielectric microfacet
    layer of its own roughness and IOR (3.x's Clearcoat: a quarter of its weight, IOR
    1.5); here it is a Phong highlight and a mirror split by roughness as a metal's are,
    both weighted per hit by the exact Fresnel factor of the IOR (native)."""
    b = s.b
    node = out.node
    weight_socket = find_socket(node.inputs, COAT_INPUTS["weight"])
    if weight_socket is None:
        return None
    weight = b.clamp01(s.scalar(out, COAT_INPUTS["weight"], 0.0))
    if _zero(weight):
        return None
    roughness = b.clamp01(s.scalar(out, COAT_INPUTS["roughness"], 0.03))
    if weight_socket.name == "Clearcoat":
        # 3.x: Cycles scales the clearcoat lobe by a quarter and fixes its IOR at 1.5.
        weight = b.mul(b.f(0.25), weight)
        ior = b.f(1.5)
        beneath = b.const((1.0, 1.0, 1.0), COLOR)
    else:
        ior = s.scalar(out, COAT_INPUTS["ior"], 1.5)
        tint = s.color(out, COAT_INPUTS["tint"], (1.0, 1.0, 1.0, 1.0))
        beneath = b.vlerp(weight, b.const((1.0, 1.0, 1.0), COLOR), tint)
    shape = (
        "a GGX lobe of the coat's roughness"
        if s.glossy
        else "a Phong highlight and a mirror of the coat's roughness"
    )
    s.c.warn(
        node,
        f"'{weight_socket.name}' is approximated: {shape}, weighted by its Fresnel factor "
        "at the view (docs/SUPPORT.md)",
    )
    sharp = _sharpness(b, roughness, s.glossy)
    fields = {
        "coat_specular": b.mul(weight, b.sub(b.f(1.0), sharp)),
        "coat_reflectivity": b.mul(weight, sharp),
        "coat_shininess": shininess_of(b, roughness),
        "coat_ior": ior,
        **({"coat_roughness": roughness} if s.glossy else {}),
    }
    return fields, beneath, s.normal(out, COAT_INPUTS["normal"])


def _specular_layer(s, out, f0, tint, metallic, roughness, transmission):
    """The sharp share (1 - 4 roughness) of the opaque dielectric part's specular as
    a clear layer's mirror on top, in the coat fields (as _coat returns them), or None
    when there is none or it is tinted. Cycles reflects the surroundings there,
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
    sharp = _sharpness(b, roughness, s.glossy)
    if _zero(opaque) or _zero(f0) or _zero(sharp):
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
    return layer, b.const((1.0, 1.0, 1.0), COLOR), s.normal(out)


def _sharpness(b, roughness, glossy=False):
    """The share of a specular lobe that is the layer's reflection: in the Lecture model
    1 - 4 roughness, at least 0 (a mirror cannot be blurred, so it fades into the Phong
    highlight by 0.25); in the Blender model (`glossy`) all of it, its GGX lobe."""
    if glossy:
        return b.f(1.0)
    return b.maximum(b.f(0.0), b.sub(b.f(1.0), b.mul(b.f(4.0), b.clamp01(roughness))))


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
    if _zero(weight):
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
    facing = b.op(ops.LAYER_WEIGHT, 1, (b.f(0.5),), kind=FLOAT)
    grazing = b.math("POWER", facing, b.f(5.0))
    return b.vmul(b.mul(weight, grazing), color)


def _warn_ignored_principled_inputs(s, out):
    for names in PRINCIPLED_IGNORED_WEIGHTS:
        socket = find_socket(out.node.inputs, names)
        if socket is None or source(socket, out.scope)[0] is not None:
            continue
        if socket.default_value > 0.0:
            s.c.warn(out.node, f"'{socket.name}' has no Whitted equivalent; it is ignored")


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
    glossy = glossy and not (_zero(metallic) and _zero(transmission))
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


def _diffuse(s, out):
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    roughness = s.scalar(out, ("Roughness",), 0.0)
    if _zero(roughness):
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
    anisotropy = find_socket(node.inputs, ("Anisotropy",))
    if anisotropy is not None and (
        source(anisotropy, out.scope)[0] is not None or anisotropy.default_value != 0.0
    ):
        s.c.warn(node, "anisotropy is not supported; the lobe is round (isotropic)")
    _warn_microfacet_distribution(s, node)
    # A glossy reflector of colour C is a metal of base colour C.
    fields = whitted_fields(
        b,
        base=color,
        metallic=b.f(1.0),
        roughness=roughness,
        f0=b.const((0.0, 0.0, 0.0), COLOR),
        transmission=b.f(0.0),
        glossy=s.glossy,
    )
    return s.closure(
        normal=s.normal(out),
        highlight=True,
        multiscatter=s.glossy and node.distribution == "MULTI_GGX",
        **fields,
    )


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
    it (native DiffuseModel VELVET). 4.x's Microfiber distribution is approximated by it."""
    node = out.node
    sigma_names = ("Sigma", "Roughness")
    if getattr(node, "distribution", "ASHIKHMIN") != "ASHIKHMIN":
        s.c.warn(node, "the Microfiber sheen is approximated by Ashikhmin's velvet lobe")
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    sigma = s.b.clamp01(s.scalar(out, sigma_names, 1.0))
    return s.closure(
        diffuse=color, normal=s.normal(out), diffuse_model="VELVET", diffuse_roughness=sigma
    )


def _toon(s, out):
    node = out.node
    if node.component == "DIFFUSE":
        return _lambert_of_color("a diffuse Toon BSDF")(s, out)
    s.c.warn(node, "a glossy Toon BSDF is approximated as a Glossy BSDF of roughness Size")
    b = s.b
    color = s.color(out, ("Color",), (0.8, 0.8, 0.8, 1.0))
    roughness = s.scalar(out, ("Size",), 0.5)
    fields = whitted_fields(
        b,
        base=color,
        metallic=b.f(1.0),
        roughness=roughness,
        f0=b.const((0.0, 0.0, 0.0), COLOR),
        transmission=b.f(0.0),
        glossy=s.glossy,
    )
    return s.closure(normal=s.normal(out), highlight=True, **fields)


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


_GLOSSY = (_glossy, {"Color", "Roughness", "Anisotropy", "Normal", "Weight"})
_SHADERS = {
    "ShaderNodeBsdfPrincipled": (_principled, PRINCIPLED_READ | {"Weight"}),
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

SUPPORTED_SHADERS = frozenset(_SHADERS)


def surface(c, output_node, local_model="BLENDER"):
    """The closure of a material's active output (its Surface input)."""
    lowering = ShaderLowering(c, local_model)
    socket = output_node.inputs["Surface"]
    return lowering.shader(socket, ())


def finish(c, closure):
    """The Whitted fields of a closure: {field: Expr}, alpha the clamped coverage."""
    fields = dict(closure.fields)
    fields["alpha"] = c.b.clamp01(closure.coverage)
    if closure.normal is not None:
        fields["normal"] = closure.normal
    if closure.coat_normal is not None:
        fields["coat_normal"] = closure.coat_normal
    return replace(closure, fields=fields).fields
