"""The Bump node: a normal from the height the texture graph gives.

As Cycles does (its SVM compiler's bump states), the height sub-graph is lowered
three times: at the hit, and with every input that moves with the point read at
the hit moved by each of two small offsets along the surface (INPUT modes with
IN_BUMP_X / IN_BUMP_Y; the native side picks the offsets, see
docs/notes/shader_program.md). The BUMP op turns the three heights into the
displaced surface's normal.
"""

from . import ops
from .graph import source
from .ir import FLOAT, VECTOR

# Inputs that depend on where on the surface the hit is; the rest (normals, the view,
# Light Path, Object Info) stay as they are at the offsets, as in Cycles.
_MOVING = ("IN_POSITION", "IN_GENERATED", "IN_OBJECT", "IN_CAMERA", "IN_WINDOW")


def _moves(mode):
    moving = any(mode == getattr(ops, name) for name in _MOVING)
    return moving or ops.IN_UV <= mode < ops.IN_ATTRIBUTE + ops.ATTRIBUTES


def moved(b, expr, bit, memo=None):
    """`expr` with every input that moves with the point read at bump offset `bit`
    (IN_BUMP_X or IN_BUMP_Y); `expr` itself when none of its inputs moves."""
    memo = {} if memo is None else memo
    key = id(expr)
    if key in memo:
        return memo[key]
    if expr.is_const:
        result = expr
    elif expr.op == ops.INPUT:
        result = b.op(ops.INPUT, expr.mode | bit, (), kind=expr.kind) if _moves(expr.mode) else expr
    else:
        args = tuple(None if a is None else moved(b, a, bit, memo) for a in expr.args)
        unchanged = all(x is y for x, y in zip(args, expr.args, strict=True))
        result = expr if unchanged else b.op(expr.op, expr.mode, args, e=expr.e, kind=expr.kind)
    memo[key] = result
    return result


def bump(c, out):
    """ShaderNodeBump's Normal: BUMP of the height at the hit and at both offsets."""
    node = out.node
    normal = None
    socket = next((s for s in node.inputs if s.name == "Normal"), None)
    if socket is not None and source(socket, out.scope)[0] is not None:
        normal = c.value(socket, out.scope, VECTOR)
    unbent = normal if normal is not None else c.hit(ops.IN_NORMAL)
    if c.world:
        c.warn(node, "a Bump in a world has no surface; it gives the normal unchanged")
        return unbent
    strength = c.input(out, ("Strength",), FLOAT)
    distance = c.input(out, ("Distance",), FLOAT)
    height = c.input(out, ("Height",), FLOAT)
    if height is None or height.is_const or (strength.is_const and strength.value[0] <= 0.0):
        return unbent
    b = c.b
    at_x = moved(b, height, ops.IN_BUMP_X)
    at_y = moved(b, height, ops.IN_BUMP_Y)
    if at_x is height and at_y is height:
        return unbent  # a height that does not change along the surface
    zero = b.f(0.0)
    packed = b.op(ops.PACK, 0, (strength, distance, zero, zero), kind=VECTOR)
    mode = ops.pack("BUMP", invert=node.invert)
    return b.op(ops.BUMP, mode, (packed, normal, height, at_x, at_y), kind=VECTOR)
