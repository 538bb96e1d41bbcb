"""The compiler's expressions: one `Expr` per value of the lowered graph, made by a
`Builder` that folds constants and shares equal sub-expressions.

Every value is four floats, as a register is: a scalar in all four components,
a vector in xyz (w 0), a colour in xyz with alpha in w. An op whose inputs are
all constant is computed here, with the definitions of Cycles' SVM kernels
(intern/cycles/kernel/svm/*.h) that the native program mirrors, so a constant
sub-graph never reaches the program. Ops that read the hit (INPUT, IMAGE, ...)
never fold.
"""

import itertools
import math

from . import ops

FLOAT = "float"
VECTOR = "vector"
COLOR = "color"


class Expr:
    """One value: a constant (`op` CONST, `value` its four floats) or an op of
    other Exprs. Compare with `is`: the Builder shares equal expressions."""

    __slots__ = ("args", "e", "kind", "mode", "op", "value")

    def __init__(self, op, mode, args, e, value, kind):
        self.op = op
        self.mode = mode
        self.args = args
        self.e = e
        self.value = value
        self.kind = kind

    @property
    def is_const(self):
        return self.op == ops.CONST

    def __repr__(self):
        if self.is_const:
            return f"Const{self.value}"
        name = ops.OP_NAMES.get(self.op, self.op)
        return f"{name}[{self.mode}]({', '.join(map(repr, self.args))})"


def splat(x):
    x = float(x)
    return (x, x, x, x)


def _vec(v, w=0.0):
    v = tuple(float(c) for c in v)
    if len(v) == 1:
        return splat(v[0])
    if len(v) == 2:
        return (v[0], v[1], 0.0, w)
    if len(v) == 3:
        return (*v, w)
    return v[:4]


