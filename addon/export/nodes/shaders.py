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
- the shading normal and the glossy lobe's tangent: the first closure's that has one (a
  warning when two normals differ).

For closures of coverage 1 and a constant factor this is exactly the previous
mapping's blend of the Whitted parameters.
"""

import math
from dataclasses import dataclass, replace

from . import ops
from .bsdfs import BSDF_SHADERS
from .graph import Output, socket_type, source
from .ir import COLOR, FLOAT, VECTOR
from .principled import DEFAULT_SURFACE, PRINCIPLED_SHADERS
from .shader_fields import is_one, is_zero
from .sockets import find_socket

LINEAR_FIELDS = (
    "diffuse",
    "specular",
    "reflectivity",
    "transmissivity",
    "emission",
    "coat_specular",
    "coat_reflectivity",
    "layer_reflectivity",
    "sheen",
)
WEIGHTED_FIELDS = (
    "shininess",
    "ior",
    "coat_shininess",
    "coat_ior",
    "diffuse_roughness",
    "roughness",
    "coat_roughness",
    "layer_ior",
    "anisotropy",
    "sheen_roughness",
)
DEFAULTS = {
    "shininess": 1.0,
    "ior": 1.45,
    "coat_shininess": 1.0,
    "coat_ior": 1.5,
    "diffuse_roughness": 0.0,
    "roughness": 0.0,
    "coat_roughness": 0.0,
    "layer_ior": 1.5,
    "anisotropy": 0.0,
    "sheen_roughness": 0.0,
}


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
    tangent: object = None  # Expr (world vector) or None: the anisotropic lobe's tangent
    # The distribution of its coat's rough lobe where not GGX's (native CoatModel's name:
    # "GTR1", Blender 3.x's Clearcoat); None: GGX's.
    coat_model: object = None


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
        # Whatever feeds it (a Normal Map, a Bump, a Bevel, any vector) is the shading
        # normal in the world, normalised natively, as Cycles normalises its Normal input.
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
        tangent=None,
        coat_model=None,
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
            # The specular layer beneath a coat, by its IOR.
            "layer_ior": coverage if "layer_ior" in fields else self.b.f(0.0),
            # A diffuse lobe of another shape than Lambert's, by its roughness.
            "diffuse_roughness": coverage if diffuse_model else self.b.f(0.0),
            # A glossy lobe, by its roughness, and an anisotropic one by its anisotropy.
            "roughness": coverage if "roughness" in fields else self.b.f(0.0),
            "anisotropy": coverage if "anisotropy" in fields else self.b.f(0.0),
            # A sheen lobe, by its sigma.
            "sheen_roughness": coverage if "sheen_roughness" in fields else self.b.f(0.0),
        }
        return Closure(
            coverage,
            values,
            weights,
            normal,
            coat_normal,
            diffuse_model,
            multiscatter,
            tangent,
            coat_model if coat else None,
        )

    def anisotropic(self, output, amount, normal, rotation=("Rotation",)):
        """The fields of a glossy lobe's anisotropy (Cycles' alpha_x and alpha_y by the
        Glossy BSDF's convention, native ggx_anisotropic_alphas) as closure keywords:
        {"anisotropy", "tangent"}; none where `amount` is 0 or the model is the Lecture's.
        The tangent is the node's Tangent input, else Cycles' default (the Geometry node's
        Tangent: radial about the object's Z axis), turned about the closure's normal by
        Rotation (a full turn per 1), as Cycles turns it."""
        B = self.b
        if not self.glossy or is_zero(amount):
            return {}
        socket = find_socket(output.node.inputs, ("Tangent",))
        if socket is not None and source(socket, output.scope)[0] is not None:
            tangent = self.c.value(socket, output.scope, VECTOR)
        else:
            tangent = self.c.hit(ops.IN_RADIAL_TANGENT + 2)
        turn = self.scalar(output, rotation, 0.0)
        if not is_zero(turn):
            axis = normal if normal is not None else self.c.hit(ops.IN_NORMAL)
            mode = ops.pack("VECTOR_ROTATE", rotation_type="AXIS_ANGLE", invert=False)
            angle = B.mul(turn, B.f(2.0 * math.pi))
            origin = B.const((0.0, 0.0, 0.0), VECTOR)
            tangent = B.op(ops.VECTOR_ROTATE, mode, (tangent, origin, axis, angle), kind=VECTOR)
        return {"anisotropy": amount, "tangent": tangent}

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
            if is_zero(wa) or (is_zero(fa) and is_zero(fb)):
                fields[name] = fb if is_zero(wa) else fa
            elif is_zero(wb) or (fa is fb and mix_factor is not None):
                fields[name] = fa
            elif mix_factor is not None and is_one(a.coverage) and is_one(b.coverage):
                fields[name] = B.vlerp(mix_factor, fa, fb)
            else:
                total = B.vadd(B.vmul(wa, fa), B.vmul(wb, fb))
                fields[name] = total if is_one(coverage) else B.vdiv(total, coverage)
        weights = {}
        for name in WEIGHTED_FIELDS:
            oa = B.mul(share_a, a.weights[name])
            ob = B.mul(share_b, b.weights[name])
            weights[name] = B.add(oa, ob)
            va, vb = a.fields[name], b.fields[name]
            if is_zero(ob) and is_zero(oa):
                # Neither has one: the coverage-weighted mean of the defaults.
                fields[name] = (
                    va if va is vb else B.div(B.add(B.mul(wa, va), B.mul(wb, vb)), B.add(wa, wb))
                )
            elif is_zero(ob) or va is vb:
                fields[name] = va
            elif is_zero(oa):
                fields[name] = vb
            else:
                fields[name] = B.div(B.add(B.mul(oa, va), B.mul(ob, vb)), weights[name])
        normal = a.normal if a.normal is not None else b.normal
        if a.normal is not None and b.normal is not None and a.normal is not b.normal:
            self.c.warn(node, "combines two different normals; the first one is used")
        coat_normal = a.coat_normal if a.coat_normal is not None else b.coat_normal
        tangent = a.tangent if a.tangent is not None else b.tangent
        # One shape for the material's whole diffuse lobe (a Lambertian part takes the
        # other's shape).
        model = a.diffuse_model or b.diffuse_model
        if a.diffuse_model and b.diffuse_model and a.diffuse_model != b.diffuse_model:
            self.c.warn(node, "combines two diffuse models; the first one is used")
        multiscatter = a.multiscatter or b.multiscatter
        # Only Blender 3.x's Clearcoat is GTR1's, and 3.x has no other coat: the two agree.
        coat_model = a.coat_model or b.coat_model
        return Closure(
            coverage, fields, weights, normal, coat_normal, model, multiscatter, tangent, coat_model
        )


def fixed_texture(expr):
    """An IMAGE (flat) or CHECKER (constant colours and scale) op read at UV,
    Generated or Object coordinates: what the native ImageTexture and CheckerTexture
    compute by themselves. None otherwise."""
    flat = expr.op == ops.IMAGE and ops.unpack("IMAGE", expr.mode)["projection"] == "FLAT"
    if flat or (expr.op == ops.CHECKER and all(a.is_const for a in expr.args[1:])):
        vector = expr.args[0]
    else:
        return None
    if vector.op != ops.INPUT or not (
        vector.mode in (ops.IN_GENERATED, ops.IN_OBJECT)
        or ops.IN_UV <= vector.mode < ops.IN_UV + ops.UV_SETS
    ):
        return None
    return expr


_SHADERS = {**PRINCIPLED_SHADERS, **BSDF_SHADERS}

SUPPORTED_SHADERS = frozenset(_SHADERS)


def surface(c, output_node, local_model="BLENDER"):
    """The closure of a material's active output (its Surface input)."""
    lowering = ShaderLowering(c, local_model)
    socket = output_node.inputs["Surface"]
    return lowering.shader(socket, ())


def default_surface(c, local_model="BLENDER"):
    """The closure of Blender 5.0's default surface (principled.DEFAULT_SURFACE), made by
    the Principled BSDF's own converter."""
    convert, _ = _SHADERS[DEFAULT_SURFACE.bl_idname]
    return convert(ShaderLowering(c, local_model), Output(DEFAULT_SURFACE, None, ()))


def finish(c, closure):
    """The Whitted fields of a closure: {field: Expr}, alpha the clamped coverage."""
    fields = dict(closure.fields)
    fields["alpha"] = c.b.clamp01(closure.coverage)
    if closure.normal is not None:
        fields["normal"] = closure.normal
    if closure.coat_normal is not None:
        fields["coat_normal"] = closure.coat_normal
    if closure.tangent is not None:
        fields["tangent"] = closure.tangent
    return replace(closure, fields=fields).fields
