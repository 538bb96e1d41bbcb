"""The shader program's numbers (docs/notes/shader_program.md): op codes, input
modes, mode bits and the operation lists, all defined by native/src/shader/ops.h
and read from the native module (whitted_native.OPS, OP_NUMBERS, MATH_OPS,
VECTOR_MATH_OPS, MIX_BLEND) the first time one is asked for, as attributes of this
module (ops.IMAGE, ops.IN_UV, ops.CLAMP_BIT, ops.OP_NAMES, ...): the add-on imports
before that module loads (native.py). Defined here: the lists of the other ops'
modes, which only the compiler names.

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
    }


def __getattr__(name):
    numbers = _native_numbers()
    if name not in numbers:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return numbers[name]


# Vector Math operations whose result is a value (in all four components).
VECTOR_VALUE_OPS = frozenset({"DOT_PRODUCT", "DISTANCE", "LENGTH"})

MAP_RANGE_MODES = ("LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP")
RAMP_MODES = ("CONSTANT", "LINEAR", "EASE", "CARDINAL", "B_SPLINE")
MAPPING_TYPES = ("POINT", "TEXTURE", "VECTOR", "NORMAL")
IMAGE_PROJECTIONS = ("FLAT", "BOX", "SPHERE", "TUBE")
ENVIRONMENT_PROJECTIONS = ("EQUIRECTANGULAR", "MIRROR_BALL")
GRADIENT_TYPES = (
    "LINEAR",
    "QUADRATIC",
    "EASING",
    "DIAGONAL",
    "SPHERICAL",
    "QUADRATIC_SPHERE",
    "RADIAL",
)
NORMAL_MAP_SPACES = ("TANGENT", "OBJECT", "WORLD")

# NOISE's mode: dimensions - 1 in bits 0-1, the fractal (NOISE_TYPES) in bits 2-4,
# NOISE_NORMALIZE and NOISE_COLOR.
NOISE_TYPES = (
    "FBM",
    "MULTIFRACTAL",
    "HYBRID_MULTIFRACTAL",
    "RIDGED_MULTIFRACTAL",
    "HETERO_TERRAIN",
)
DIMENSIONS = ("1D", "2D", "3D", "4D")
# VORONOI's mode: dimensions - 1 in bits 0-1, feature in bits 2-4, metric in bits
# 5-6, VORONOI_INTEGER_HASH, NOISE_NORMALIZE, and the output (VORONOI_OUTPUTS) in bits
# 9-10.
VORONOI_FEATURES = ("F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS")
VORONOI_METRICS = ("EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI")
VORONOI_OUTPUTS = ("DISTANCE", "COLOR", "POSITION")  # DISTANCE: also Radius
# WAVE's mode: type in bit 0, direction in bits 1-2, profile in bits 3-4.
WAVE_TYPES = ("BANDS", "RINGS")
WAVE_BANDS_DIRECTIONS = ("X", "Y", "Z", "DIAGONAL")
WAVE_RINGS_DIRECTIONS = ("X", "Y", "Z", "SPHERICAL")
WAVE_PROFILES = ("SIN", "SAW", "TRI")


def math_op(identifier):
    return _native_numbers()["MATH_OPS"].index(identifier)


def vector_math_op(identifier):
    return _native_numbers()["VECTOR_MATH_OPS"].index(identifier)


def mix_blend(identifier):
    return _native_numbers()["MIX_BLEND"].index(identifier)
