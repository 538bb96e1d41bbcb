// The vocabulary of a shader program (docs/notes/shader_program.md): its op codes, its
// input modes, and Blender's operation enums of the Math, Vector Math and Mix nodes.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace whitted {

// An instruction's op (column 0 of a program's code).
enum class Op : uint32_t {
  kInput = 1,
  kMath = 2,
  kVectorMath = 3,
  kMix = 4,
  kMixValue = 5,
  kSeparate = 6,
  kSwizzle = 7,
  kCombine = 8,
  kHueSat = 9,
  kGamma = 10,
  kBrightContrast = 11,
  kInvert = 12,
  kClamp = 13,
  kMapRange = 14,
  kColorRamp = 15,
  kCurve = 16,
  kMapping = 17,
  kImage = 18,
  kEnvironment = 19,
  kChecker = 20,
  kGradient = 21,
  kNoise = 22,  // 22..26: the procedural textures (shader/procedural.h)
  kVoronoi = 23,
  kWave = 24,
  kMagic = 25,
  kBrick = 26,
  kFresnel = 27,
  kLayerWeight = 28,
  kNormalMap = 29,
  kPack = 30,
  kRgbToBw = 31,
  kBump = 32,
};

// What every layer knows of an op, defined here once: its name (the Python compiler's
// constant: addon/export/nodes/ops.py reads this table, whitted_native.OPS), its register operands
// (columns a, b, c, d, then e), and whether it reads the hit (its inputs, images, shading normal or
// bump offsets). An op that does not is a function of its operands alone: the compiler folds it
// when they are constants (Program::fold), with this same code, so a folded graph and a run one
// give the same floats. Indexed by the op code; 0 is the compiler's CONST, a register
// filled before the first instruction, never a row.
struct OpInfo {
  std::string_view name;
  uint32_t operands;
  bool reads_hit;
};
inline constexpr std::array<OpInfo, static_cast<size_t>(Op::kBump) + 1> kOpTable = {{
    {"CONST", 0, false},
    {"INPUT", 0, true},
    {"MATH", 3, false},
    {"VECTOR_MATH", 3, false},
    {"MIX", 3, false},
    {"MIX_VALUE", 3, false},
    {"SEPARATE", 1, false},
    {"SWIZZLE", 1, false},
    {"COMBINE", 3, false},
    {"HUE_SAT", 5, false},  // hue, saturation, value, factor, colour (in e)
    {"GAMMA", 2, false},
    {"BRIGHT_CONTRAST", 3, false},
    {"INVERT", 2, false},
    {"CLAMP", 3, false},
    {"MAP_RANGE", 3, false},   // value, the four bounds packed, steps
    {"COLOR_RAMP", 1, false},  // e: its stops' offset in the constants
    {"CURVE", 2, false},       // e: its table's offset in the constants
    {"MAPPING", 4, false},
    {"IMAGE", 2, true},
    {"ENVIRONMENT", 1, true},
    {"CHECKER", 4, false},
    {"GRADIENT", 1, false},
    {"NOISE", 3, false},
    {"VORONOI", 3, false},
    {"WAVE", 3, false},
    {"MAGIC", 3, false},
    {"BRICK", 3, false},
    {"FRESNEL", 2, true},
    {"LAYER_WEIGHT", 2, true},
    {"NORMAL_MAP", 2, true},
    {"PACK", 4, false},
    {"RGB_TO_BW", 1, false},
    {"BUMP", 5, true},
}};

// The modes of op INPUT: what a hit offers a program.
enum Input : uint32_t {
  kInputPosition = 0,
  kInputNormal = 1,
  kInputTrueNormal = 2,
  kInputIncoming = 3,
  kInputGenerated = 4,
  kInputObject = 5,
  kInputCamera = 6,
  kInputWindow = 7,
  kInputReflection = 8,
  kInputBackfacing = 9,
  kInputObjectSpaceNormal = 10,  // the shading normal in object space (unit, incoming side)
  kInputIsCameraRay = 16,
  kInputIsShadowRay = 17,
  kInputIsReflectionRay = 18,
  kInputIsTransmissionRay = 19,
  kInputRayDepth = 20,
  kInputIsDiffuseRay = 21,
  kInputIsSingularRay = 22,
  kInputObjectLocation = 32,
  kInputObjectRandom = 33,
  kInputObjectIndex = 34,
  kInputObjectColor = 35,
  kInputUvSet = 64,       // + k, k < 64
  kInputAttribute = 128,  // + k, k < 128
  kInputPublicEnd = 256,
  // Either bit on a public mode: that input at the hit moved by the first or the second
  // bump offset (ProgramHit::bump_dx, bump_dy), for the height a Bump node differentiates.
  kInputBumpX = 1u << 8,
  kInputBumpY = 1u << 9,
  // Not selectable by INPUT: what NORMAL_MAP reads in tangent space, asked of the hit
  // through the same table (Program::inputs).
  kInputTangent = 1u << 16,       // + k: tangent set k, object space xyz, bitangent sign w
  kInputObjectNormal = 1u << 17,  // the unnormalised interpolated normal in object space
};

