// Shader programs: validation, and each op against Blender's own definitions, with values
// worked out by hand.
#include "shader/program.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <vector>

#include "program_builder.h"

namespace whitted {
namespace {

using glm::vec4;
using testing::kU;
using testing::make;
using testing::Row;

vec4 run(const Program& program, uint32_t reg, const ProgramHit& hit = {}) {
  std::vector<vec4> r(Program::kMaxRegisters + 1);
  program.run(hit, r.data());
  return r[reg];
}

// One instruction over registers 0..n-1 (a, b, c, d in order), written to register n.
vec4 eval(Op op, uint32_t mode, std::initializer_list<vec4> operands, const ProgramHit& hit = {},
          std::vector<float> constants = {}, uint32_t e = kU,
          std::vector<std::string> textures = {}) {
  std::vector<vec4> registers(operands);
  const auto n = static_cast<uint32_t>(registers.size());
  registers.emplace_back(-7.0f);  // the output, overwritten
  Row row{op, mode, n};
  uint32_t* fields[] = {&row.a, &row.b, &row.c, &row.d};
  for (uint32_t i = 0; i < n && i < 4; ++i) *fields[i] = i;
  row.e = e;
  return run(make({row}, registers, std::move(constants), std::move(textures)), n, hit);
}

float math(MathOp op, float a, float b = 0.0f, float c = 0.0f, bool clamp = false) {
  return eval(Op::kMath, static_cast<uint32_t>(op) | (clamp ? 256u : 0u),
              {vec4(a), vec4(b), vec4(c)})
      .x;
}

vec4 vmath(VectorMathOp op, Vec3 a, Vec3 b = Vec3(0.0f), Vec3 c = Vec3(0.0f)) {
  return eval(Op::kVectorMath, static_cast<uint32_t>(op), {vec4(a, 0), vec4(b, 0), vec4(c, 0)});
}

Vec3 mix(MixBlend blend, float t, Vec3 c1, Vec3 c2, bool clamp = false) {
  return Vec3(eval(Op::kMix, static_cast<uint32_t>(blend) | (clamp ? 256u : 0u),
                   {vec4(t), vec4(c1, 1), vec4(c2, 1)}));
}

void expect_near(const Vec3& got, const Vec3& want, float eps = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, eps);
  EXPECT_NEAR(got.y, want.y, eps);
  EXPECT_NEAR(got.z, want.z, eps);
}

void expect_invalid(const std::vector<Row>& rows, const char* message, size_t registers = 2,
                    std::vector<float> constants = {}, std::vector<std::string> textures = {}) {
  try {
    make(rows, std::vector<vec4>(registers, vec4(0.0f)), std::move(constants), std::move(textures));
    ADD_FAILURE() << "accepted, expected: " << message;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(Program, ValidationNamesTheFirstProblem) {
  expect_invalid({{Op(99), 0, 0}}, "instruction 0: unknown op 99");
  expect_invalid({{Op::kVoronoi, 3u << 9, 0}}, "(VORONOI): mode 1536 is not one of its modes");
  expect_invalid({{Op::kMagic, 11, 0}}, "(MAGIC): mode 11 is not one of its modes");
  expect_invalid({{Op::kMath, 0, 2}}, "out register 2 out of range");
  expect_invalid({{Op::kMath, 0, 0, 5}}, "operand a register 5 out of range");
  expect_invalid({{Op::kMath, 0, 0}, {Op::kMath, 41, 0}}, "instruction 1 (MATH): mode 41");
  expect_invalid({{Op::kVectorMath, 30, 0}}, "mode 30");
  expect_invalid({{Op::kMix, 19, 0}}, "mode 19");
  expect_invalid({{Op::kInput, 15, 0}}, "mode 15 is not an input");
  expect_invalid({{Op::kMixValue, 3, 0}}, "(MIX_VALUE): mode 3 is not one of its modes");
  expect_invalid({{Op::kSwizzle, 4, 0}}, "(SWIZZLE): mode 4");
  expect_invalid({{Op::kLayerWeight, 2, 0}}, "(LAYER_WEIGHT): mode 2");
  expect_invalid({{Op::kBump, 2, 0}}, "(BUMP): mode 2");
  expect_invalid({{Op::kCurve, 3, 0, kU, kU, kU, kU, 0}}, "(CURVE): mode 3", 2,
                 std::vector<float>(4 * kCurveTable));
  // An op without a mode takes 0 only.
  expect_invalid({{Op::kGamma, 1, 0}}, "(GAMMA): mode 1 is not one of its modes");
  expect_invalid({{Op::kFresnel, 1u << 8, 0}}, "(FRESNEL): mode 256");
  EXPECT_NO_THROW(make({{Op::kGamma, 0, 0}}, {vec4(0)}));
  expect_invalid({{Op::kImage, 0, 0, kU, kU, kU, kU, 1}}, "texture slot 1 out of range", 2, {},
                 {"t"});
  expect_invalid({{Op::kColorRamp, 1, 0, kU, kU, kU, kU, 0}}, "do not hold a ramp", 2, {2, 0, 1});
  expect_invalid({{Op::kColorRamp, 1, 0, kU, kU, kU, kU, 0}}, "not sorted", 2,
                 {2, 0.5f, 0, 0, 0, 1, 0.25f, 0, 0, 0, 1});
  expect_invalid({{Op::kCurve, 0, 0, kU, kU, kU, kU, 0}}, "4 x 256 curve table", 2, {0});
  expect_invalid({}, "1 to 1024 registers", 0);
  const std::vector<vec4> nan{vec4(std::nanf(""))};
  EXPECT_THROW(make({}, nan), std::invalid_argument);
  // The clamp bit is a flag of MATH, not of VECTOR_MATH.
  EXPECT_NO_THROW(make({{Op::kMath, 256, 0}}, {vec4(0)}));
  expect_invalid({{Op::kVectorMath, 256, 0}}, "mode 256");
}

TEST(Program, UnusedOperandsReadZeroAndInstructionsRunInOrder) {
  // r1 = r0 + unused = r0; r1 = r1 * r0 (reads r1 before writing it).
  const Program p = make({{Op::kMath, static_cast<uint32_t>(MathOp::kAdd), 1, 0},
                          {Op::kMath, static_cast<uint32_t>(MathOp::kMultiply), 1, 1, 0}},
                         {vec4(3.0f), vec4(0.0f)});
  EXPECT_EQ(run(p, 1), vec4(9.0f));
}

TEST(Program, MathMatchesBlendersSafeDefinitions) {
  EXPECT_EQ(math(MathOp::kDivide, 1.0f, 0.0f), 0.0f);  // safe division
  EXPECT_EQ(math(MathOp::kDivide, 1.0f, 4.0f), 0.25f);
  EXPECT_EQ(math(MathOp::kAdd, 0.75f, 0.5f, 0.0f, true), 1.0f);  // clamp bit
  EXPECT_EQ(math(MathOp::kSubtract, 0.25f, 0.5f, 0.0f, true), 0.0f);
  EXPECT_EQ(math(MathOp::kMultiplyAdd, 2, 3, 4), 10.0f);
  EXPECT_EQ(math(MathOp::kPower, -2.0f, 3.0f), -8.0f);
  EXPECT_EQ(math(MathOp::kPower, -2.0f, 0.5f), 0.0f);  // negative base, fractional power
  EXPECT_FLOAT_EQ(math(MathOp::kLogarithm, 8.0f, 2.0f), 3.0f);
  EXPECT_EQ(math(MathOp::kLogarithm, -1.0f, 2.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kSqrt, -4.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kInverseSqrt, 0.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kInverseSqrt, 4.0f), 0.5f);
  EXPECT_EQ(math(MathOp::kLessThan, 1, 2), 1.0f);
  EXPECT_EQ(math(MathOp::kGreaterThan, 1, 2), 0.0f);
  EXPECT_EQ(math(MathOp::kSign, -3), -1.0f);
  EXPECT_EQ(math(MathOp::kSign, 0), 0.0f);
  EXPECT_EQ(math(MathOp::kCompare, 1.0f, 1.05f, 0.1f), 1.0f);
  EXPECT_EQ(math(MathOp::kCompare, 1.0f, 1.5f, 0.1f), 0.0f);
  // Smooth minimum: h = (k - |a-b|)/k = 0.5, min - h^3 k / 6.
  EXPECT_FLOAT_EQ(math(MathOp::kSmoothMin, 1.0f, 2.0f, 2.0f), 1.0f - 0.125f * 2.0f / 6.0f);
  EXPECT_FLOAT_EQ(math(MathOp::kSmoothMax, 1.0f, 2.0f, 2.0f), 2.0f + 0.125f * 2.0f / 6.0f);
  EXPECT_EQ(math(MathOp::kSmoothMin, 1.0f, 2.0f, 0.0f), 1.0f);
  EXPECT_EQ(math(MathOp::kRound, -1.5f), -1.0f);
  EXPECT_EQ(math(MathOp::kTrunc, -1.5f), -1.0f);
  EXPECT_EQ(math(MathOp::kFloor, -1.5f), -2.0f);
  EXPECT_EQ(math(MathOp::kCeil, -1.5f), -1.0f);
  EXPECT_EQ(math(MathOp::kFract, -1.25f), 0.75f);
  EXPECT_EQ(math(MathOp::kModulo, -5.0f, 3.0f), -2.0f);  // truncated
  EXPECT_EQ(math(MathOp::kFlooredModulo, -5.0f, 3.0f), 1.0f);
  EXPECT_EQ(math(MathOp::kModulo, 5.0f, 0.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kFlooredModulo, 5.0f, 0.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kWrap, 5.0f, 3.0f, 1.0f), 1.0f);  // wrap(value, max, min)
  EXPECT_EQ(math(MathOp::kWrap, 5.0f, 1.0f, 1.0f), 1.0f);  // empty range: min
  EXPECT_EQ(math(MathOp::kSnap, 7.0f, 3.0f), 6.0f);
  EXPECT_EQ(math(MathOp::kSnap, 7.0f, 0.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kPingpong, 3.0f, 2.0f), 1.0f);
  EXPECT_EQ(math(MathOp::kPingpong, 5.0f, 2.0f), 1.0f);
  EXPECT_EQ(math(MathOp::kPingpong, 5.0f, 0.0f), 0.0f);
  EXPECT_EQ(math(MathOp::kArcsine, 2.0f), std::asin(1.0f));  // clamped to the domain
  EXPECT_EQ(math(MathOp::kArccosine, -2.0f), std::acos(-1.0f));
  EXPECT_EQ(math(MathOp::kArctan2, 0.0f, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(math(MathOp::kArctan2, 1.0f, 0.0f), kPi / 2);
  EXPECT_FLOAT_EQ(math(MathOp::kRadians, 180.0f), kPi);
  EXPECT_FLOAT_EQ(math(MathOp::kDegrees, kPi), 180.0f);
  EXPECT_FLOAT_EQ(math(MathOp::kExponent, 1.0f), std::exp(1.0f));
  EXPECT_FLOAT_EQ(math(MathOp::kTanh, 0.5f), std::tanh(0.5f));
  // A scalar result fills all four components.
  EXPECT_EQ(eval(Op::kMath, 0, {vec4(1, 5, 5, 5), vec4(2, 6, 6, 6)}), vec4(3.0f));
}

TEST(Program, VectorMath) {
  EXPECT_EQ(vmath(VectorMathOp::kCrossProduct, {1, 0, 0}, {0, 1, 0}), vec4(0, 0, 1, 0));
  EXPECT_EQ(vmath(VectorMathOp::kDotProduct, {1, 2, 3}, {4, 5, 6}), vec4(32.0f));
  EXPECT_EQ(vmath(VectorMathOp::kLength, {3, 4, 0}), vec4(5.0f));
  EXPECT_EQ(vmath(VectorMathOp::kDistance, {1, 1, 1}, {1, 4, 5}), vec4(5.0f));
  EXPECT_EQ(vmath(VectorMathOp::kDivide, {1, 2, 3}, {2, 0, 3}), vec4(0.5f, 0, 1, 0));
  EXPECT_EQ(vmath(VectorMathOp::kNormalize, {0, 0, 0}), vec4(0.0f));
  EXPECT_EQ(vmath(VectorMathOp::kNormalize, {0, 3, 4}), vec4(0, 0.6f, 0.8f, 0));
  EXPECT_EQ(vmath(VectorMathOp::kScale, {1, 2, 3}, {2, 9, 9}), vec4(2, 4, 6, 0));  // b.x
  EXPECT_EQ(vmath(VectorMathOp::kProject, {1, 1, 0}, {2, 0, 0}), vec4(1, 0, 0, 0));
  EXPECT_EQ(vmath(VectorMathOp::kProject, {1, 1, 0}, {0, 0, 0}), vec4(0.0f));
  EXPECT_EQ(vmath(VectorMathOp::kReflect, {1, -1, 0}, {0, 2, 0}), vec4(1, 1, 0, 0));
  // Refract: straight through at eta 1; total internal reflection gives zero.
  expect_near(Vec3(vmath(VectorMathOp::kRefract, {0, -1, 0}, {0, 1, 0}, {1, 0, 0})), {0, -1, 0});
  const Vec3 grazing = glm::normalize(Vec3(1, -0.1f, 0));
  EXPECT_EQ(vmath(VectorMathOp::kRefract, grazing, {0, 1, 0}, {1.5f, 0, 0}), vec4(0.0f));
  EXPECT_EQ(vmath(VectorMathOp::kFaceforward, {1, 2, 3}, {0, -1, 0}, {0, 1, 0}), vec4(1, 2, 3, 0));
  EXPECT_EQ(vmath(VectorMathOp::kFaceforward, {1, 2, 3}, {0, 1, 0}, {0, 1, 0}),
            vec4(-1, -2, -3, 0));
  EXPECT_EQ(vmath(VectorMathOp::kPower, {2, -2, -2}, {3, 2, 0.5f}), vec4(8, 4, 0, 0));
  EXPECT_EQ(vmath(VectorMathOp::kSign, {-2, 0, 3}), vec4(-1, 0, 1, 0));
  EXPECT_EQ(vmath(VectorMathOp::kModulo, {-5, 5, 1}, {3, 0, 1}), vec4(-2, 0, 0, 0));
  EXPECT_EQ(vmath(VectorMathOp::kWrap, {5, 5, 5}, {3, 3, 3}, {1, 1, 1}), vec4(1, 1, 1, 0));
  EXPECT_EQ(vmath(VectorMathOp::kSnap, {7, 7, 7}, {3, 2, 0}), vec4(6, 6, 0, 0));
  EXPECT_EQ(vmath(VectorMathOp::kFraction, {-1.25f, 0.5f, 2}), vec4(0.75f, 0.5f, 0, 0));
  EXPECT_EQ(vmath(VectorMathOp::kMultiplyAdd, {1, 2, 3}, {2, 2, 2}, {1, 1, 1}), vec4(3, 5, 7, 0));
}

TEST(Program, MixBlendModes) {
  const Vec3 a(0.2f, 0.5f, 0.8f), b(0.6f, 0.5f, 0.0f);
  expect_near(mix(MixBlend::kMix, 0.5f, a, b), {0.4f, 0.5f, 0.4f});
  expect_near(mix(MixBlend::kMultiply, 1.0f, a, b), a * b);
  expect_near(mix(MixBlend::kAdd, 1.0f, a, b), a + b);
  expect_near(mix(MixBlend::kAdd, 1.0f, a, b, true), {0.8f, 1.0f, 0.8f});  // clamp bit
  expect_near(mix(MixBlend::kSubtract, 1.0f, a, b), a - b);
  expect_near(mix(MixBlend::kScreen, 1.0f, a, b), Vec3(1.0f) - (Vec3(1.0f) - a) * (Vec3(1) - b));
  expect_near(mix(MixBlend::kDifference, 1.0f, a, b), {0.4f, 0.0f, 0.8f});
  expect_near(mix(MixBlend::kDarken, 1.0f, a, b), {0.2f, 0.5f, 0.0f});
  expect_near(mix(MixBlend::kLighten, 1.0f, a, b), {0.6f, 0.5f, 0.8f});
  expect_near(mix(MixBlend::kDivide, 1.0f, a, b), {0.2f / 0.6f, 1.0f, 0.8f});  // /0 keeps a
  expect_near(mix(MixBlend::kExclusion, 1.0f, a, b), a + b - 2.0f * a * b);
  // Overlay: below 0.5 a * 2b, above 1 - 2 (1 - a)(1 - b).
  expect_near(mix(MixBlend::kOverlay, 1.0f, a, b), {0.2f * 1.2f, 1.0f - 1.0f * 0.5f, 1 - 0.4f});
  expect_near(mix(MixBlend::kLinearLight, 1.0f, a, b), a + 2.0f * b - Vec3(1.0f));
  // Dodge and burn divide by (1 - b) and by b, saturating.
  expect_near(mix(MixBlend::kDodge, 1.0f, a, b), {0.5f, 1.0f, 0.8f});
  expect_near(mix(MixBlend::kBurn, 1.0f, a, b), {0.0f, 0.0f, 0.0f});
  // Value takes the blend colour's value; hue leaves a grey blend colour alone.
  expect_near(mix(MixBlend::kValue, 1.0f, {0.4f, 0.2f, 0.2f}, {0.8f, 0.8f, 0.8f}),
              {0.8f, 0.4f, 0.4f});
  expect_near(mix(MixBlend::kHue, 1.0f, a, Vec3(0.5f)), a);
  expect_near(mix(MixBlend::kHue, 1.0f, {1, 0, 0}, {0, 0.5f, 0}), {0, 1, 0});
  expect_near(mix(MixBlend::kSaturation, 1.0f, {1, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}), Vec3(1.0f));
  // Colour: the blend colour's hue and saturation at the base's value.
  expect_near(mix(MixBlend::kColor, 1.0f, {0.5f, 0.5f, 0.5f}, {0, 1, 0}), {0, 0.5f, 0});
  // The result keeps the first colour's alpha.
  EXPECT_EQ(eval(Op::kMix, 0, {vec4(0.5f), vec4(0, 0, 0, 0.25f), vec4(1)}).w, 0.25f);
}

TEST(Program, MixValueSeparateCombineSwizzlePack) {
  EXPECT_EQ(eval(Op::kMixValue, 0, {vec4(0.25f), vec4(0.0f), vec4(4.0f)}), vec4(1.0f));
  EXPECT_EQ(eval(Op::kMixValue, 1, {vec4(0.5f), vec4(0, 2, 4, 0), vec4(2, 2, 0, 0)}),
            vec4(1, 2, 2, 0));
  EXPECT_EQ(eval(Op::kMixValue, 2, {vec4(0, 1, 0.5f, 0), vec4(0, 0, 0, 0), vec4(2, 2, 2, 0)}),
            vec4(0, 2, 1, 0));
  EXPECT_EQ(eval(Op::kSwizzle, 2, {vec4(1, 2, 3, 4)}), vec4(3.0f));
  EXPECT_EQ(eval(Op::kPack, 0, {vec4(1), vec4(2), vec4(3), vec4(4)}), vec4(1, 2, 3, 4));
  EXPECT_EQ(eval(Op::kCombine, 0, {vec4(1), vec4(2), vec4(3)}), vec4(1, 2, 3, 1));
  EXPECT_FLOAT_EQ(eval(Op::kRgbToBw, 0, {vec4(1, 1, 1, 0)}).x, 1.0f);
  EXPECT_FLOAT_EQ(eval(Op::kRgbToBw, 0, {vec4(0, 1, 0, 0)}).x, 0.7152f);
  // HSV and HSL: pure red is hue 0, full saturation; there and back again.
  expect_near(Vec3(eval(Op::kSeparate, 1, {vec4(1, 0, 0, 1)})), {0, 1, 1});
  expect_near(Vec3(eval(Op::kSeparate, 1, {vec4(0, 0.5f, 0, 1)})), {1.0f / 3.0f, 1, 0.5f});
  expect_near(Vec3(eval(Op::kSeparate, 2, {vec4(0, 0, 1, 1)})), {2.0f / 3.0f, 1, 0.5f});
  for (const Vec3 c : {Vec3(0.2f, 0.5f, 0.8f), Vec3(0.9f, 0.1f, 0.3f), Vec3(0.4f, 0.4f, 0.1f),
                       Vec3(0.3f), Vec3(0.0f)}) {
    const vec4 hsv = eval(Op::kSeparate, 1, {vec4(c, 1)});
    expect_near(Vec3(eval(Op::kCombine, 1, {vec4(hsv.x), vec4(hsv.y), vec4(hsv.z)})), c);
    const vec4 hsl = eval(Op::kSeparate, 2, {vec4(c, 1)});
    expect_near(Vec3(eval(Op::kCombine, 2, {vec4(hsl.x), vec4(hsl.y), vec4(hsl.z)})), c);
  }
}

TEST(Program, ColourAdjustments) {
  const auto hue_sat = [](float hue, float sat, float val, float fac, Vec3 c) {
    return Vec3(
        eval(Op::kHueSat, 0, {vec4(hue), vec4(sat), vec4(val), vec4(fac), vec4(c, 1)}, {}, {}, 4));
  };
  expect_near(hue_sat(0.5f, 1.0f, 1.0f, 1.0f, {0.2f, 0.5f, 0.8f}), {0.2f, 0.5f, 0.8f});
  expect_near(hue_sat(0.5f + 1.0f / 3.0f, 1.0f, 1.0f, 1.0f, {1, 0, 0}), {0, 1, 0});  // red->green
  expect_near(hue_sat(0.5f, 0.0f, 0.5f, 1.0f, {1, 0, 0}), Vec3(0.5f));
  expect_near(hue_sat(0.5f, 0.0f, 1.0f, 0.5f, {1, 0, 0}), {1.0f, 0.5f, 0.5f});
  expect_near(Vec3(eval(Op::kGamma, 0, {vec4(0.5f, -1, 2, 1), vec4(2.0f)})), {0.25f, -1, 4});
  expect_near(Vec3(eval(Op::kGamma, 0, {vec4(0.5f), vec4(0.0f)})), Vec3(1.0f));
  expect_near(Vec3(eval(Op::kBrightContrast, 0, {vec4(0.5f, 0.2f, 0, 1), vec4(0.1f), vec4(0)})),
              {0.6f, 0.3f, 0.1f});
  expect_near(Vec3(eval(Op::kBrightContrast, 0, {vec4(0.5f, 0.2f, 0, 1), vec4(0), vec4(1)})),
              {0.5f, 0.0f, 0.0f});  // 2c - 0.5, not below 0
  expect_near(Vec3(eval(Op::kInvert, 0, {vec4(1.0f), vec4(0.2f, 0.5f, 1, 1)})), {0.8f, 0.5f, 0});
  expect_near(Vec3(eval(Op::kInvert, 0, {vec4(0.5f), vec4(0.2f, 0.5f, 1, 1)})), Vec3(0.5f));
}

TEST(Program, ClampAndMapRange) {
  EXPECT_EQ(eval(Op::kClamp, 0, {vec4(5), vec4(0), vec4(1)}).x, 1.0f);
  EXPECT_EQ(eval(Op::kClamp, 0, {vec4(0.5f), vec4(1), vec4(0)}).x, 0.0f);  // min-max: max wins
  EXPECT_EQ(eval(Op::kClamp, 1, {vec4(0.5f), vec4(1), vec4(0)}).x, 0.5f);  // range: swapped
  const auto map_range = [](uint32_t mode, float v, vec4 range, float steps = 4.0f) {
    return eval(Op::kMapRange, mode, {vec4(v), range, vec4(steps)}).x;
  };
  const vec4 unit_to_ten(0, 1, 0, 10);
  EXPECT_FLOAT_EQ(map_range(0, 0.25f, unit_to_ten), 2.5f);
  EXPECT_FLOAT_EQ(map_range(0, 2.0f, unit_to_ten), 20.0f);
  EXPECT_FLOAT_EQ(map_range(256, 2.0f, unit_to_ten), 10.0f);  // clamp bit
  EXPECT_FLOAT_EQ(map_range(256, -1.0f, vec4(0, 1, 10, 0)), 10.0f);
  EXPECT_FLOAT_EQ(map_range(1, 0.3f, unit_to_ten), 2.5f);  // floor(0.3 * 5) / 4
  EXPECT_FLOAT_EQ(map_range(2, 0.5f, unit_to_ten), 5.0f);
  EXPECT_FLOAT_EQ(map_range(2, 0.25f, unit_to_ten), 10.0f * 0.15625f);
  // A reversed source range: 1 - smoothstep(0, 1, 0.25).
  EXPECT_FLOAT_EQ(map_range(2, 0.25f, vec4(1, 0, 0, 10)), 10.0f * 0.84375f);
  EXPECT_FLOAT_EQ(map_range(3, 0.25f, unit_to_ten), 10.0f * 0.103515625f);
  EXPECT_EQ(map_range(0, 0.5f, vec4(1, 1, 0, 10)), 0.0f);  // empty source range
}

// Two stops, red at 0.25 and blue at 0.75 (alpha 1 and 0.5).
const std::vector<float> kRamp{2, 0.25f, 1, 0, 0, 1, 0.75f, 0, 0, 1, 0.5f};

vec4 ramp(uint32_t mode, float f, const std::vector<float>& stops = kRamp) {
  return eval(Op::kColorRamp, mode, {vec4(f)}, {}, stops, 0);
}

TEST(Program, ColorRampAtAndBetweenStops) {
  EXPECT_EQ(ramp(1, 0.1f), vec4(1, 0, 0, 1));   // before the first: the first
  EXPECT_EQ(ramp(1, 0.25f), vec4(1, 0, 0, 1));  // at a stop
  EXPECT_EQ(ramp(1, 0.75f), vec4(0, 0, 1, 0.5f));
  EXPECT_EQ(ramp(1, 0.9f), vec4(0, 0, 1, 0.5f));  // after the last: the last
  EXPECT_EQ(ramp(1, 0.5f), vec4(0.5f, 0, 0.5f, 0.75f));
  EXPECT_EQ(ramp(1, -3.0f), vec4(1, 0, 0, 1));  // the factor is clamped to [0, 1]
  EXPECT_EQ(ramp(0, 0.5f), vec4(1, 0, 0, 1));   // constant: the stop before
  EXPECT_EQ(ramp(0, 0.75f), vec4(0, 0, 1, 0.5f));
  // Ease: weight 3t^2 - 2t^3 of the second stop, t = 0.25 of the way.
  const float ease = 3 * 0.0625f - 2 * 0.015625f;
  EXPECT_NEAR(ramp(2, 0.375f).z, ease, 1e-6f);
  // Cardinal passes through its stops; b-spline smooths them: 1/6, 2/3, 1/6.
  const std::vector<float> three{3, 0, 0, 0, 0, 1, 0.5f, 1, 1, 1, 1, 1, 0, 0, 0, 1};
  EXPECT_NEAR(ramp(3, 0.5f, three).x, 1.0f, 1e-6f);
  EXPECT_NEAR(ramp(4, 0.5f, three).x, 2.0f / 3.0f, 1e-6f);
  EXPECT_EQ(ramp(1, 0.3f, {1, 0.5f, 0.1f, 0.2f, 0.3f, 0.4f}), vec4(0.1f, 0.2f, 0.3f, 0.4f));
}

TEST(Program, Curves) {
  // Rows: C the identity, R = x^2, G and B the identity.
  std::vector<float> table(4 * 256);
  for (int i = 0; i < 256; ++i) {
    const float x = static_cast<float>(i) / 255.0f;
    table[i] = x;
    table[256 + i] = x * x;
    table[512 + i] = x;
    table[768 + i] = x;
  }
  const vec4 rgb = eval(Op::kCurve, 0, {vec4(1.0f), vec4(0.5f, 0.5f, 0.5f, 0.7f)}, {}, table, 0);
  EXPECT_NEAR(rgb.x, 0.25f, 1e-4f);
  EXPECT_NEAR(rgb.y, 0.5f, 1e-6f);
  EXPECT_EQ(rgb.w, 0.7f);
  const vec4 half = eval(Op::kCurve, 0, {vec4(0.5f), vec4(0.5f)}, {}, table, 0);
  EXPECT_NEAR(half.x, 0.375f, 1e-4f);  // the factor mixes with the input
  EXPECT_NEAR(eval(Op::kCurve, 1, {vec4(1.0f), vec4(0.25f)}, {}, table, 0).x, 0.25f, 1e-6f);
  EXPECT_NEAR(eval(Op::kCurve, 2, {vec4(1.0f), vec4(0.5f)}, {}, table, 0).y, 0.25f, 1e-4f);
  // Beyond the table: held, or extrapolated along the end slope with bit 8.
  EXPECT_NEAR(eval(Op::kCurve, 1, {vec4(1.0f), vec4(2.0f)}, {}, table, 0).x, 1.0f, 1e-6f);
  EXPECT_NEAR(eval(Op::kCurve, 257, {vec4(1.0f), vec4(2.0f)}, {}, table, 0).x, 2.0f, 1e-4f);
}

TEST(Program, MappingTypes) {
  const vec4 v(1, 0, 0, 0), loc(0, 0, 1, 0), rot(0, 0, kPi / 2, 0), scale(2, 2, 2, 0);
  expect_near(Vec3(eval(Op::kMapping, 0, {v, loc, rot, scale})), {0, 2, 1});  // point
  expect_near(Vec3(eval(Op::kMapping, 2, {v, loc, rot, scale})), {0, 2, 0});  // vector
  // Texture is the inverse of point.
  expect_near(Vec3(eval(Op::kMapping, 1, {vec4(0, 2, 1, 0), loc, rot, scale})), {1, 0, 0});
  expect_near(Vec3(eval(Op::kMapping, 3, {v, loc, rot, scale})), {0, 1, 0});  // normal: unit
  expect_near(Vec3(eval(Op::kMapping, 1, {v, vec4(0), vec4(0), vec4(0)})), {0, 0, 0});  // /0
  // Euler XYZ: X first. (0,1,0) turned 90 degrees about X is +Z, then about Z stays +Z.
  expect_near(Vec3(eval(Op::kMapping, 2,
                        {vec4(0, 1, 0, 0), vec4(0), vec4(kPi / 2, 0, kPi / 2, 0), vec4(1)})),
              {0, 0, 1});
}

// A 4x2 image whose red channel numbers its texels: x + 4 y (rows bottom to top).
ImageTexture numbered_image() {
  std::vector<float> rgba;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) rgba.insert(rgba.end(), {float(x + 4 * y), 0.0f, 0.0f, 1.0f});
  }
  return make_image_texture(rgba.data(), 4, 2, Extension::kRepeat, Interpolation::kClosest);
}

float image_at(Op op, uint32_t mode, Vec3 co, ProgramHit hit = {}, float blend = 0.0f) {
  static_assert(std::is_same_v<decltype(hit.images), const ImageTexture* const*>);
  const ImageTexture image = numbered_image();
  const ImageTexture* images[] = {&image};
  hit.images = images;
  return eval(op, mode, {vec4(co, 0), vec4(blend)}, hit, {}, 0, {"img"}).x;
}

TEST(Program, ImageProjections) {
  EXPECT_EQ(image_at(Op::kImage, 0, {0.6f, 0.7f, 0}), 6.0f);  // flat: (x, y)
  // Sphere: +Y of the box centre is u = 0.5, +X u = 0.25, -Y the seam u = 0; the equator
  // v = 0.5 (the upper row), below it the lower row.
  EXPECT_EQ(image_at(Op::kImage, 2, {0.5f, 1.0f, 0.5f}), 6.0f);
  EXPECT_EQ(image_at(Op::kImage, 2, {1.0f, 0.5f, 0.5f}), 5.0f);
  EXPECT_EQ(image_at(Op::kImage, 2, {0.5f, 0.1f, 0.5f}), 4.0f);
  EXPECT_EQ(image_at(Op::kImage, 2, {0.5f, 0.1f, 0.2f}), 0.0f);
  // Tube: u around Z as the sphere, v = (z + 1) / 2 of the remapped box.
  EXPECT_EQ(image_at(Op::kImage, 3, {0.5f, 1.0f, 0.8f}), 6.0f);
  // Box: a +Z normal reads (y, x); a +X normal (y, z); -X mirrors y.
  ProgramHit up;
  up.normal = Vec3(0, 0, 1);
  EXPECT_EQ(image_at(Op::kImage, 1, {0.6f, 0.2f, 0.5f}, up), 7.0f);  // (1 - 0.2, 0.6)
  ProgramHit side;
  side.normal = Vec3(1, 0, 0);
  EXPECT_EQ(image_at(Op::kImage, 1, {0.5f, 0.9f, 0.8f}, side), 7.0f);
  side.normal = Vec3(-1, 0, 0);
  EXPECT_EQ(image_at(Op::kImage, 1, {0.5f, 0.9f, 0.8f}, side), 4.0f);
  // Between two sides with blend: an even mix of both lookups.
  ProgramHit diagonal;
  diagonal.normal = glm::normalize(Vec3(1, 1, 0));
  const float both = image_at(Op::kImage, 1, {0.1f, 0.9f, 0.2f}, diagonal, 0.5f);
  EXPECT_FLOAT_EQ(both, 0.5f * 3.0f + 0.5f * 3.0f);  // (0.9, 0.2) and (1 - 0.1, 0.2)
}

TEST(Program, EnvironmentDirectionsToTexels) {
  // Equirectangular: +X at the centre, +Y a quarter to the left, -Y to the right, the seam
  // at -X; up is the top row.
  EXPECT_EQ(image_at(Op::kEnvironment, 0, {1, 0, 0.2f}), 6.0f);  // u 0.5, v above 0.5
  EXPECT_EQ(image_at(Op::kEnvironment, 0, {1, 0, -0.2f}), 2.0f);
  EXPECT_EQ(image_at(Op::kEnvironment, 0, {-0.1f, 1, 0.2f}), 4.0f);    // u just under 0.25
  EXPECT_EQ(image_at(Op::kEnvironment, 0, {-0.1f, -1, -0.2f}), 3.0f);  // u just over 0.75
  EXPECT_EQ(image_at(Op::kEnvironment, 0, {0, 0, 0}), 0.0f);           // no direction
  // Mirror ball: looking back along -Y meets the ball's centre; +X the right half.
  EXPECT_EQ(image_at(Op::kEnvironment, 1, {0, -1, 0.01f}), 6.0f);
  // (1, -1, -0.1) lands at u 0.69, v 0.48.
  EXPECT_EQ(image_at(Op::kEnvironment, 1, {1, -1, -0.1f}), 2.0f);
}

TEST(Program, CheckerAndGradient) {
  const vec4 c1(1, 0, 0, 1), c2(0, 0, 1, 1);
  // Scale 2: the cell of (0.75, 0.25, 0.25) has odd x, so the first colour.
  EXPECT_EQ(eval(Op::kChecker, 0, {vec4(0.75f, 0.25f, 0.25f, 0), c1, c2, vec4(2)}),
            vec4(1, 0, 0, 1));
  EXPECT_EQ(eval(Op::kChecker, 0, {vec4(0.25f, 0.25f, 0.25f, 0), c1, c2, vec4(2)}),
            vec4(0, 0, 1, 0));
  const auto gradient = [](uint32_t mode, Vec3 p) {
    return eval(Op::kGradient, mode, {vec4(p, 0)}).x;
  };
  EXPECT_EQ(gradient(0, {0.25f, 0, 0}), 0.25f);
  EXPECT_EQ(gradient(0, {2.0f, 0, 0}), 1.0f);  // saturated
  EXPECT_EQ(gradient(1, {0.5f, 0, 0}), 0.25f);
  EXPECT_EQ(gradient(2, {0.5f, 0, 0}), 0.5f);
  EXPECT_EQ(gradient(3, {0.5f, 0.25f, 0}), 0.375f);
  EXPECT_NEAR(gradient(4, {0.5f, 0, 0}), 0.499999f, 1e-6f);
  EXPECT_EQ(gradient(4, {1, 0, 0}), 0.0f);  // exactly 0 on the unit sphere
  EXPECT_NEAR(gradient(5, {0.5f, 0, 0}), 0.499999f * 0.499999f, 1e-6f);
  EXPECT_FLOAT_EQ(gradient(6, {0, 1, 0}), 0.75f);
  EXPECT_FLOAT_EQ(gradient(6, {-1, -0.0f, 0}), 0.0f);
}

TEST(Program, FresnelAndLayerWeight) {
  ProgramHit hit;  // incoming and normal both +Z: normal incidence
  EXPECT_NEAR(eval(Op::kFresnel, 0, {vec4(1.5f)}, hit).x, 0.04f, 1e-6f);
  hit.backfacing = true;  // leaving glass: 1/eta, the same at normal incidence
  EXPECT_NEAR(eval(Op::kFresnel, 0, {vec4(1.5f)}, hit).x, 0.04f, 1e-6f);
  hit.incoming = glm::normalize(Vec3(1, 0, 0.1f));  // past the critical angle
  EXPECT_EQ(eval(Op::kFresnel, 0, {vec4(1.5f)}, hit).x, 1.0f);
  // A given normal replaces the shading normal.
  ProgramHit front;
  EXPECT_NEAR(eval(Op::kFresnel, 0, {vec4(1.5f), vec4(0, 0, 1, 0)}, front).x, 0.04f, 1e-6f);
  EXPECT_NEAR(eval(Op::kFresnel, 0, {vec4(1.5f), vec4(1, 0, 0, 0)}, front).x, 1.0f, 1e-6f);
  // Layer weight: blend 0.5 is an index of 2 (front), (1/3)^2 head on.
  EXPECT_NEAR(eval(Op::kLayerWeight, 0, {vec4(0.5f)}, front).x, 1.0f / 9.0f, 1e-6f);
  EXPECT_NEAR(eval(Op::kLayerWeight, 1, {vec4(0.5f)}, front).x, 0.0f, 1e-6f);
  ProgramHit oblique;
  oblique.incoming = glm::normalize(Vec3(1, 0, 1));
  const float c = std::sqrt(0.5f);
  EXPECT_NEAR(eval(Op::kLayerWeight, 1, {vec4(0.5f)}, oblique).x, 1.0f - c, 1e-6f);
  EXPECT_NEAR(eval(Op::kLayerWeight, 1, {vec4(0.25f)}, oblique).x, 1.0f - std::pow(c, 0.5f), 1e-6f);
  EXPECT_NEAR(eval(Op::kLayerWeight, 1, {vec4(0.75f)}, oblique).x, 1.0f - c * c, 1e-5f);
}

TEST(Program, NormalMapInTangentObjectAndWorldSpace) {
  // Tangent +X (sign 1) and normal +Z: the bitangent is +Y.
  const vec4 tangent(1, 0, 0, 1);
  const vec4 normal(0, 0, 1, 0);
  const Program p = make({{Op::kNormalMap, 0, 2, 0, 1, kU, kU, 0}}, {vec4(1.0f), vec4(0), vec4(0)});
  ASSERT_EQ(p.inputs().size(), 2u);
  EXPECT_EQ(p.inputs()[0], kInputTangent + 0);
  EXPECT_EQ(p.inputs()[1], kInputObjectNormal);
  const auto tangent_space = [&](Vec3 color, vec4 t, float strength = 1.0f, ProgramHit hit = {}) {
    std::vector<vec4> inputs{t, normal};
    hit.inputs = inputs.data();
    const Program q =
        make({{Op::kNormalMap, 0, 2, 0, 1, kU, kU, 0}}, {vec4(strength), vec4(color, 1), vec4(0)});
    return Vec3(run(q, 2, hit));
  };
  expect_near(tangent_space({1, 0.5f, 0.5f}, tangent), {1, 0, 0});
  expect_near(tangent_space({0.5f, 1, 0.5f}, tangent), {0, 1, 0});
  expect_near(tangent_space({0.5f, 1, 0.5f}, vec4(1, 0, 0, -1)), {0, -1, 0});  // flipped sign
  expect_near(tangent_space({0.5f, 0.5f, 1}, tangent), {0, 0, 1});
  expect_near(tangent_space({1, 0.5f, 0.5f}, tangent, 0.0f), {0, 0, 1});  // no strength: flat
  ProgramHit rotated;  // an object turned 90 degrees about Z
  rotated.normal_to_world = glm::mat3(Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1));
  expect_near(tangent_space({1, 0.5f, 0.5f}, tangent, 1.0f, rotated), {0, 1, 0});
  ProgramHit back;
  back.backfacing = true;
  expect_near(tangent_space({1, 0.5f, 0.5f}, tangent, 1.0f, back), {-1, 0, 0});
  ProgramHit unperturbed;
  unperturbed.normal = Vec3(0, 1, 0);
  expect_near(tangent_space({1, 0.5f, 0.5f}, vec4(0), 1.0f, unperturbed), {0, 1, 0});
  // Object and world space: the colour is the normal (object space moved by the object).
  expect_near(Vec3(eval(Op::kNormalMap, 1, {vec4(1), vec4(0.5f, 1, 0.5f, 1)}, rotated)),
              {-1, 0, 0});
  expect_near(Vec3(eval(Op::kNormalMap, 2, {vec4(1), vec4(0.5f, 1, 0.5f, 1)}, rotated)), {0, 1, 0});
}

TEST(Program, InputsAreReadFromTheHitTableOncePerMode) {
  const Program p = make({{Op::kInput, kInputUvSet + 1, 0},
                          {Op::kInput, kInputPosition, 1},
                          {Op::kInput, kInputUvSet + 1, 2},
                          {Op::kMath, 0, 3, 0, 1}},
                         std::vector<vec4>(4, vec4(0.0f)));
  ASSERT_EQ(p.inputs(), (std::vector<uint32_t>{kInputUvSet + 1, kInputPosition}));
  std::vector<vec4> inputs{vec4(0.25f, 0.5f, 0, 0), vec4(2, 3, 4, 0)};
  ProgramHit hit;
  hit.inputs = inputs.data();
  EXPECT_EQ(run(p, 2, hit), vec4(0.25f, 0.5f, 0, 0));
  EXPECT_EQ(run(p, 3, hit), vec4(2.25f));
}

}  // namespace
}  // namespace whitted
