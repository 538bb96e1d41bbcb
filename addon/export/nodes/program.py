"""Lowered Exprs as the native program's arrays (docs/notes/shader_program.md):
one register per distinct Expr (constants filled in before the first
instruction), one code row per op in dependency order, the COLOR_RAMP and CURVE
tables in `constants`, the images in `textures`.
"""

from dataclasses import dataclass

import numpy as np

from . import ops

# Material fields in the order their outputs are emitted.
FIELD_ORDER = (
    "alpha",
    "normal",
    "diffuse",
    "specular",
    "shininess",
    "reflectivity",
    "transmissivity",
    "ior",
    "emission",
    "coat_specular",
    "coat_reflectivity",
    "coat_shininess",
    "coat_ior",
    "coat_normal",
    "diffuse_roughness",
    "roughness",
    "coat_roughness",
)


@dataclass(frozen=True, eq=False)
class ProgramData:
    code: np.ndarray  # uint32[K, 8]: (op, mode, out, a, b, c, d, e)
    registers: np.ndarray  # float32[R, 4]: every register before the first instruction
    constants: np.ndarray  # float32[C]
    textures: tuple  # texture names; an IMAGE/ENVIRONMENT op's e indexes this

    def __eq__(self, other):
        return (
            isinstance(other, ProgramData)
            and self.textures == other.textures
            and all(
                np.array_equal(getattr(self, name), getattr(other, name))
                for name in ("code", "registers", "constants")
            )
        )

    def __hash__(self):
        return hash((self.code.tobytes(), self.registers.tobytes(), self.textures))

    def describe(self):
        """One line per instruction, for tests and debugging."""
        lines = []
        for row in self.code:
            op, mode, out, *args = (int(x) for x in row)
            operands = ", ".join("-" if a == ops.UNUSED else str(a) for a in args)
            lines.append(f"r{out} = {ops.OP_NAMES.get(op, op)}[{mode}]({operands})")
        return "\n".join(lines)


def emit(fields):
    """(ProgramData, {field: register}) computing the non-constant `fields`
    ({field: Expr}); (None, {}) when all are constant."""
    varying = [(name, fields[name]) for name in FIELD_ORDER if name in fields]
    varying = [(name, expr) for name, expr in varying if not expr.is_const]
    if not varying:
        return None, {}
    registers = {}  # id(Expr) -> index
    initial = []
    code = []
    constants = []
    constant_offsets = {}
    textures = []

    def register(expr):
        key = id(expr)
        if key in registers:
            return registers[key]
        if expr.is_const:
            registers[key] = len(initial)
            initial.append(expr.value)
            return registers[key]
        operands = [ops.UNUSED if a is None else register(a) for a in expr.args]
        out = len(initial)
        initial.append((0.0, 0.0, 0.0, 0.0))
        registers[key] = out
        e = ops.UNUSED
        if len(operands) > 4:
            e = operands[4]
        elif expr.op in (ops.IMAGE, ops.ENVIRONMENT):
            if expr.e not in textures:
                textures.append(expr.e)
            e = textures.index(expr.e)
        elif expr.op in (ops.COLOR_RAMP, ops.CURVE):
            if expr.e not in constant_offsets:
                constant_offsets[expr.e] = len(constants)
                constants.extend(expr.e)
            e = constant_offsets[expr.e]
        elif expr.op == ops.NORMAL_MAP:
            e = expr.e[1]
        row = [expr.op, expr.mode, out, *operands[:4]]
        row += [ops.UNUSED] * (7 - len(row))
        code.append((*row, e))
        return out

    outputs = {name: register(expr) for name, expr in varying}
    program = ProgramData(
        code=np.array(code, dtype=np.uint32).reshape(-1, 8),
        registers=np.array(initial, dtype=np.float32).reshape(-1, 4),
        constants=np.array(constants, dtype=np.float32),
        textures=tuple(textures),
    )
    return program, outputs


# Register operands of each op (HUE_SAT's fifth is in e).
ARITY = {
    ops.MATH: 3,
    ops.VECTOR_MATH: 3,
    ops.MIX: 3,
    ops.MIX_VALUE: 3,
    ops.SEPARATE: 1,
    ops.SWIZZLE: 1,
    ops.COMBINE: 3,
    ops.HUE_SAT: 4,
    ops.GAMMA: 2,
    ops.BRIGHT_CONTRAST: 3,
    ops.INVERT: 2,
    ops.CLAMP: 3,
    ops.MAP_RANGE: 3,
    ops.MAPPING: 4,
    ops.PACK: 4,
    ops.RGB_TO_BW: 1,
    ops.CHECKER: 4,
    ops.GRADIENT: 1,
    ops.FRESNEL: 2,
    ops.LAYER_WEIGHT: 2,
}


def run(program, inputs, textures=None):
    """Execute `program` in Python on one hit: `inputs` maps an INPUT mode to its four
    floats; `textures` a texture name to a function(vector, mode) -> rgba. A
    reference for tests; ops without a Python definition raise."""
    from .ir import _FOLD, fresnel_value, layer_weight_value, splat

    registers = [tuple(float(x) for x in r) for r in program.registers]
    for row in program.code:
        op, mode, out, a, b, c, d, e = (int(x) for x in row)
        operands = [None if i == ops.UNUSED else registers[i] for i in (a, b, c, d)]
        operands = operands[: ARITY.get(op, 4)]
        if op == ops.INPUT:
            value = tuple(inputs[mode])
        elif op in (ops.IMAGE, ops.ENVIRONMENT):
            value = tuple(textures[program.textures[e]](operands[0], mode))
        elif op in (ops.FRESNEL, ops.LAYER_WEIGHT):
            incoming, normal = inputs[ops.IN_INCOMING], inputs[ops.IN_NORMAL]
            cosi = sum(i * n for i, n in zip(incoming[:3], normal[:3], strict=True))
            backfacing = inputs.get(ops.IN_BACKFACING, (0.0,))[0] != 0.0
            if op == ops.FRESNEL:
                value = splat(fresnel_value(operands[0][0], cosi, backfacing))
            else:
                value = splat(layer_weight_value(mode, operands[0][0], cosi, backfacing))
        elif op in (ops.COLOR_RAMP, ops.CURVE):
            payload = _payload(program.constants, op, e)
            value = _FOLD[op](mode, operands[: 1 if op == ops.COLOR_RAMP else 2], payload)
        else:
            if e != ops.UNUSED and op == ops.HUE_SAT:
                operands.append(registers[e])
            value = _FOLD[op](mode, operands, None)
        registers[out] = tuple(value)
    return registers


def _payload(constants, op, offset):
    if op == ops.COLOR_RAMP:
        count = int(constants[offset])
        return tuple(float(x) for x in constants[offset : offset + 1 + 5 * count])
    return tuple(float(x) for x in constants[offset : offset + 4 * ops.CURVE_TABLE_SIZE])