class Builder:
    """Makes Exprs: constants folded, equal expressions shared."""

    def __init__(self):
        self._cache = {}

    def const(self, value, kind=None, w=None):
        """A constant: a float (splat), or a 2-, 3- or 4-tuple."""
        if isinstance(value, (int, float, bool)):
            value = splat(value)
            kind = kind or FLOAT
        else:
            value = _vec(value, 1.0 if (kind == COLOR and w is None) else (w or 0.0))
            kind = kind or (COLOR if len(value) == 4 else VECTOR)
        value = tuple(0.0 if c == 0.0 else c for c in value)  # no -0.0 in keys
        key = (ops.CONST, value, kind)
        expr = self._cache.get(key)
        if expr is None:
            expr = self._cache[key] = Expr(ops.CONST, 0, (), None, value, kind)
        return expr

    def f(self, x):
        return self.const(float(x), FLOAT)

    def op(self, op, mode, args, e=None, kind=FLOAT):
        """An op of `args` (Exprs or None), folded when it can be."""
        args = tuple(args)
        if op in _FOLD and all(a is None or a.is_const for a in args):
            values = [None if a is None else a.value for a in args]
            try:
                value = _FOLD[op](mode, values, e)
            except (ValueError, OverflowError, ZeroDivisionError):
                value = None
            if value is not None and all(math.isfinite(c) for c in value):
                return self.const(value, kind)
        key = (op, mode, tuple(None if a is None else id(a) for a in args), e, kind)
        expr = self._cache.get(key)
        if expr is None:
            # The cache holds every Expr, so the ids in its keys stay unique.
            expr = self._cache[key] = Expr(op, mode, args, e, None, kind)
        return expr

    # --- scalar arithmetic with the identities that keep programs short -----

    def math(self, name, a, b=None, c=None, clamp=False):
        mode = ops.math_op(name) | (ops.CLAMP_BIT if clamp else 0)
        return self.op(ops.MATH, mode, (a, b, c))

    def add(self, a, b):
        if _is(a, 0.0):
            return b
        if _is(b, 0.0):
            return a
        return self.math("ADD", a, b)

    def sub(self, a, b):
        if _is(b, 0.0):
            return a
        return self.math("SUBTRACT", a, b)

    def mul(self, a, b):
        if _is(a, 1.0):
            return b
        if _is(b, 1.0):
            return a
        if _is(a, 0.0) or _is(b, 0.0):
            return self.f(0.0)
        return self.math("MULTIPLY", a, b)

    def div(self, a, b):
        if _is(b, 1.0):
            return a
        return self.math("DIVIDE", a, b)

    def maximum(self, a, b):
        return self.math("MAXIMUM", a, b)

    def minimum(self, a, b):
        return self.math("MINIMUM", a, b)

    def clamp01(self, a):
        if a.is_const:
            return self.f(min(max(a.value[0], 0.0), 1.0))
        if a.op == ops.MATH and a.mode & ops.CLAMP_BIT:
            return a
        if a.op == ops.SWIZZLE and a.mode == 3 and a.args[0].op == ops.IMAGE:
            return a  # an image's alpha is already in [0, 1]
        return self.op(ops.CLAMP, 0, (a, self.f(0.0), self.f(1.0)))

    def clamp(self, a, low, high):
        return self.op(ops.CLAMP, 0, (a, self.f(low), self.f(high)))

    def lerp(self, t, a, b):
        """(1 - t) a + t b of scalars."""
        if a is b or _is(t, 0.0):
            return a
        if _is(t, 1.0):
            return b
        if _is(a, 0.0) and _is(b, 1.0):
            return t
        if _is(a, 0.0):
            return self.mul(t, b)
        return self.op(ops.MIX_VALUE, 0, (t, a, b))

    # --- vectors and colours ------------------------------------------------

    def vmath(self, name, a, b=None, c=None, kind=VECTOR):
        if name in ops.VECTOR_VALUE_OPS:
            kind = FLOAT
        return self.op(ops.VECTOR_MATH, ops.vector_math_op(name), (a, b, c), kind=kind)

    def vadd(self, a, b, kind=COLOR):
        if _is(a, 0.0, 3):
            return b
        if _is(b, 0.0, 3):
            return a
        return self.vmath("ADD", a, b, kind=kind)

    def vmul(self, a, b, kind=COLOR):
        """Component-wise product (a scalar is a splat)."""
        if _is(a, 1.0, 3):
            return b
        if _is(b, 1.0, 3):
            return a
        if _is(a, 0.0, 3) or _is(b, 0.0, 3):
            return self.const((0.0, 0.0, 0.0), kind)
        return self.vmath("MULTIPLY", a, b, kind=kind)

    def vdiv(self, a, b, kind=COLOR):
        if _is(b, 1.0, 3):
            return a
        return self.vmath("DIVIDE", a, b, kind=kind)

    def vlerp(self, t, a, b, kind=COLOR):
        """(1 - t) a + t b, t a scalar."""
        if a is b or _is(t, 0.0):
            return a
        if _is(t, 1.0):
            return b
        if _is(a, 0.0, 3):
            return self.vmul(t, b, kind)
        return self.op(ops.MIX_VALUE, 1, (t, a, b), kind=kind)

    def swizzle(self, a, component):
        if a.kind == FLOAT:
            return a
        return self.op(ops.SWIZZLE, component, (a,))

    def pack(self, x, y, z, w=None, kind=VECTOR):
        return self.op(ops.PACK, 0, (x, y, z, w or self.f(0.0)), kind=kind)

    def luminance(self, a):
        if a.kind == FLOAT:
            return a
        return self.op(ops.RGB_TO_BW, 0, (a,))

    def average(self, a):
        if a.kind == FLOAT:
            return a
        third = 1.0 / 3.0
        return self.vmath("DOT_PRODUCT", a, self.const((third, third, third), VECTOR))


def _is(expr, x, components=1):
    return expr.is_const and all(c == x for c in expr.value[:components])


# --- folding: Cycles' definitions -------------------------------------------


def _safe_divide(a, b):
    return a / b if b != 0.0 else 0.0


def _safe_pow(a, b):
    if a < 0.0 and b != math.floor(b):
        return 0.0
    if a == 0.0 and b < 0.0:
        return 0.0
    return math.pow(a, b)


def _safe_log(a, b):
    if a <= 0.0 or b <= 0.0:
        return 0.0
    return _safe_divide(math.log(a), math.log(b))


def _safe_fmod(a, b):
    return math.fmod(a, b) if b != 0.0 else 0.0


def _wrap(value, high, low):
    span = high - low
    return value - span * math.floor((value - low) / span) if span != 0.0 else low


def _pingpong(a, b):
    if b == 0.0:
        return 0.0
    x = (a - b) / (b * 2.0)
    return abs((x - math.floor(x)) * b * 2.0 - b)


def _smoothmin(a, b, c):
    if c != 0.0:
        h = max(c - abs(a - b), 0.0) / c
        return min(a, b) - h * h * h * c * (1.0 / 6.0)
    return min(a, b)


def _sign(a):
    return 1.0 if a > 0.0 else (-1.0 if a < 0.0 else 0.0)


