"""Lowered Exprs as the native program's arrays (docs/notes/shader_program.md):
one register per distinct Expr (constants filled in before the first
instruction), one code row per op in dependency order, the COLOR_RAMP and CURVE
tables in `constants`, the images in `textures`.
"""

from dataclasses import dataclass
from functools import cache

import numpy as np

from ...native import load_native
from . import ops


@cache
def material_fields():
    """The fields a material's program may drive as (name, components: 3 a colour or a
    normal, 1 a value), in the order emit() gives their outputs: the native table
    (native/src/scene/material.h, whitted_native.MATERIAL_FIELDS), read once the first
    time it is asked for (the add-on imports before the module loads)."""
    return tuple((name, components) for name, components in load_native().MATERIAL_FIELDS)


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

    def native(self, native):
        """This program as a whitted_native.Program (ValueError for one it refuses)."""
        return native.Program(self.code, self.registers, self.constants, list(self.textures))

    def describe(self):
        """One line per instruction, for tests and debugging."""
        lines = []
        for row in self.code:
            op, mode, out, *args = (int(x) for x in row)
            operands = ", ".join("-" if a == ops.UNUSED else str(a) for a in args)
            lines.append(f"r{out} = {ops.OP_NAMES.get(op, op)}[{mode}]({operands})")
        return "\n".join(lines)


def emit(fields, keep_constant=False):
    """(ProgramData, {field: register}) computing the non-constant `fields`
    ({field: Expr}, fields of material_fields()); (None, {}) when all are constant.
    With `keep_constant`, constant fields are outputs too (their registers hold them)
    and a program is always made: a displacement's, which a vertex reads from it."""
    order = [name for name, _ in material_fields()]
    unknown = fields.keys() - set(order)
    if unknown:
        raise ValueError(f"not material fields: {sorted(unknown)}")
    varying = [(name, fields[name]) for name in order if name in fields]
    varying = [(name, expr) for name, expr in varying if keep_constant or not expr.is_const]
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
        elif expr.op in ops.TABLE_OPS:
            if expr.e not in constant_offsets:
                constant_offsets[expr.e] = len(constants)
                constants.extend(expr.e)
            e = constant_offsets[expr.e]
        elif expr.op in (ops.NORMAL_MAP, ops.UV_TANGENT):
            e = expr.e[1]  # ("set", the UV set whose tangents it reads)
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
