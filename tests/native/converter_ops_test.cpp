// Ops WHITE_NOISE, WAVELENGTH, VECTOR_ROTATE, LIGHT_FALLOFF and WIREFRAME (issue 49) against
// analytic values; tests/blender/test_nodes_vs_cycles.py checks them against Cycles.
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "program_builder.h"
#include "shader/procedural.h"
#include "shader/wavelength.h"

namespace whitted {
namespace {

using testing::make;
using testing::Row;

const glm::vec4 kZero(0.0f);

glm::vec4 run_one(Op op, uint32_t mode, const std::vector<glm::vec4>& operands) {
  // Operands in registers 0.., the result in the register after them.
  const auto out = static_cast<uint32_t>(operands.size());
  Row row{op, mode, out};
  uint32_t* slots[] = {&row.a, &row.b, &row.c, &row.d, &row.e};
  for (uint32_t i = 0; i < operands.size(); ++i) *slots[i] = i;
  std::vector<glm::vec4> registers = operands;
  registers.emplace_back(0.0f);
  const Program program = make({row}, registers);
  std::vector<glm::vec4> r(Program::kMaxRegisters + 1);
  program.run(ProgramHit{}, r.data());
  // The compiler's folding runs the same code.
  std::vector<std::optional<glm::vec4>> folded_operands(operands.begin(), operands.end());
  const auto folded = Program::fold(static_cast<uint32_t>(op), mode, folded_operands, {});
  EXPECT_TRUE(folded.has_value());
  EXPECT_EQ(*folded, r[out]);
  return r[out];
}

uint32_t rotate_mode(uint32_t type, bool invert) {
  return type << mode_field::kVectorRotateType.shift |
         (invert ? 1u << mode_field::kVectorRotateInvert.shift : 0u);
}

void expect_near(const glm::vec4& a, const glm::vec3& b, float tolerance = 1e-6f) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tolerance) << "component " << k;
}

TEST(VectorRotate, TurnsAboutTheCentreRightHanded) {
  const float quarter = std::numbers::pi_v<float> / 2.0f;
  const glm::vec4 v(2.0f, 1.0f, 0.5f, 0.0f), centre(1.0f, 1.0f, 0.0f, 0.0f);
  const glm::vec4 angle(quarter);
  // About Z by a quarter turn: the offset (1, 0, 0.5) becomes (0, 1, 0.5).
  expect_near(run_one(Op::kVectorRotate, rotate_mode(3, false), {v, centre, kZero, angle}),
              {1.0f, 2.0f, 0.5f});
  // Inverted: the other way.
  expect_near(run_one(Op::kVectorRotate, rotate_mode(3, true), {v, centre, kZero, angle}),
              {1.0f, 0.0f, 0.5f});
  // An axis of any length along Z is the same; a zero axis leaves the vector.
  const glm::vec4 z(0.0f, 0.0f, 3.0f, 0.0f);
  expect_near(run_one(Op::kVectorRotate, rotate_mode(0, false), {v, centre, z, angle}),
              {1.0f, 2.0f, 0.5f});
  expect_near(run_one(Op::kVectorRotate, rotate_mode(0, false), {v, centre, kZero, angle}),
              {2.0f, 1.0f, 0.5f});
  // About X: (1, 0, 0.5) -> (1, -0.5, 0); about Y: -> (0.5, 0, -1).
  expect_near(run_one(Op::kVectorRotate, rotate_mode(1, false), {v, centre, kZero, angle}),
              {2.0f, 0.5f, 0.0f});
  expect_near(run_one(Op::kVectorRotate, rotate_mode(2, false), {v, centre, kZero, angle}),
              {1.5f, 1.0f, -1.0f});
  // Euler XYZ by (0, 0, quarter) is the turn about Z; inverted, back again.
  const glm::vec4 euler(0.0f, 0.0f, quarter, 0.0f);
  expect_near(run_one(Op::kVectorRotate, rotate_mode(4, false), {v, centre, euler, kZero}),
              {1.0f, 2.0f, 0.5f});
  const glm::vec4 there = run_one(Op::kVectorRotate, rotate_mode(4, false),
                                  {v, centre, glm::vec4(0.3f, -0.7f, 1.1f, 0.0f), kZero});
  expect_near(run_one(Op::kVectorRotate, rotate_mode(4, true),
                      {there, centre, glm::vec4(0.3f, -0.7f, 1.1f, 0.0f), kZero}),
              {2.0f, 1.0f, 0.5f}, 1e-5f);
}

TEST(LightFalloff, ScalesByTheRayLength) {
  const glm::vec4 strength(3.0f), none(0.0f), length(2.0f), smooth(4.0f);
  EXPECT_EQ(run_one(Op::kLightFalloff, 0, {strength, none, length}).x, 3.0f);
  EXPECT_EQ(run_one(Op::kLightFalloff, 1, {strength, none, length}).x, 6.0f);
  EXPECT_EQ(run_one(Op::kLightFalloff, 2, {strength, none, length}).x, 12.0f);
  // Smooth 4 at length 2: times 4 / (4 + 4).
  EXPECT_FLOAT_EQ(run_one(Op::kLightFalloff, 2, {strength, smooth, length}).x, 6.0f);
  // A length whose square overflows is left unsmoothed.
  EXPECT_EQ(run_one(Op::kLightFalloff, 0, {strength, smooth, glm::vec4(1e30f)}).x, 3.0f);
}