_MATH = {
    "ADD": lambda a, b, c: a + b,
    "SUBTRACT": lambda a, b, c: a - b,
    "MULTIPLY": lambda a, b, c: a * b,
    "DIVIDE": lambda a, b, c: _safe_divide(a, b),
    "MULTIPLY_ADD": lambda a, b, c: a * b + c,
    "POWER": lambda a, b, c: _safe_pow(a, b),
    "LOGARITHM": lambda a, b, c: _safe_log(a, b),
    "SQRT": lambda a, b, c: math.sqrt(a) if a > 0.0 else 0.0,
    "INVERSE_SQRT": lambda a, b, c: 1.0 / math.sqrt(a) if a > 0.0 else 0.0,
    "ABSOLUTE": lambda a, b, c: abs(a),
    "EXPONENT": lambda a, b, c: math.exp(a),
    "MINIMUM": lambda a, b, c: min(a, b),
    "MAXIMUM": lambda a, b, c: max(a, b),
    "LESS_THAN": lambda a, b, c: float(a < b),
    "GREATER_THAN": lambda a, b, c: float(a > b),
    "SIGN": lambda a, b, c: _sign(a),
    "COMPARE": lambda a, b, c: float(abs(a - b) <= max(c, 1e-5)),
    "SMOOTH_MIN": lambda a, b, c: _smoothmin(a, b, c),
    "SMOOTH_MAX": lambda a, b, c: -_smoothmin(-a, -b, c),
    "ROUND": lambda a, b, c: math.floor(a + 0.5),
    "FLOOR": lambda a, b, c: math.floor(a),
    "CEIL": lambda a, b, c: math.ceil(a),
    "TRUNC": lambda a, b, c: float(math.trunc(a)),
    "FRACT": lambda a, b, c: a - math.floor(a),
    "MODULO": lambda a, b, c: _safe_fmod(a, b),
    "FLOORED_MODULO": lambda a, b, c: a - math.floor(a / b) * b if b != 0.0 else 0.0,
    "WRAP": lambda a, b, c: _wrap(a, b, c),
    "SNAP": lambda a, b, c: math.floor(_safe_divide(a, b)) * b,
    "PINGPONG": lambda a, b, c: _pingpong(a, b),
    "SINE": lambda a, b, c: math.sin(a),
    "COSINE": lambda a, b, c: math.cos(a),
    "TANGENT": lambda a, b, c: math.tan(a),
    "ARCSINE": lambda a, b, c: math.asin(min(max(a, -1.0), 1.0)),
    "ARCCOSINE": lambda a, b, c: math.acos(min(max(a, -1.0), 1.0)),
    "ARCTANGENT": lambda a, b, c: math.atan(a),
    "ARCTAN2": lambda a, b, c: math.atan2(a, b),
    "SINH": lambda a, b, c: math.sinh(a),
    "COSH": lambda a, b, c: math.cosh(a),
    "TANH": lambda a, b, c: math.tanh(a),
    "RADIANS": lambda a, b, c: a * (math.pi / 180.0),
    "DEGREES": lambda a, b, c: a * (180.0 / math.pi),
}


def math_value(name, a, b=0.0, c=0.0):
    """Blender's Math node on floats (svm_math)."""
    return float(_MATH[name](a, b, c))


def _fold_math(mode, values, e):
    name = ops.MATH_OPS[mode & 0xFF]
    a, b, c = (0.0 if v is None else v[0] for v in values)
    result = math_value(name, a, b, c)
    if mode & ops.CLAMP_BIT:
        result = min(max(result, 0.0), 1.0)
    return splat(result)


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _normalize(a):
    length = math.sqrt(_dot(a, a))
    return tuple(c / length for c in a[:3]) if length != 0.0 else (0.0, 0.0, 0.0)


def _per(fn, *vectors):
    return tuple(fn(*cs) for cs in zip(*(v[:3] for v in vectors), strict=True))


def _refract(incident, normal, eta):
    k = 1.0 - eta * eta * (1.0 - _dot(normal, incident) ** 2)
    if k < 0.0:
        return (0.0, 0.0, 0.0)
    scale = eta * _dot(normal, incident) + math.sqrt(k)
    return tuple(eta * i - scale * n for i, n in zip(incident[:3], normal, strict=True))


