"""The compiler's expressions: one `Expr` per value of the lowered graph, made by a
`Builder` that folds constants and shares equal sub-expressions.

Every value is four floats, as a register is: a scalar in all four components,
a vector in xyz (w 0), a colour in xyz with alpha in w. An op whose inputs are
all constant is computed when it is made, by the native program's own code
(`fold`), so a constant sub-graph never reaches the program. Ops that read the
hit (INPUT, IMAGE, ...) never fold.
"""

import math

from ...native import load_native
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
        if all(a is None or a.is_const for a in args):
            value = fold(op, mode, [None if a is None else a.value for a in args], e)
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
        mode = ops.pack("MATH", operation=name, clamp=clamp)
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
        if a.op == ops.MATH and ops.unpack("MATH", a.mode)["clamp"]:
            return a
        alpha = a.op == ops.SWIZZLE and ops.unpack("SWIZZLE", a.mode)["component"] == 3
        if alpha and a.args[0].op == ops.IMAGE:
            return a  # an image's alpha (w) is already in [0, 1]
        return self.clamp(a, 0.0, 1.0)

    def clamp(self, a, low, high):
        mode = ops.pack("CLAMP", clamp_type="MINMAX")
        return self.op(ops.CLAMP, mode, (a, self.f(low), self.f(high)))

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
        return self.op(ops.MIX_VALUE, ops.pack("MIX_VALUE", factor_mode="FLOAT"), (t, a, b))

    # --- vectors and colours ------------------------------------------------

    def vmath(self, name, a, b=None, c=None, kind=VECTOR):
        if name in ops.VECTOR_VALUE_OPS:
            kind = FLOAT
        mode = ops.pack("VECTOR_MATH", operation=name)
        return self.op(ops.VECTOR_MATH, mode, (a, b, c), kind=kind)

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
        mode = ops.pack("MIX_VALUE", factor_mode="UNIFORM")
        return self.op(ops.MIX_VALUE, mode, (t, a, b), kind=kind)

    def swizzle(self, a, component):
        if a.kind == FLOAT:
            return a
        return self.op(ops.SWIZZLE, ops.pack("SWIZZLE", component=component), (a,))

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


def fold(op, mode, values, e=None):
    """The four floats of `op` on constant operand `values` (four floats each, or None),
    computed by the native program's own code (whitted_native.fold_op: one definition of
    each node's maths, in the program's float32), so a folded graph gives what running it
    would. None for an op that reads the hit (INPUT, IMAGE, FRESNEL, ...)."""
    table = e if op in ops.TABLE_OPS else ()
    return load_native().fold_op(op, mode, values, table)


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
            folded = fold(node.op, node.mode, [value(a) for a in node.args], node.e)
            memo[key] = folded if folded is not None else leaf(node)
        return memo[key]

    return value(expr)