TEST(Wavelength, IsTheMatchingFunctionsInRec709) {
  // Black past the table (780 nm on) and well below it.
  EXPECT_EQ(run_one(Op::kWavelength, 0, {glm::vec4(780.0f)}), glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(run_one(Op::kWavelength, 0, {glm::vec4(300.0f)}), glm::vec4(0, 0, 0, 1));
  // At a sample: its XYZ to Rec.709 / 2.52; 555 nm is green, 450 nm blue, 610 nm red.
  const glm::vec4 green = run_one(Op::kWavelength, 0, {glm::vec4(555.0f)});
  EXPECT_EQ(Vec3(green), sky::xyz_to_rec709(Vec3(0.5121f, 1.0f, 0.0057f)) / 2.52f);
  EXPECT_GT(green.y, green.x);
  EXPECT_GT(green.y, green.z);
  const glm::vec4 blue = run_one(Op::kWavelength, 0, {glm::vec4(450.0f)});
  EXPECT_GT(blue.z, blue.x);
  const glm::vec4 red = run_one(Op::kWavelength, 0, {glm::vec4(610.0f)});
  EXPECT_GT(red.x, red.y);
  // Halfway between two samples: their mean.
  const Vec3 mean = 0.5f * (Vec3(0.5121f, 1.0f, 0.0057f) + Vec3(0.5945f, 0.9950f, 0.0039f));
  expect_near(run_one(Op::kWavelength, 0, {glm::vec4(557.5f)}), sky::xyz_to_rec709(mean) / 2.52f);
}

TEST(Wireframe, IsOneWithinHalfTheSizeOfAnEdgeLine) {
  // The right triangle (0, 0, 0), (2, 0, 0), (0, 2, 0): its legs on the axes, its
  // hypotenuse x + y = 2.
  const glm::vec4 c0(0.0f), c1(2.0f, 0.0f, 0.0f, 0.0f), c2(0.0f, 2.0f, 0.0f, 0.0f);
  const auto at = [&](float x, float y, float size) {
    return run_one(Op::kWireframe, 0, {glm::vec4(size), glm::vec4(x, y, 0.0f, 0.0f), c0, c1, c2}).x;
  };
  EXPECT_EQ(at(0.5f, 0.09f, 0.2f), 1.0f);  // 0.09 from the x axis, within 0.1
  EXPECT_EQ(at(0.5f, 0.11f, 0.2f), 0.0f);
  EXPECT_EQ(at(0.09f, 0.5f, 0.2f), 1.0f);
  // 0.3 / sqrt(2) = 0.212 from the hypotenuse.
  EXPECT_EQ(at(0.85f, 0.85f, 0.5f), 1.0f);
  EXPECT_EQ(at(0.85f, 0.85f, 0.4f), 0.0f);
  // Off a triangle (every corner at the origin): 0.
  EXPECT_EQ(run_one(Op::kWireframe, 0, {glm::vec4(1.0f), kZero, kZero, kZero, kZero}).x, 0.0f);
}

TEST(WhiteNoise, HashesTheFloatBitsOfItsDimensions) {
  const glm::vec4 p(0.3f, -1.7f, 2.5f, 0.0f), w(0.8f);
  for (uint32_t d = 0; d < 4; ++d) {
    const uint32_t color = 1u << mode_field::kWhiteNoiseColor.shift;
    const glm::vec4 both = run_one(Op::kWhiteNoise, d | color, {p, w});
    const glm::vec4 value = run_one(Op::kWhiteNoise, d, {p, w});
    EXPECT_EQ(value, glm::vec4(both.w)) << d + 1 << "D";
    EXPECT_EQ(both.x, both.w) << d + 1 << "D";  // the colour's red is the value's hash
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(both[k], 0.0f);
      EXPECT_LE(both[k], 1.0f);
    }
  }
  // 1D reads W only, 2D x and y only, 3D no W.
  const auto noise = [](int d, glm::vec4 q, float wq) {
    return procedural::white_noise(d, Vec3(q), wq);
  };
  EXPECT_EQ(noise(1, p, 0.8f), noise(1, glm::vec4(9.0f), 0.8f));
  EXPECT_NE(noise(1, p, 0.8f), noise(1, p, 0.9f));
  EXPECT_EQ(noise(2, p, 0.8f), noise(2, glm::vec4(0.3f, -1.7f, 7.0f, 0.0f), 0.1f));
  EXPECT_EQ(noise(3, p, 0.8f), noise(3, p, 0.1f));
  EXPECT_NE(noise(4, p, 0.8f), noise(4, p, 0.1f));
  // The value is lookup3 of the bits, as Cycles' hash_float_to_float.
  EXPECT_EQ(noise(1, p, 0.8f).w,
            static_cast<float>(procedural::hash(std::bit_cast<uint32_t>(0.8f))) *
                (1.0f / static_cast<float>(0xFFFFFFFFu)));
}

}  // namespace
}  // namespace whitted