def vector_math_value(name, a, b, c, scale):
    """Blender's Vector Math node (svm_vector_math): a vector (3-tuple) or a float."""
    if name == "ADD":
        return _per(lambda x, y: x + y, a, b)
    if name == "SUBTRACT":
        return _per(lambda x, y: x - y, a, b)
    if name == "MULTIPLY":
        return _per(lambda x, y: x * y, a, b)
    if name == "DIVIDE":
        return _per(_safe_divide, a, b)
    if name == "MULTIPLY_ADD":
        return _per(lambda x, y, z: x * y + z, a, b, c)
    if name == "CROSS_PRODUCT":
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    if name == "PROJECT":
        length = _dot(b, b)
        return tuple(x * _dot(a, b) / length for x in b[:3]) if length != 0.0 else (0.0,) * 3
    if name == "REFLECT":
        n = _normalize(b)
        d = _dot(n, a)
        return tuple(x - 2.0 * d * y for x, y in zip(a[:3], n, strict=True))
    if name == "REFRACT":
        return _refract(a, _normalize(b), scale)
    if name == "FACEFORWARD":
        return tuple(a[:3]) if _dot(c, b) < 0.0 else tuple(-x for x in a[:3])
    if name == "DOT_PRODUCT":
        return _dot(a, b)
    if name == "DISTANCE":
        return math.dist(a[:3], b[:3])
    if name == "LENGTH":
        return math.sqrt(_dot(a, a))
    if name == "SCALE":
        return tuple(x * scale for x in a[:3])
    if name == "NORMALIZE":
        return _normalize(a)
    if name == "ABSOLUTE":
        return _per(abs, a)
    if name == "POWER":
        return _per(_safe_pow, a, b)
    if name == "SIGN":
        return _per(_sign, a)
    if name == "MINIMUM":
        return _per(min, a, b)
    if name == "MAXIMUM":
        return _per(max, a, b)
    if name == "FLOOR":
        return _per(math.floor, a)
    if name == "CEIL":
        return _per(math.ceil, a)
    if name == "FRACTION":
        return _per(lambda x: x - math.floor(x), a)
    if name == "MODULO":
        return _per(_safe_fmod, a, b)
    if name == "WRAP":
        return _per(_wrap, a, b, c)
    if name == "SNAP":
        return _per(lambda x, y: math.floor(_safe_divide(x, y)) * y, a, b)
    if name == "SINE":
        return _per(math.sin, a)
    if name == "COSINE":
        return _per(math.cos, a)
    if name == "TANGENT":
        return _per(math.tan, a)
    if name == "ROUND":
        return _per(lambda x: math.floor(x + 0.5), a)
    raise ValueError(name)


def _fold_vector_math(mode, values, e):
    name = ops.VECTOR_MATH_OPS[mode]
    a, b, c = ((0.0,) * 4 if v is None else v for v in values)
    # The float operand (Scale, or REFRACT's IOR) rides in b (SCALE) or c (REFRACT).
    scale = b[0] if name == "SCALE" else c[0]
    result = vector_math_value(name, a, b, c, scale)
    if isinstance(result, float):
        return splat(result)
    return (*result, 0.0)


# Colour models (intern/cycles/util/color.h).


def rgb_to_hsv(rgb):
    r, g, b = rgb[:3]
    cmax = max(r, g, b)
    cmin = min(r, g, b)
    delta = cmax - cmin
    v = cmax
    s = delta / cmax if cmax != 0.0 else 0.0
    if s == 0.0:
        return (0.0, 0.0, v)
    cr, cg, cb = ((cmax - x) / delta for x in (r, g, b))
    if r == cmax:
        h = cb - cg
    elif g == cmax:
        h = 2.0 + cr - cb
    else:
        h = 4.0 + cg - cr
    h /= 6.0
    if h < 0.0:
        h += 1.0
    return (h, s, v)


def hsv_to_rgb(hsv):
    h, s, v = hsv[:3]
    if s == 0.0:
        return (v, v, v)
    if h == 1.0:
        h = 0.0
    h *= 6.0
    i = math.floor(h)
    f = h - i
    p = v * (1.0 - s)
    q = v * (1.0 - s * f)
    t = v * (1.0 - s * (1.0 - f))
    return [(v, t, p), (q, v, p), (p, v, t), (p, q, v), (t, p, v), (v, p, q)][min(int(i), 5) % 6]


def rgb_to_hsl(rgb):
    r, g, b = rgb[:3]
    cmax = max(r, g, b)
    cmin = min(r, g, b)
    lightness = min(1.0, (cmax + cmin) / 2.0)
    if cmax == cmin:
        return (0.0, 0.0, lightness)
    d = cmax - cmin
    s = d / (2.0 - cmax - cmin) if lightness > 0.5 else d / (cmax + cmin)
    if cmax == r:
        h = (g - b) / d + (6.0 if g < b else 0.0)
    elif cmax == g:
        h = (b - r) / d + 2.0
    else:
        h = (r - g) / d + 4.0
    return (h / 6.0, s, lightness)


def hsl_to_rgb(hsl):
    h, s, lightness = hsl[:3]
    nr = min(max(abs(h * 6.0 - 3.0) - 1.0, 0.0), 1.0)
    ng = min(max(2.0 - abs(h * 6.0 - 2.0), 0.0), 1.0)
    nb = min(max(2.0 - abs(h * 6.0 - 4.0), 0.0), 1.0)
    chroma = (1.0 - abs(2.0 * lightness - 1.0)) * s
    return tuple((n - 0.5) * chroma + lightness for n in (nr, ng, nb))


