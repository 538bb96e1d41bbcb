// The vocabulary of a shader program (docs/notes/shader_program.md): its op codes, its
// input modes, and Blender's operation enums of the Math, Vector Math and Mix nodes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
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
  kSky = 33,
  kBlackbody = 34,
  kWhiteNoise = 35,
  kWavelength = 36,
  kVectorRotate = 37,
  kLightFalloff = 38,
  kWireframe = 39,
  kAmbientOcclusion = 40,
  kBevel = 41,
  kUvTangent = 42,
  kGabor = 43,
  kIes = 44,
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
inline constexpr std::array<OpInfo, static_cast<size_t>(Op::kIes) + 1> kOpTable = {{
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
    {"SKY", 1, false},        // a direction; e: its table's offset in the constants (shader/sky.h)
    {"BLACKBODY", 1, false},  // a temperature in kelvin (shader/blackbody.h)
    {"WHITE_NOISE", 2, false},    // a vector, W (shader/procedural.h white_noise)
    {"WAVELENGTH", 1, false},     // a wavelength in nanometres (shader/wavelength.h)
    {"VECTOR_ROTATE", 4, false},  // vector, centre, axis or Euler rotation, angle
    {"LIGHT_FALLOFF", 3, false},  // strength, smooth, the ray's length (IN_RAY_LENGTH)
    {"WIREFRAME", 5, false},      // size, the point, the triangle's three corners (IN_TRIANGLE)
    // Distance, the normal (unused: the shading normal); traces rays from the hit
    // (ProgramHit::rays).
    {"AMBIENT_OCCLUSION", 2, true},
    // Radius, the hit's point (IN_POSITION) and true normal (IN_TRUE_NORMAL), the Normal
    // input (unused: the shading normal); traces rays near the hit (ProgramHit::rays).
    {"BEVEL", 4, true},
    // e: a UV set. Its tangent (kInputTangent) carried to the world as a normal and made
    // perpendicular to the shading normal, as Cycles' Tangent node of a UV map.
    {"UV_TANGENT", 0, true},
    // Blender 4.3's Gabor Texture (shader/procedural.h gabor_op): the vector, scale,
    // frequency, anisotropy, and in e the orientation (2D: an angle, 3D: a direction).
    {"GABOR", 5, false},
    // The IES Texture (shader/ies.h): the lookup vector, Strength; e: the profile's table
    // offset in the constants.
    {"IES", 2, false},
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
  // |M^T n|, M the object's linear part, n the shading normal: how far a unit length along
  // the normal in object space reaches along it in the world (Cycles' object-space
  // Displacement node, dP = M normalize(M^T n) h, meets n at h |M^T n|).
  kInputObjectNormalScale = 11,
  // Cycles' radial tangent about the object's X, Y or Z axis (+ 0, 1, 2; the Tangent
  // node's Radial, and the Geometry node's Tangent about Z, every anisotropic lobe's
  // default): round the generated coordinates' centre, carried to the world as a normal
  // is and made perpendicular to the shading normal.
  kInputRadialTangent = 12,  // + axis, axis < 3
  kInputIsCameraRay = 16,
  kInputIsShadowRay = 17,
  kInputIsReflectionRay = 18,
  kInputIsTransmissionRay = 19,
  kInputRayDepth = 20,
  kInputIsDiffuseRay = 21,
  kInputIsSingularRay = 22,
  // Cycles' ray length at a surface: from where the ray starts (a camera ray at its near
  // clip distance) to the hit; 0 in the world.
  kInputRayLength = 23,
  // The instance's Object and Instancer attributes (Scene Instance::attributes), RGBA.
  kInputObjectAttribute = 24,  // + k, k < kObjectAttributes
  kInputObjectLocation = 32,
  kInputObjectRandom = 33,
  kInputObjectIndex = 34,
  kInputObjectColor = 35,
  // Inside a Volume object: its grid of role k (scene/volume_object.h GridRole) at the
  // point, a scalar in x, y and z; 0 elsewhere (the exporter reads them only there).
  kInputGrid = 36,  // + k, k < kGridRoles
  // Cycles' object_volume_density: a Volume object's VolumeObject::density_scale, 1
  // elsewhere.
  kInputVolumeDensity = 40,
  // Inside a Volume object: the temperature grid's voxel k of the eight its interpolation
  // weighs at the point, and that voxel's weight (scene/volume_object.h VolumeSample);
  // 0 elsewhere.
  kInputGridTemperatureVoxel = 41,  // + k, k < kGridVoxels
  kInputGridVoxelWeight = 49,       // + k, k < kGridVoxels
  // Corner k of the hit's triangle (world); (0, 0, 0) off a triangle (a curve, a point, a
  // medium), where the Wireframe node gives 0 as Cycles'.
  kInputTriangleVertex = 57,  // + k, k < 3
  kInputUvSet = 64,           // + k, k < 64
  kInputAttribute = 128,      // + k, k < 128
  kInputPublicEnd = 256,
  // Either bit on a public mode: that input at the hit moved by the first or the second
  // bump offset (ProgramHit::bump_dx, bump_dy), for the height a Bump node differentiates.
  kInputBumpX = 1u << 8,
  kInputBumpY = 1u << 9,
  // Not selectable by INPUT: what NORMAL_MAP and UV_TANGENT read, asked of the hit
  // through the same table (Program::inputs).
  kInputTangent = 1u << 16,       // + k: tangent set k, object space xyz, bitangent sign w
  kInputObjectNormal = 1u << 17,  // the unnormalised interpolated normal in object space
};

// The voxels a grid's trilinear interpolation weighs.
inline constexpr uint32_t kGridVoxels = 8;
static_assert(kInputGridVoxelWeight + kGridVoxels <= kInputTriangleVertex &&
              kInputTriangleVertex + 3 <= kInputUvSet);

// The per-instance attributes INPUT reaches (kInputObjectAttribute + k).
inline constexpr uint32_t kObjectAttributes = 8;
static_assert(kInputObjectAttribute + kObjectAttributes <= kInputObjectLocation);

// The UV sets and the attributes INPUT reaches (kInputUvSet + k, kInputAttribute + k).
inline constexpr uint32_t kUvSets = kInputAttribute - kInputUvSet;
inline constexpr uint32_t kAttributes = kInputPublicEnd - kInputAttribute;

// A register operand the op does not read.
inline constexpr uint32_t kUnusedOperand = 0xFFFFFFFFu;
// Entries per curve of a CURVE table.
inline constexpr uint32_t kCurveTable = 256;

// The named numbers of a program's code besides its op codes, defined here once with
// the names the Python compiler gives them (whitted_native.OP_NUMBERS, from which
// addon/export/nodes/ops.py takes its constants): the INPUT modes and how many UV sets and
// attributes they reach, the unused operand and the CURVE table's size. The other ops'
// modes are fields (kOpModes, below).
struct OpNumber {
  std::string_view name;
  uint32_t value;
};
inline constexpr std::array<OpNumber, 44> kOpNumbers = {{
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
    {"IN_OBJECT_NORMAL_SCALE", kInputObjectNormalScale},
    {"IN_RADIAL_TANGENT", kInputRadialTangent},
    {"IN_IS_CAMERA_RAY", kInputIsCameraRay},
    {"IN_IS_SHADOW_RAY", kInputIsShadowRay},
    {"IN_IS_REFLECTION_RAY", kInputIsReflectionRay},
    {"IN_IS_TRANSMISSION_RAY", kInputIsTransmissionRay},
    {"IN_RAY_DEPTH", kInputRayDepth},
    {"IN_IS_DIFFUSE_RAY", kInputIsDiffuseRay},
    {"IN_IS_SINGULAR_RAY", kInputIsSingularRay},
    {"IN_RAY_LENGTH", kInputRayLength},
    {"IN_OBJECT_ATTRIBUTE", kInputObjectAttribute},
    {"OBJECT_ATTRIBUTES", kObjectAttributes},
    {"IN_OBJECT_LOCATION", kInputObjectLocation},
    {"IN_OBJECT_RANDOM", kInputObjectRandom},
    {"IN_OBJECT_INDEX", kInputObjectIndex},
    {"IN_OBJECT_COLOR", kInputObjectColor},
    // kInputGrid + GridRole (scene/volume_object.h), by role.
    {"IN_GRID_DENSITY", kInputGrid},
    {"IN_GRID_COLOR", kInputGrid + 1},
    {"IN_GRID_TEMPERATURE", kInputGrid + 2},
    {"IN_GRID_FLAME", kInputGrid + 3},
    {"IN_VOLUME_DENSITY", kInputVolumeDensity},
    {"IN_GRID_TEMPERATURE_VOXEL", kInputGridTemperatureVoxel},
    {"IN_GRID_VOXEL_WEIGHT", kInputGridVoxelWeight},
    {"GRID_VOXELS", kGridVoxels},
    {"IN_TRIANGLE", kInputTriangleVertex},
    {"IN_UV", kInputUvSet},
    {"IN_ATTRIBUTE", kInputAttribute},
    {"IN_BUMP_X", kInputBumpX},
    {"IN_BUMP_Y", kInputBumpY},
    {"UV_SETS", kUvSets},
    {"ATTRIBUTES", kAttributes},
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

// The mode word of the other ops: fields of bits, each a choice among Blender's
// identifiers (value k the k-th), a number or a flag; an op without fields takes mode 0
// only. Defined here once: the decoders (program.cpp, procedural.cpp) read each field
// through its constant below, the program's check (Program::Program) through kOpModes,
// and the Python compiler packs modes from the same table (whitted_native.OP_MODES;
// addon/export/nodes/ops.py pack()).
struct ModeField {
  std::string_view name;  // the keyword ops.pack() takes: Blender's property name where one is
  uint32_t shift;
  uint32_t width;
  uint32_t count;                                 // the values it may take, 0 .. count - 1
  std::span<const std::string_view> identifiers;  // a choice's; empty: a number or a flag

  constexpr uint32_t mask() const { return ((1u << width) - 1u) << shift; }
  // The field's value in `mode`.
  constexpr uint32_t in(uint32_t mode) const { return (mode & mask()) >> shift; }
  constexpr bool on(uint32_t mode) const { return (mode & mask()) != 0; }
};

constexpr ModeField choice(std::string_view name, uint32_t shift, uint32_t width,
                           std::span<const std::string_view> identifiers) {
  return {name, shift, width, static_cast<uint32_t>(identifiers.size()), identifiers};
}
constexpr ModeField number(std::string_view name, uint32_t shift, uint32_t width, uint32_t count) {
  return {name, shift, width, count, {}};
}
constexpr ModeField flag(std::string_view name, uint32_t shift) {
  return {name, shift, 1, 2, {}};
}

// Blender's identifiers of the enums the modes choose from, in the order of their values.
inline constexpr std::array<std::string_view, 3> kColorModeNames = {"RGB", "HSV", "HSL"};
// MIX_VALUE: values by a value (the Mix node's Float), vectors by a value or by a vector
// (its factor_mode).
inline constexpr std::array<std::string_view, 3> kMixValueNames = {"FLOAT", "UNIFORM",
                                                                   "NON_UNIFORM"};
inline constexpr std::array<std::string_view, 2> kClampTypeNames = {"MINMAX", "RANGE"};
inline constexpr std::array<std::string_view, 4> kMapRangeNames = {"LINEAR", "STEPPED",
                                                                   "SMOOTHSTEP", "SMOOTHERSTEP"};
// CURVE: which node's curves, RGB Curves', Float Curve's or Vector Curves'.
inline constexpr std::array<std::string_view, 3> kCurveKindNames = {"RGB", "FLOAT", "VECTOR"};
inline constexpr std::array<std::string_view, 5> kRampNames = {"CONSTANT", "LINEAR", "EASE",
                                                               "CARDINAL", "B_SPLINE"};
inline constexpr std::array<std::string_view, 4> kMappingNames = {"POINT", "TEXTURE", "VECTOR",
                                                                  "NORMAL"};
inline constexpr std::array<std::string_view, 4> kImageProjectionNames = {"FLAT", "BOX", "SPHERE",
                                                                          "TUBE"};
inline constexpr std::array<std::string_view, 2> kEnvironmentProjectionNames = {"EQUIRECTANGULAR",
                                                                                "MIRROR_BALL"};
inline constexpr std::array<std::string_view, 7> kGradientNames = {
    "LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"};
// LAYER_WEIGHT: the output it computes.
inline constexpr std::array<std::string_view, 2> kLayerWeightNames = {"FRESNEL", "FACING"};
inline constexpr std::array<std::string_view, 3> kNormalMapSpaceNames = {"TANGENT", "OBJECT",
                                                                         "WORLD"};
inline constexpr std::array<std::string_view, 4> kDimensionNames = {"1D", "2D", "3D", "4D"};
inline constexpr std::array<std::string_view, 5> kNoiseTypeNames = {
    "FBM", "MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HETERO_TERRAIN"};
inline constexpr std::array<std::string_view, 5> kVoronoiFeatureNames = {
    "F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"};
inline constexpr std::array<std::string_view, 4> kVoronoiMetricNames = {"EUCLIDEAN", "MANHATTAN",
                                                                        "CHEBYCHEV", "MINKOWSKI"};
// Which output VORONOI computes: a value (Distance, also Radius), Color, or the feature
// point (Position, W).
inline constexpr std::array<std::string_view, 3> kVoronoiOutputNames = {"DISTANCE", "COLOR",
                                                                        "POSITION"};
// sky::Model, in its order.
inline constexpr std::array<std::string_view, 3> kSkyModelNames = {"PREETHAM", "SINGLE_SCATTERING",
                                                                   "HOSEK_WILKIE"};
inline constexpr std::array<std::string_view, 2> kWaveTypeNames = {"BANDS", "RINGS"};
inline constexpr std::array<std::string_view, 4> kWaveBandsNames = {"X", "Y", "Z", "DIAGONAL"};
inline constexpr std::array<std::string_view, 4> kWaveRingsNames = {"X", "Y", "Z", "SPHERICAL"};
inline constexpr std::array<std::string_view, 3> kWaveProfileNames = {"SIN", "SAW", "TRI"};
// ShaderNodeVectorRotate.rotation_type.
inline constexpr std::array<std::string_view, 5> kVectorRotateNames = {
    "AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"};
// ShaderNodeLightFalloff's outputs: the strength scaled for each falloff.
inline constexpr std::array<std::string_view, 3> kLightFalloffNames = {"QUADRATIC", "LINEAR",
                                                                       "CONSTANT"};
// ShaderNodeTexGabor.gabor_type, and which of its outputs GABOR computes.
inline constexpr std::array<std::string_view, 2> kGaborTypeNames = {"2D", "3D"};
// How IES's interpolation treats the table's edges (shader/ies.h): as Cycles 3.x, or as
// Cycles 4.x+.
inline constexpr std::array<std::string_view, 2> kIesEdgeNames = {"LEGACY", "BOUNDS"};
inline constexpr std::array<std::string_view, 3> kGaborOutputNames = {"VALUE", "PHASE",
                                                                      "INTENSITY"};

// Each field, named by op (the decoders read these).
namespace mode_field {
inline constexpr ModeField kClamp = flag("clamp", 8);  // MATH, MIX, MAP_RANGE: clamp the result
inline constexpr ModeField kMathOperation = choice("operation", 0, 8, kMathOpNames);
inline constexpr ModeField kVectorMathOperation = choice("operation", 0, 8, kVectorMathOpNames);
inline constexpr ModeField kMixBlend = choice("blend_type", 0, 8, kMixBlendNames);
inline constexpr ModeField kMixValue = choice("factor_mode", 0, 2, kMixValueNames);
inline constexpr ModeField kColorMode = choice("mode", 0, 2, kColorModeNames);  // SEPARATE, COMBINE
// SWIZZLE: the component (x, y, z, w: alpha) it puts in all four.
inline constexpr ModeField kSwizzle = number("component", 0, 2, 4);
inline constexpr ModeField kClampType = choice("clamp_type", 0, 1, kClampTypeNames);
inline constexpr ModeField kMapRange = choice("interpolation_type", 0, 2, kMapRangeNames);
inline constexpr ModeField kRamp = choice("interpolation", 0, 3, kRampNames);
// CURVE: extrapolate past [0, 1] (not clamp).
inline constexpr ModeField kCurveKind = choice("kind", 0, 2, kCurveKindNames);
inline constexpr ModeField kCurveExtrapolate = flag("extrapolate", 8);
inline constexpr ModeField kMapping = choice("vector_type", 0, 2, kMappingNames);
inline constexpr ModeField kImageProjection = choice("projection", 0, 2, kImageProjectionNames);
inline constexpr ModeField kEnvironmentProjection =
    choice("projection", 0, 1, kEnvironmentProjectionNames);
inline constexpr ModeField kGradient = choice("gradient_type", 0, 3, kGradientNames);
inline constexpr ModeField kLayerWeight = choice("output", 0, 1, kLayerWeightNames);
inline constexpr ModeField kNormalMapSpace = choice("space", 0, 2, kNormalMapSpaceNames);
inline constexpr ModeField kBumpInvert = flag("invert", 0);  // BUMP: the height negated
inline constexpr ModeField kSkyModel = choice("model", 0, 2, kSkyModelNames);
inline constexpr ModeField kDimensions = choice("dimensions", 0, 2, kDimensionNames);
inline constexpr ModeField kNoiseType = choice("noise_type", 2, 3, kNoiseTypeNames);
inline constexpr ModeField kNormalize = flag("normalize", 8);  // NOISE, VORONOI: to [0, 1]
inline constexpr ModeField kNoiseColor = flag("color", 9);     // NOISE: the Color output too
inline constexpr ModeField kVoronoiFeature = choice("feature", 2, 3, kVoronoiFeatureNames);
inline constexpr ModeField kVoronoiMetric = choice("metric", 5, 2, kVoronoiMetricNames);
// VORONOI: the 2D-4D cells hashed by their integer coordinates (Blender 5.0).
inline constexpr ModeField kVoronoiIntegerHash = flag("integer_hash", 7);
inline constexpr ModeField kVoronoiOutput = choice("output", 9, 2, kVoronoiOutputNames);
// WAVE: the direction is bands' or rings', by the type; both lie in the same bits.
inline constexpr ModeField kWaveType = choice("wave_type", 0, 1, kWaveTypeNames);
inline constexpr ModeField kWaveBands = choice("bands_direction", 1, 2, kWaveBandsNames);
inline constexpr ModeField kWaveRings = choice("rings_direction", 1, 2, kWaveRingsNames);
inline constexpr ModeField kWaveProfile = choice("wave_profile", 3, 2, kWaveProfileNames);
inline constexpr ModeField kMagicDepth = number("turbulence_depth", 0, 4, 11);
inline constexpr ModeField kBrickOffset = number("offset_frequency", 0, 8, 256);
inline constexpr ModeField kBrickSquash = number("squash_frequency", 8, 8, 256);
// WHITE_NOISE: the Color output too (else the Value in all four).
inline constexpr ModeField kWhiteNoiseColor = flag("color", 2);
inline constexpr ModeField kVectorRotateType = choice("rotation_type", 0, 3, kVectorRotateNames);
inline constexpr ModeField kVectorRotateInvert = flag("invert", 3);
inline constexpr ModeField kLightFalloff = choice("falloff", 0, 2, kLightFalloffNames);
// AMBIENT_OCCLUSION: its rays per evaluation (Blender's Samples), drawn about the opposite
// of the normal (Inside), meeting only the hit's own object (Only Local).
inline constexpr ModeField kAoSamples = number("samples", 0, 8, 256);
inline constexpr ModeField kAoInside = flag("inside", 8);
inline constexpr ModeField kAoOnlyLocal = flag("only_local", 9);
// BEVEL: its probe rays per evaluation (Blender's Samples).
inline constexpr ModeField kBevelSamples = number("samples", 0, 8, 256);
inline constexpr ModeField kGaborType = choice("gabor_type", 0, 1, kGaborTypeNames);
inline constexpr ModeField kGaborOutput = choice("output", 1, 2, kGaborOutputNames);
inline constexpr ModeField kIesEdges = choice("edges", 0, 1, kIesEdgeNames);

inline constexpr std::array kMath = {kMathOperation, kClamp};
inline constexpr std::array kVectorMath = {kVectorMathOperation};
inline constexpr std::array kMix = {kMixBlend, kClamp};
inline constexpr std::array kMixValueOp = {kMixValue};
inline constexpr std::array kColor = {kColorMode};
inline constexpr std::array kSwizzleOp = {kSwizzle};
inline constexpr std::array kClampOp = {kClampType};
inline constexpr std::array kMapRangeOp = {kMapRange, kClamp};
inline constexpr std::array kRampOp = {kRamp};
inline constexpr std::array kCurve = {kCurveKind, kCurveExtrapolate};
inline constexpr std::array kMappingOp = {kMapping};
inline constexpr std::array kImage = {kImageProjection};
inline constexpr std::array kEnvironment = {kEnvironmentProjection};
inline constexpr std::array kGradientOp = {kGradient};
inline constexpr std::array kLayerWeightOp = {kLayerWeight};
inline constexpr std::array kNormalMap = {kNormalMapSpace};
inline constexpr std::array kBump = {kBumpInvert};
inline constexpr std::array kSkyOp = {kSkyModel};
inline constexpr std::array kNoise = {kDimensions, kNoiseType, kNormalize, kNoiseColor};
inline constexpr std::array kVoronoi = {kDimensions,         kVoronoiFeature, kVoronoiMetric,
                                        kVoronoiIntegerHash, kNormalize,      kVoronoiOutput};
inline constexpr std::array kWave = {kWaveType, kWaveBands, kWaveRings, kWaveProfile};
inline constexpr std::array kMagic = {kMagicDepth};
inline constexpr std::array kBrick = {kBrickOffset, kBrickSquash};
inline constexpr std::array kWhiteNoise = {kDimensions, kWhiteNoiseColor};
inline constexpr std::array kVectorRotate = {kVectorRotateType, kVectorRotateInvert};
inline constexpr std::array kLightFalloffOp = {kLightFalloff};
inline constexpr std::array kAmbientOcclusion = {kAoSamples, kAoInside, kAoOnlyLocal};
inline constexpr std::array kBevel = {kBevelSamples};
inline constexpr std::array kGabor = {kGaborType, kGaborOutput};
inline constexpr std::array kIes = {kIesEdges};
}  // namespace mode_field

// The ops whose `e` is the offset of a table in the program's constants (whitted_native.
// TABLE_OPS): the compiler places the table, and folding hands it over whole.
inline constexpr std::array kTableOps = {Op::kColorRamp, Op::kCurve, Op::kSky, Op::kIes};
constexpr bool reads_table(Op op) {
  for (Op t : kTableOps) {
    if (t == op) return true;
  }
  return false;
}

// The ops whose mode is fields, with them (whitted_native.OP_MODES): all but INPUT (its
// modes are kOpNumbers') and those without a mode. Every bit of such a mode lies in a
// field, and every field holds one of its values (Program checks).
struct OpMode {
  Op op;
  std::span<const ModeField> fields;
};
inline constexpr std::array<OpMode, 31> kOpModes = {{
    {Op::kMath, mode_field::kMath},
    {Op::kVectorMath, mode_field::kVectorMath},
    {Op::kMix, mode_field::kMix},
    {Op::kMixValue, mode_field::kMixValueOp},
    {Op::kSeparate, mode_field::kColor},
    {Op::kSwizzle, mode_field::kSwizzleOp},
    {Op::kCombine, mode_field::kColor},
    {Op::kClamp, mode_field::kClampOp},
    {Op::kMapRange, mode_field::kMapRangeOp},
    {Op::kColorRamp, mode_field::kRampOp},
    {Op::kCurve, mode_field::kCurve},
    {Op::kMapping, mode_field::kMappingOp},
    {Op::kImage, mode_field::kImage},
    {Op::kEnvironment, mode_field::kEnvironment},
    {Op::kGradient, mode_field::kGradientOp},
    {Op::kLayerWeight, mode_field::kLayerWeightOp},
    {Op::kNormalMap, mode_field::kNormalMap},
    {Op::kNoise, mode_field::kNoise},
    {Op::kVoronoi, mode_field::kVoronoi},
    {Op::kWave, mode_field::kWave},
    {Op::kMagic, mode_field::kMagic},
    {Op::kBrick, mode_field::kBrick},
    {Op::kBump, mode_field::kBump},
    {Op::kSky, mode_field::kSkyOp},
    {Op::kWhiteNoise, mode_field::kWhiteNoise},
    {Op::kVectorRotate, mode_field::kVectorRotate},
    {Op::kLightFalloff, mode_field::kLightFalloffOp},
    {Op::kAmbientOcclusion, mode_field::kAmbientOcclusion},
    {Op::kBevel, mode_field::kBevel},
    {Op::kGabor, mode_field::kGabor},
    {Op::kIes, mode_field::kIes},
}};

// The fields of op's mode; empty for INPUT and an op without a mode.
constexpr std::span<const ModeField> mode_fields(Op op) {
  for (const OpMode& m : kOpModes) {
    if (m.op == op) return m.fields;
  }
  return {};
}

// Whether `mode` is one of the modes of fields `fields`: no bit outside them, each
// field one of its values (no fields: 0).
constexpr bool valid_mode(std::span<const ModeField> fields, uint32_t mode) {
  uint32_t covered = 0;
  for (const ModeField& f : fields) {
    if (f.in(mode) >= f.count) return false;
    covered |= f.mask();
  }
  return (mode & ~covered) == 0;
}

// Each field fits its bits (count <= 2^width within 32 bits) and fields of one op share
// bits only as alternatives of the same bits (WAVE's directions).
constexpr bool well_formed(std::span<const ModeField> fields) {
  for (size_t i = 0; i < fields.size(); ++i) {
    const ModeField& f = fields[i];
    if (f.width == 0 || f.shift + f.width > 32 || f.count > (1ull << f.width)) return false;
    for (size_t j = 0; j < i; ++j) {
      const ModeField& g = fields[j];
      if (g.name == f.name) return false;
      if ((g.mask() & f.mask()) != 0 && (g.shift != f.shift || g.width != f.width)) return false;
    }
  }
  return true;
}
static_assert([] {
  for (size_t i = 0; i < kOpModes.size(); ++i) {
    if (!well_formed(kOpModes[i].fields)) return false;
    for (size_t j = 0; j < i; ++j) {
      if (kOpModes[j].op == kOpModes[i].op) return false;
    }
  }
  return true;
}());

}  // namespace whitted
