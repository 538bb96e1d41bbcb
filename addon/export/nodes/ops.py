"""The shader program's numbers (docs/notes/shader_program.md): op codes, input
modes and the operation lists, mirrored by native/src/shader/ops.h.

The operation lists are Blender 5.0's enums in their order; Blender 3.4's are
subsets of them, so an operation is always looked up by its identifier.
"""

UNUSED = 0xFFFFFFFF  # a register operand the op does not read

# Op codes (the `op` column of a code row). CONST is the compiler's own: a
# constant lives in a register before the first instruction and emits no row.
CONST = 0
INPUT = 1
MATH = 2
VECTOR_MATH = 3
MIX = 4
MIX_VALUE = 5
SEPARATE = 6
SWIZZLE = 7
COMBINE = 8
HUE_SAT = 9
GAMMA = 10
BRIGHT_CONTRAST = 11
INVERT = 12
CLAMP = 13
MAP_RANGE = 14
COLOR_RAMP = 15
CURVE = 16
MAPPING = 17
IMAGE = 18
ENVIRONMENT = 19
CHECKER = 20
GRADIENT = 21
NOISE = 22
VORONOI = 23
WAVE = 24
MAGIC = 25
BRICK = 26
FRESNEL = 27
LAYER_WEIGHT = 28
NORMAL_MAP = 29
PACK = 30
RGB_TO_BW = 31
BUMP = 32

OP_NAMES = {
    value: name
    for name, value in dict(globals()).items()
    if isinstance(value, int) and name.isupper() and name not in ("UNUSED",)
}

# Mode bit of MATH, MIX and MAP_RANGE: clamp the result to [0, 1] (MAP_RANGE: to
# the target range).
CLAMP_BIT = 1 << 8

# INPUT modes.
IN_POSITION = 0
IN_NORMAL = 1
IN_TRUE_NORMAL = 2
IN_INCOMING = 3
IN_GENERATED = 4
IN_OBJECT = 5
IN_CAMERA = 6
IN_WINDOW = 7
IN_REFLECTION = 8
IN_BACKFACING = 9
IN_OBJECT_NORMAL = 10
IN_IS_CAMERA_RAY = 16
IN_IS_SHADOW_RAY = 17
IN_IS_REFLECTION_RAY = 18
IN_IS_TRANSMISSION_RAY = 19
IN_RAY_DEPTH = 20
IN_IS_DIFFUSE_RAY = 21
IN_IS_SINGULAR_RAY = 22
IN_OBJECT_LOCATION = 32
IN_OBJECT_RANDOM = 33
IN_OBJECT_INDEX = 34
IN_OBJECT_COLOR = 35
IN_UV = 64  # + UV set index
IN_ATTRIBUTE = 128  # + corner attribute index
# Either bit on a mode: that input at the hit moved by the first or second bump offset
# (the heights a BUMP differentiates).
IN_BUMP_X = 1 << 8
IN_BUMP_Y = 1 << 9

MATH_OPS = (
    "ADD",
    "SUBTRACT",
    "MULTIPLY",
    "DIVIDE",
    "MULTIPLY_ADD",
    "POWER",
    "LOGARITHM",
    "SQRT",
    "INVERSE_SQRT",
    "ABSOLUTE",
    "EXPONENT",
    "MINIMUM",
    "MAXIMUM",
    "LESS_THAN",
    "GREATER_THAN",
    "SIGN",
    "COMPARE",
    "SMOOTH_MIN",
    "SMOOTH_MAX",
    "ROUND",
    "FLOOR",
    "CEIL",
    "TRUNC",
    "FRACT",
    "MODULO",
    "FLOORED_MODULO",
    "WRAP",
    "SNAP",
    "PINGPONG",
    "SINE",
    "COSINE",
    "TANGENT",
    "ARCSINE",
    "ARCCOSINE",
    "ARCTANGENT",
    "ARCTAN2",
    "SINH",
    "COSH",
    "TANH",
    "RADIANS",
    "DEGREES",
)

VECTOR_MATH_OPS = (
    "ADD",
    "SUBTRACT",
    "MULTIPLY",
    "DIVIDE",
    "MULTIPLY_ADD",
    "CROSS_PRODUCT",
    "PROJECT",
    "REFLECT",
    "REFRACT",
    "FACEFORWARD",
    "DOT_PRODUCT",
    "DISTANCE",
    "LENGTH",
    "SCALE",
    "NORMALIZE",
    "ABSOLUTE",
    "POWER",
    "SIGN",
    "MINIMUM",
    "MAXIMUM",
    "ROUND",  # Blender 5.1 and later
    "FLOOR",
    "CEIL",
    "FRACTION",
    "MODULO",
    "WRAP",
    "SNAP",
    "SINE",
    "COSINE",
    "TANGENT",
)

# Vector Math operations whose result is a value (in all four components).
VECTOR_VALUE_OPS = frozenset({"DOT_PRODUCT", "DISTANCE", "LENGTH"})

MIX_BLEND = (
    "MIX",
    "DARKEN",
    "MULTIPLY",
    "BURN",
    "LIGHTEN",
    "SCREEN",
    "DODGE",
    "ADD",
    "OVERLAY",
    "SOFT_LIGHT",
    "LINEAR_LIGHT",
    "DIFFERENCE",
    "EXCLUSION",
    "SUBTRACT",
    "DIVIDE",
    "HUE",
    "SATURATION",
    "COLOR",
    "VALUE",
)

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
NOISE_NORMALIZE = 1 << 8
NOISE_COLOR = 1 << 9
DIMENSIONS = ("1D", "2D", "3D", "4D")
# VORONOI's mode: dimensions - 1 in bits 0-1, feature in bits 2-4, metric in bits
# 5-6, VORONOI_INTEGER_HASH, NOISE_NORMALIZE, and the output (VORONOI_OUTPUTS) in bits
# 9-10.
VORONOI_INTEGER_HASH = 1 << 7  # 2D-4D cells hashed by their integers (Blender 5.0)
VORONOI_FEATURES = ("F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS")
VORONOI_METRICS = ("EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI")
VORONOI_OUTPUTS = ("DISTANCE", "COLOR", "POSITION")  # DISTANCE: also Radius
# WAVE's mode: type in bit 0, direction in bits 1-2, profile in bits 3-4.
WAVE_TYPES = ("BANDS", "RINGS")
WAVE_BANDS_DIRECTIONS = ("X", "Y", "Z", "DIAGONAL")
WAVE_RINGS_DIRECTIONS = ("X", "Y", "Z", "SPHERICAL")
WAVE_PROFILES = ("SIN", "SAW", "TRI")

# The CURVE table: rows over [0, 1].
CURVE_TABLE_SIZE = 256


def math_op(identifier):
    return MATH_OPS.index(identifier)


def vector_math_op(identifier):
    return VECTOR_MATH_OPS.index(identifier)


def mix_blend(identifier):
    return MIX_BLEND.index(identifier)