// Mode bits of some ops.
inline constexpr uint32_t kClampBit = 1u << 8;  // MATH, MIX, MAP_RANGE: clamp; CURVE: extrapolate
inline constexpr uint32_t kNoiseNormalizeBit = 1u << 8;      // NOISE, VORONOI: normalise to [0, 1]
inline constexpr uint32_t kNoiseColorBit = 1u << 9;          // NOISE: compute the Color output too
inline constexpr uint32_t kVoronoiIntegerHashBit = 1u << 7;  // VORONOI: Blender 5.0's cell hash
// A register operand the op does not read.
inline constexpr uint32_t kUnusedOperand = 0xFFFFFFFFu;
// Entries per curve of a CURVE table.
inline constexpr uint32_t kCurveTable = 256;

// The named numbers of a program's code besides its op codes, defined here once with
// the names the Python compiler gives them (whitted_native.OP_NUMBERS, from which
// addon/export/nodes/ops.py takes its constants): the INPUT modes, the mode bits, the
// unused operand and the CURVE table's size.
struct OpNumber {
  std::string_view name;
  uint32_t value;
};
inline constexpr std::array<OpNumber, 32> kOpNumbers = {{
    {"IN_POSITION", kInputPosition},
    {"IN_NORMAL", kInputNormal},
    {"IN_TRUE_NORMAL", kInputTrueNormal},
    {"IN_INCOMING", kInputIncoming},
    {"IN_GENERATED", kInputGenerated},
    {"IN_OBJECT", kInputObject},
    {"IN_CAMERA", kInputCamera},
    {"IN_WINDOW", kInputWindow},
    {"IN_REFLECTION", kInputReflection},
    {"IN_BACKFACING", kInputBackfacing},
    {"IN_OBJECT_NORMAL", kInputObjectSpaceNormal},
    {"IN_IS_CAMERA_RAY", kInputIsCameraRay},
    {"IN_IS_SHADOW_RAY", kInputIsShadowRay},
    {"IN_IS_REFLECTION_RAY", kInputIsReflectionRay},
    {"IN_IS_TRANSMISSION_RAY", kInputIsTransmissionRay},
    {"IN_RAY_DEPTH", kInputRayDepth},
    {"IN_IS_DIFFUSE_RAY", kInputIsDiffuseRay},
    {"IN_IS_SINGULAR_RAY", kInputIsSingularRay},
    {"IN_OBJECT_LOCATION", kInputObjectLocation},
    {"IN_OBJECT_RANDOM", kInputObjectRandom},
    {"IN_OBJECT_INDEX", kInputObjectIndex},
    {"IN_OBJECT_COLOR", kInputObjectColor},
    {"IN_UV", kInputUvSet},
    {"IN_ATTRIBUTE", kInputAttribute},
    {"IN_BUMP_X", kInputBumpX},
    {"IN_BUMP_Y", kInputBumpY},
    {"CLAMP_BIT", kClampBit},
    {"NOISE_NORMALIZE", kNoiseNormalizeBit},
    {"NOISE_COLOR", kNoiseColorBit},
    {"VORONOI_INTEGER_HASH", kVoronoiIntegerHashBit},
    {"UNUSED", kUnusedOperand},
    {"CURVE_TABLE_SIZE", kCurveTable},
}};

