"""The shader program's numbers (docs/notes/shader_program.md): op codes, input
modes, the operation lists and the other ops' mode fields, all defined by
native/src/shader/ops.h and read from the native module (whitted_native.OPS,
OP_NUMBERS, MATH_OPS, VECTOR_MATH_OPS, MIX_BLEND, OP_MODES, TABLE_OPS) the first time one is asked
for: the op codes and numbers as attributes of this module (ops.IMAGE, ops.IN_UV,
ops.OP_NAMES, ...), the modes through pack() and unpack(). The add-on imports before
that module loads (native.py).

The operation lists are Blender 5.0's enums in their order; Blender 3.4's are
subsets of them, so an operation is always looked up by its identifier.
"""

from functools import cache

from ...native import load_native


@cache
def _native_numbers():
    # Read once: the native module's tables do not change while it is loaded.
    native = load_native()
    names = [name for name, _, _ in native.OPS]
    return {
        **{name: code for code, name in enumerate(names)},  # CONST (0) is the compiler's own
        **native.OP_NUMBERS,
        "OP_NAMES": dict(enumerate(names)),
        "MATH_OPS": tuple(native.MATH_OPS),
        "VECTOR_MATH_OPS": tuple(native.VECTOR_MATH_OPS),
        "MIX_BLEND": tuple(native.MIX_BLEND),
        # The ops whose `e` is a table the program keeps in its constants.
        "TABLE_OPS": frozenset(native.TABLE_OPS),
    }


def __getattr__(name):
    if name.startswith("__"):  # Python's and Blender's probes (__addon_enabled__, ...)
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    numbers = _native_numbers()
    if name not in numbers:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return numbers[name]


# Vector Math operations whose result is a value (in all four components).
VECTOR_VALUE_OPS = frozenset({"DOT_PRODUCT", "DISTANCE", "LENGTH"})


@cache
def _mode_fields():
    # op name -> {field: (shift, width, count, Blender's identifiers or ())}, read once.
    return {
        op: {name: (shift, width, count, tuple(ids)) for name, shift, width, count, ids in fields}
        for op, fields in load_native().OP_MODES.items()
    }


def _fields_of(op):
    fields = _mode_fields().get(op)
    if fields is None:
        raise ValueError(f"{op} has no mode fields (whitted_native.OP_MODES)")
    return fields


def pack(op, **values):
    """The mode of op `op` (its name: "VORONOI") from its fields by keyword, as
    native/src/shader/ops.h lays them out (whitted_native.OP_MODES): a choice by Blender's
    identifier, a flag by a bool, a number by an int; a field not given is 0. ValueError
    for a value the field does not take, TypeError for a field the op lacks or two given
    in the same bits (WAVE's bands_direction and rings_direction)."""
    fields = _fields_of(op)
    mode = taken = 0
    for name, value in values.items():
        if name not in fields:
            raise TypeError(f"{op} has no mode field {name!r} (it has {', '.join(fields)})")
        shift, width, count, identifiers = fields[name]
        if identifiers:
            if value not in identifiers:
                raise ValueError(f"{op} {name}: {value!r} is not one of {', '.join(identifiers)}")
            number = identifiers.index(value)
        elif width == 1:
            if not isinstance(value, bool):
                raise TypeError(f"{op} {name}: a flag is a bool, not {value!r}")
            number = int(value)
        else:
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < count:
                raise ValueError(f"{op} {name}: {value!r} is not an int in [0, {count})")
            number = value
        mask = ((1 << width) - 1) << shift
        if taken & mask:
            raise TypeError(f"{op} {name}: its bits are another field's given")
        taken |= mask
        mode |= number << shift
    return mode


def unpack(op, mode):
    """{field: value} of op `op`'s `mode` as pack() takes them (identifiers, bools, ints)."""
    out = {}
    for name, (shift, width, _, identifiers) in _fields_of(op).items():
        number = mode >> shift & ((1 << width) - 1)
        if identifiers:
            out[name] = identifiers[number] if number < len(identifiers) else number
        else:
            out[name] = bool(number) if width == 1 else number
    return out