def _lerp3(a, b, t):
    return tuple((1.0 - t) * x + t * y for x, y in zip(a[:3], b[:3], strict=True))


def _dodge(c1, c2, t):
    out = []
    for x, y in zip(c1, c2, strict=True):
        if x != 0.0:
            tmp = 1.0 - t * y
            x = 1.0 if tmp <= 0.0 else min(x / tmp, 1.0)
        out.append(x)
    return tuple(out)


def _burn(c1, c2, t):
    out = []
    for x, y in zip(c1, c2, strict=True):
        tmp = (1.0 - t) + t * y
        if tmp <= 0.0:
            out.append(0.0)
        else:
            out.append(min(max(1.0 - (1.0 - x) / tmp, 0.0), 1.0))
    return tuple(out)


def _hue(c1, c2, t):
    hsv2 = rgb_to_hsv(c2)
    if hsv2[1] == 0.0:
        return tuple(c1)
    hsv = rgb_to_hsv(c1)
    return _lerp3(c1, hsv_to_rgb((hsv2[0], hsv[1], hsv[2])), t)


def _saturation(c1, c2, t):
    hsv = rgb_to_hsv(c1)
    if hsv[1] == 0.0:
        return tuple(c1)
    hsv2 = rgb_to_hsv(c2)
    return hsv_to_rgb((hsv[0], (1.0 - t) * hsv[1] + t * hsv2[1], hsv[2]))


def _value(c1, c2, t):
    hsv = rgb_to_hsv(c1)
    hsv2 = rgb_to_hsv(c2)
    return hsv_to_rgb((hsv[0], hsv[1], (1.0 - t) * hsv[2] + t * hsv2[2]))


def _color(c1, c2, t):
    hsv2 = rgb_to_hsv(c2)
    if hsv2[1] == 0.0:
        return tuple(c1)
    hsv = rgb_to_hsv(c1)
    return _lerp3(c1, hsv_to_rgb((hsv2[0], hsv2[1], hsv[2])), t)


def _overlay(c1, c2, t):
    tm = 1.0 - t
    return tuple(
        x * (tm + 2.0 * t * y) if x < 0.5 else 1.0 - (tm + 2.0 * t * (1.0 - y)) * (1.0 - x)
        for x, y in zip(c1, c2, strict=True)
    )


def _soft_light(c1, c2, t):
    tm = 1.0 - t
    out = []
    for x, y in zip(c1, c2, strict=True):
        screen = 1.0 - (1.0 - y) * (1.0 - x)
        out.append(tm * x + t * ((1.0 - x) * y * x + x * screen))
    return tuple(out)


_BLENDS = {
    "MIX": lambda c1, c2, t: _lerp3(c1, c2, t),
    "ADD": lambda c1, c2, t: tuple(x + t * y for x, y in zip(c1, c2, strict=True)),
    "MULTIPLY": lambda c1, c2, t: tuple(
        x * ((1.0 - t) + t * y) for x, y in zip(c1, c2, strict=True)
    ),
    "SCREEN": lambda c1, c2, t: tuple(
        1.0 - ((1.0 - t) + t * (1.0 - y)) * (1.0 - x) for x, y in zip(c1, c2, strict=True)
    ),
    "OVERLAY": _overlay,
    "SUBTRACT": lambda c1, c2, t: tuple(x - t * y for x, y in zip(c1, c2, strict=True)),
    "DIVIDE": lambda c1, c2, t: tuple(
        (1.0 - t) * x + t * x / y if y != 0.0 else x for x, y in zip(c1, c2, strict=True)
    ),
    "DIFFERENCE": lambda c1, c2, t: _lerp3(c1, _per(lambda x, y: abs(x - y), c1, c2), t),
    "EXCLUSION": lambda c1, c2, t: tuple(
        max(v, 0.0) for v in _lerp3(c1, _per(lambda x, y: x + y - 2.0 * x * y, c1, c2), t)
    ),
    "DARKEN": lambda c1, c2, t: _lerp3(c1, _per(min, c1, c2), t),
    "LIGHTEN": lambda c1, c2, t: _lerp3(c1, _per(max, c1, c2), t),
    "DODGE": _dodge,
    "BURN": _burn,
    "HUE": _hue,
    "SATURATION": _saturation,
    "VALUE": _value,
    "COLOR": _color,
    "SOFT_LIGHT": _soft_light,
    "LINEAR_LIGHT": lambda c1, c2, t: tuple(
        x + t * (2.0 * y - 1.0) for x, y in zip(c1, c2, strict=True)
    ),
}