// ShaderNodeMath.operation, in Blender 5.0's order (3.4 lacks FLOORED_MODULO).
enum class MathOp : uint32_t {
  kAdd,
  kSubtract,
  kMultiply,
  kDivide,
  kMultiplyAdd,
  kPower,
  kLogarithm,
  kSqrt,
  kInverseSqrt,
  kAbsolute,
  kExponent,
  kMinimum,
  kMaximum,
  kLessThan,
  kGreaterThan,
  kSign,
  kCompare,
  kSmoothMin,
  kSmoothMax,
  kRound,
  kFloor,
  kCeil,
  kTrunc,
  kFract,
  kModulo,
  kFlooredModulo,
  kWrap,
  kSnap,
  kPingpong,
  kSine,
  kCosine,
  kTangent,
  kArcsine,
  kArccosine,
  kArctangent,
  kArctan2,
  kSinh,
  kCosh,
  kTanh,
  kRadians,
  kDegrees,
};
inline constexpr std::array<std::string_view, 41> kMathOpNames = {
    "ADD",        "SUBTRACT",       "MULTIPLY",     "DIVIDE",    "MULTIPLY_ADD", "POWER",
    "LOGARITHM",  "SQRT",           "INVERSE_SQRT", "ABSOLUTE",  "EXPONENT",     "MINIMUM",
    "MAXIMUM",    "LESS_THAN",      "GREATER_THAN", "SIGN",      "COMPARE",      "SMOOTH_MIN",
    "SMOOTH_MAX", "ROUND",          "FLOOR",        "CEIL",      "TRUNC",        "FRACT",
    "MODULO",     "FLOORED_MODULO", "WRAP",         "SNAP",      "PINGPONG",     "SINE",
    "COSINE",     "TANGENT",        "ARCSINE",      "ARCCOSINE", "ARCTANGENT",   "ARCTAN2",
    "SINH",       "COSH",           "TANH",         "RADIANS",   "DEGREES"};
static_assert(kMathOpNames.size() == static_cast<size_t>(MathOp::kDegrees) + 1);

// ShaderNodeVectorMath.operation, in Blender 5.2's order (3.4 lacks POWER and SIGN, 5.0 ROUND).
enum class VectorMathOp : uint32_t {
  kAdd,
  kSubtract,
  kMultiply,
  kDivide,
  kMultiplyAdd,
  kCrossProduct,
  kProject,
  kReflect,
  kRefract,
  kFaceforward,
  kDotProduct,
  kDistance,
  kLength,
  kScale,
  kNormalize,
  kAbsolute,
  kPower,
  kSign,
  kMinimum,
  kMaximum,
  kRound,  // Blender 5.1 and later
  kFloor,
  kCeil,
  kFraction,
  kModulo,
  kWrap,
  kSnap,
  kSine,
  kCosine,
  kTangent,
};
inline constexpr std::array<std::string_view, 30> kVectorMathOpNames = {
    "ADD",     "SUBTRACT", "MULTIPLY",  "DIVIDE",      "MULTIPLY_ADD", "CROSS_PRODUCT",
    "PROJECT", "REFLECT",  "REFRACT",   "FACEFORWARD", "DOT_PRODUCT",  "DISTANCE",
    "LENGTH",  "SCALE",    "NORMALIZE", "ABSOLUTE",    "POWER",        "SIGN",
    "MINIMUM", "MAXIMUM",  "ROUND",     "FLOOR",       "CEIL",         "FRACTION",
    "MODULO",  "WRAP",     "SNAP",      "SINE",        "COSINE",       "TANGENT"};
static_assert(kVectorMathOpNames.size() == static_cast<size_t>(VectorMathOp::kTangent) + 1);

// ShaderNodeMixRGB.blend_type (and ShaderNodeMix's), in Blender 5.0's order (3.4 lacks
// EXCLUSION).
enum class MixBlend : uint32_t {
  kMix,
  kDarken,
  kMultiply,
  kBurn,
  kLighten,
  kScreen,
  kDodge,
  kAdd,
  kOverlay,
  kSoftLight,
  kLinearLight,
  kDifference,
  kExclusion,
  kSubtract,
  kDivide,
  kHue,
  kSaturation,
  kColor,
  kValue,
};
inline constexpr std::array<std::string_view, 19> kMixBlendNames = {
    "MIX",    "DARKEN",  "MULTIPLY",   "BURN",         "LIGHTEN",    "SCREEN",    "DODGE",
    "ADD",    "OVERLAY", "SOFT_LIGHT", "LINEAR_LIGHT", "DIFFERENCE", "EXCLUSION", "SUBTRACT",
    "DIVIDE", "HUE",     "SATURATION", "COLOR",        "VALUE"};
static_assert(kMixBlendNames.size() == static_cast<size_t>(MixBlend::kValue) + 1);

}  // namespace whitted
