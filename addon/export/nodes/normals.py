"""The Bump node: a normal from the height the texture graph gives; the Displacement
node and a material output's Displacement (output_displacement), which Cycles' default
method (Bump Only) shades as such a bump (displacement_bump) and its two other methods
add to the mesh's vertices.

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


def linked_normal(c, out):
    """The value linked to the Normal input of `out.node` (a Bump, a Displacement, an
    Ambient Occlusion), or None where it is unlinked."""
    socket = next((s for s in out.node.inputs if s.name == "Normal"), None)
    if socket is None or source(socket, out.scope)[0] is None:
        return None
    return c.value(socket, out.scope, VECTOR)


def bump(c, out):
    """ShaderNodeBump's Normal: BUMP of the height at the hit and at both offsets."""
    node = out.node
    # Unlinked, the shading normal: a displacement's bumped one where there is one.
    normal = linked_normal(c, out)
    normal = normal if normal is not None else c.shading_normal
    unbent = normal if normal is not None else c.hit(ops.IN_NORMAL)
    if c.world:
        c.warn(node, "a Bump in a world has no surface; it gives the normal unchanged")
        return unbent
    strength = c.input(out, ("Strength",), FLOAT)
    distance = c.input(out, ("Distance",), FLOAT)
    height = c.input(out, ("Height",), FLOAT)
    if height is None or height.is_const or (strength.is_const and strength.value[0] <= 0.0):
        return unbent
    bumped = _bumped(c.b, height, strength, distance, normal, node.invert)
    return unbent if bumped is None else bumped


def _bumped(b, height, strength, distance, normal, invert):
    """BUMP of `height` (an Expr) at the hit and at both offsets, bending `normal` (None:
    the hit's); None where the height does not change along the surface."""
    at_x = moved(b, height, ops.IN_BUMP_X)
    at_y = moved(b, height, ops.IN_BUMP_Y)
    if at_x is height and at_y is height:
        return None
    zero = b.f(0.0)
    packed = b.op(ops.PACK, 0, (strength, distance, zero, zero), kind=VECTOR)
    mode = ops.pack("BUMP", invert=invert)
    return b.op(ops.BUMP, mode, (packed, normal, height, at_x, at_y), kind=VECTOR)


def displacement(c, out):
    """ShaderNodeDisplacement's Displacement, as Cycles' svm_node_displacement gives it:
    its Normal (unlinked: the shading normal) times (Height - Midlevel) * Scale, a world
    vector. In Object space (Blender's default) Cycles carries the normal into object
    space, scales it there and back to the world, which stretches its length along the
    normal by |M^T n| (IN_OBJECT_NORMAL_SCALE, M the object's linear part): kept here, and
    the direction kept along the normal, which is all a bump reads of it (under
    non-uniform scale Cycles' vector also leans off the normal)."""
    node = out.node
    b = c.b
    normal = linked_normal(c, out)
    if normal is None:
        normal = c.hit(ops.IN_NORMAL)
    height = c.input(out, ("Height",), FLOAT)
    midlevel = c.input(out, ("Midlevel",), FLOAT)
    scale = c.input(out, ("Scale",), FLOAT)
    amount = b.mul(b.sub(height, midlevel), scale)
    if node.space == "OBJECT":
        amount = b.mul(amount, c.hit(ops.IN_OBJECT_NORMAL_SCALE, FLOAT))
    return b.vmul(amount, normal, VECTOR)


def output_displacement(c, output_node):
    """The world vector a material output's linked Displacement gives (the Displacement
    node's, a Vector Displacement's or any vector linked there), lowered once for both of
    its uses: the bump of Bump Only and Displacement and Bump (displacement_bump), and
    the vertices Displacement Only and Displacement and Bump move (export/material.py,
    evaluated at each vertex by the native displace). None where it is unlinked."""
    socket = output_node.inputs.get("Displacement")
    if socket is None or source(socket, ())[0] is None:
        return None
    return c.value(socket, (), VECTOR)


def displacement_bump(c, output_node):
    """The shading normal a material output's linked Displacement gives under Cycles'
    Bump Only method (and the bump of Displacement and Bump), as Cycles' shader graph
    builds it (bump_from_displacement): a Bump of Distance 1 and Strength 1 whose height
    is the displacement along the shading normal, at the hit and at both offsets. None
    without a linked Displacement, or where it does not change along the surface."""
    vector = output_displacement(c, output_node)
    if vector is None:
        return None
    b = c.b
    height = b.vmath("DOT_PRODUCT", vector, c.hit(ops.IN_NORMAL))
    if height.is_const:
        return None
    one = b.f(1.0)
    return _bumped(b, height, one, one, None, False)