def mix_value(blend, t, c1, c2, clamp=False):
    """Blender's MixRGB (svm_mix) of rgb tuples with factor t (already clamped)."""
    result = tuple(_BLENDS[blend](tuple(c1[:3]), tuple(c2[:3]), t))
    if clamp:
        result = tuple(min(max(x, 0.0), 1.0) for x in result)
    return result


def _fold_mix(mode, values, e):
    t, c1, c2 = values
    rgb = mix_value(ops.MIX_BLEND[mode & 0xFF], t[0], c1, c2, bool(mode & ops.CLAMP_BIT))
    return (*rgb, c1[3])


def _fold_mix_value(mode, values, e):
    t, a, b = values
    if mode == 2:
        return tuple((1.0 - ti) * x + ti * y for ti, x, y in zip(t, a, b, strict=True))
    return tuple((1.0 - t[0]) * x + t[0] * y for x, y in zip(a, b, strict=True))


def _fold_separate(mode, values, e):
    (a,) = values
    if mode == 1:
        return (*rgb_to_hsv(a), a[3])
    if mode == 2:
        return (*rgb_to_hsl(a), a[3])
    return a


def _fold_combine(mode, values, e):
    xyz = tuple(v[0] for v in values[:3])
    if mode == 1:
        xyz = hsv_to_rgb(xyz)
    elif mode == 2:
        xyz = hsl_to_rgb(xyz)
    return (*xyz, 1.0)


def hue_sat_value(hue, saturation, value, factor, color):
    """svm_node_hsv."""
    h, s, v = rgb_to_hsv(color)
    h = math.fmod(h + hue + 0.5, 1.0)
    s = min(max(s * saturation, 0.0), 1.0)
    v *= value
    rgb = hsv_to_rgb((h, s, v))
    return tuple(
        max(factor * x + (1.0 - factor) * c, 0.0) for x, c in zip(rgb, color[:3], strict=True)
    )


def _fold_hue_sat(mode, values, e):
    hue, sat, val, fac, color = values
    return (*hue_sat_value(hue[0], sat[0], val[0], fac[0], color), color[3])


def _fold_gamma(mode, values, e):
    color, gamma = values
    g = gamma[0]
    return (*(math.pow(c, g) if c > 0.0 else c for c in color[:3]), color[3])


def _fold_bright_contrast(mode, values, e):
    color, bright, contrast = values
    a = 1.0 + contrast[0]
    b = bright[0] - contrast[0] * 0.5
    return (*(max(a * c + b, 0.0) for c in color[:3]), color[3])


def _fold_invert(mode, values, e):
    fac, color = values
    f = fac[0]
    return (*(f * (1.0 - c) + (1.0 - f) * c for c in color[:3]), color[3])


def _fold_clamp(mode, values, e):
    value, low, high = (v[0] for v in values)
    if mode == 1 and low > high:
        low, high = high, low
    return splat(min(max(value, low), high))


def _smoothstep(edge0, edge1, x):
    if x <= edge0:
        return 0.0
    if x >= edge1:
        return 1.0
    t = (x - edge0) / (edge1 - edge0)
    return t * t * (3.0 - 2.0 * t)


def _smootherstep(edge0, edge1, x):
    t = min(max(_safe_divide(x - edge0, edge1 - edge0), 0.0), 1.0)
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def map_range_value(kind, value, from_min, from_max, to_min, to_max, steps, clamp):
    """svm_node_map_range for floats."""
    if kind in ("LINEAR", "STEPPED"):
        factor = (value - from_min) / (from_max - from_min) if from_max != from_min else 0.0
        if kind == "STEPPED":
            factor = math.floor(factor * (steps + 1.0)) / steps if steps > 0.0 else 0.0
    elif kind == "SMOOTHSTEP":
        factor = (
            1.0 - _smoothstep(from_max, from_min, value)
            if from_min > from_max
            else _smoothstep(from_min, from_max, value)
        )
    else:
        factor = (
            1.0 - _smootherstep(from_max, from_min, value)
            if from_min > from_max
            else _smootherstep(from_min, from_max, value)
        )
    result = to_min + factor * (to_max - to_min)
    if clamp and kind in ("LINEAR", "STEPPED"):
        result = min(max(result, min(to_min, to_max)), max(to_min, to_max))
    return result


def _fold_map_range(mode, values, e):
    value, bounds, steps = values
    kind = ops.MAP_RANGE_MODES[mode & 0xFF]
    result = map_range_value(
        kind, value[0], *bounds, 0.0 if steps is None else steps[0], bool(mode & ops.CLAMP_BIT)
    )
    return splat(result)


def ramp_value(mode, table, t):
    """A COLOR_RAMP constants block `[n, (pos, r, g, b, a) x n]` at `t`: constant
    and linear exactly as Blender's ColorBand; ease, cardinal and b-spline are not
    folded (they stay program ops)."""
    n = int(table[0])
    stops = [table[1 + 5 * i : 6 + 5 * i] for i in range(n)]
    if t <= stops[0][0]:
        return tuple(stops[0][1:])
    if t >= stops[-1][0]:
        return tuple(stops[-1][1:])
    for left, right in itertools.pairwise(stops):
        if left[0] <= t <= right[0]:
            if mode == 0:
                return tuple((right if t == right[0] else left)[1:])
            span = right[0] - left[0]
            f = (t - left[0]) / span if span > 0.0 else 0.0
            if mode == 2:
                f = f * f * (3.0 - 2.0 * f)
            return tuple((1.0 - f) * a + f * b for a, b in zip(left[1:], right[1:], strict=True))
    return tuple(stops[-1][1:])


def _fold_color_ramp(mode, values, e):
    if mode not in (0, 1, 2):
        raise ValueError("not folded")
    return ramp_value(mode, e, values[0][0])


def curve_lookup(table, column, x, extrapolate=True):
    """Linear lookup of column `column` of a CURVE table (4 x 256 over [0, 1]),
    beyond it extended along the end slopes (Cycles' `extrapolate`) or held."""
    size = ops.CURVE_TABLE_SIZE
    if not extrapolate:
        x = min(max(x, 0.0), 1.0)
    samples = table[column * size : (column + 1) * size]
    position = x * (size - 1)
    if position < 0.0:
        return samples[0] + (samples[1] - samples[0]) * position
    if position > size - 1:
        return samples[-1] + (samples[-1] - samples[-2]) * (position - (size - 1))
    i = min(int(position), size - 2)
    f = position - i
    return (1.0 - f) * samples[i] + f * samples[i + 1]


def _fold_curve(mode, values, e):
    fac, value = values
    f = fac[0]
    extrapolate = bool(mode & ops.CLAMP_BIT)  # the bit means "extrapolate" here
    kind = mode & 0xFF
    if kind == 1:
        return splat((1.0 - f) * value[0] + f * curve_lookup(e, 0, value[0], extrapolate))
    if kind == 0:
        out = tuple(
            curve_lookup(e, 1 + k, curve_lookup(e, 0, value[k], extrapolate), extrapolate)
            for k in range(3)
        )
        return (*((1.0 - f) * v + f * o for v, o in zip(value, out, strict=False)), value[3])
    if kind == 2:
        out = tuple(curve_lookup(e, k, value[k], extrapolate) for k in range(3))
        return (*((1.0 - f) * v + f * o for v, o in zip(value, out, strict=False)), 0.0)
    raise ValueError("not folded")


def euler_matrix(rx, ry, rz):
    """Blender's Euler XYZ rotation as rows of a 3x3 matrix (R = Rz Ry Rx)."""
    cx, sx = math.cos(rx), math.sin(rx)
    cy, sy = math.cos(ry), math.sin(ry)
    cz, sz = math.cos(rz), math.sin(rz)
    return (
        (cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz),
        (cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz),
        (-sy, cy * sx, cy * cx),
    )


def _apply(m, v):
    return tuple(_dot(row, v) for row in m)


def _apply_transposed(m, v):
    return tuple(sum(m[r][c] * v[r] for r in range(3)) for c in range(3))


def mapping_value(kind, vector, location, rotation, scale):
    """svm_mapping."""
    m = euler_matrix(*rotation[:3])
    if kind == "POINT":
        return tuple(
            x + t
            for x, t in zip(
                _apply(m, _per(lambda a, b: a * b, vector, scale)), location, strict=False
            )
        )
    if kind == "TEXTURE":
        moved = _per(lambda a, b: a - b, vector, location)
        return _per(_safe_divide, _apply_transposed(m, moved), scale)
    if kind == "VECTOR":
        return _apply(m, _per(lambda a, b: a * b, vector, scale))
    return _normalize(_apply(m, _per(_safe_divide, vector, scale)))


def _fold_mapping(mode, values, e):
    vector, location, rotation, scale = values
    return (*mapping_value(ops.MAPPING_TYPES[mode], vector, location, rotation, scale), 0.0)


def _fold_swizzle(mode, values, e):
    return splat(values[0][mode])


def _fold_pack(mode, values, e):
    return tuple(v[0] for v in values)


def _fold_rgb_to_bw(mode, values, e):
    r, g, b = values[0][:3]
    return splat(0.2126 * r + 0.7152 * g + 0.0722 * b)


def checker_value(point, scale):
    """svm_checker of `point` times `scale`: 1 for colour 1, 0 for colour 2."""
    cells = [abs(math.floor((c * scale + 0.000001) * 0.999999)) for c in point[:3]]
    return 1.0 if (cells[0] % 2 == cells[1] % 2) == (cells[2] % 2 == 1) else 0.0


def _fold_checker(mode, values, e):
    vector, color1, color2, scale = values
    first = checker_value(vector, scale[0]) == 1.0
    return (*(color1 if first else color2)[:3], 1.0 if first else 0.0)


def gradient_value(kind, point):
    """svm_gradient, saturated as svm_node_tex_gradient does."""
    x, y, z = point[:3]
    if kind == "LINEAR":
        f = x
    elif kind == "QUADRATIC":
        f = max(x, 0.0) ** 2
    elif kind == "EASING":
        r = min(max(x, 0.0), 1.0)
        t = r * r
        f = 3.0 * t - 2.0 * t * r
    elif kind == "DIAGONAL":
        f = (x + y) * 0.5
    elif kind == "RADIAL":
        f = math.atan2(y, x) / (2.0 * math.pi) + 0.5
    else:
        r = max(0.999999 - math.sqrt(x * x + y * y + z * z), 0.0)
        f = r * r if kind == "QUADRATIC_SPHERE" else r
    return min(max(f, 0.0), 1.0)


def _fold_gradient(mode, values, e):
    return splat(gradient_value(ops.GRADIENT_TYPES[mode], values[0]))


def fresnel_dielectric_cos(cosi, eta):
    """Cycles' fresnel_dielectric_cos."""
    c = abs(cosi)
    g = eta * eta - 1.0 + c * c
    if g > 0.0:
        g = math.sqrt(g)
        a = (g - c) / (g + c)
        b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
        return 0.5 * a * a * (1.0 + b * b)
    return 1.0


def fresnel_value(ior, cosi, backfacing):
    """The Fresnel node (svm_node_fresnel)."""
    eta = max(ior, 1e-5)
    return fresnel_dielectric_cos(cosi, 1.0 / eta if backfacing else eta)


def layer_weight_value(kind, blend, cosi, backfacing):
    """The Layer Weight node (svm_node_layer_weight): kind 0 Fresnel, 1 Facing."""
    if kind == 0:
        eta = max(1.0 - blend, 1e-5)
        return fresnel_dielectric_cos(cosi, eta if backfacing else 1.0 / eta)
    f = abs(cosi)
    if blend != 0.5:
        blend = min(max(blend, 0.0), 1.0 - 1e-5)
        blend = 2.0 * blend if blend < 0.5 else 0.5 / (1.0 - blend)
        f = f**blend
    return 1.0 - f


_FOLD = {
    ops.CHECKER: _fold_checker,
    ops.GRADIENT: _fold_gradient,
    ops.MATH: _fold_math,
    ops.VECTOR_MATH: _fold_vector_math,
    ops.MIX: _fold_mix,
    ops.MIX_VALUE: _fold_mix_value,
    ops.SEPARATE: _fold_separate,
    ops.SWIZZLE: _fold_swizzle,
    ops.COMBINE: _fold_combine,
    ops.HUE_SAT: _fold_hue_sat,
    ops.GAMMA: _fold_gamma,
    ops.BRIGHT_CONTRAST: _fold_bright_contrast,
    ops.INVERT: _fold_invert,
    ops.CLAMP: _fold_clamp,
    ops.MAP_RANGE: _fold_map_range,
    ops.COLOR_RAMP: _fold_color_ramp,
    ops.CURVE: _fold_curve,
    ops.MAPPING: _fold_mapping,
    ops.PACK: _fold_pack,
    ops.RGB_TO_BW: _fold_rgb_to_bw,
}


def evaluate(expr, leaf):
    """The value of `expr` with every op that cannot fold replaced by `leaf(expr)`
    (four floats): the constant stand-in of a program that cannot run."""
    memo = {}

    def value(node):
        if node is None:
            return None
        if node.is_const:
            return node.value
        key = id(node)
        if key not in memo:
            args = [value(a) for a in node.args]
            folded = None
            if node.op in _FOLD:
                try:
                    folded = _FOLD[node.op](node.mode, args, node.e)
                except (ValueError, OverflowError, ZeroDivisionError):
                    folded = None
            memo[key] = folded if folded is not None else leaf(node)
        return memo[key]

    return value(expr)
