// The IES Texture's profile lookup (shader/ies.h) against what its interpolation must
// keep: constants stay constant, the table's own values are met at its angles, straight
// lines in angle stay straight, nothing lights beyond the table, and a rotationally
// symmetric profile looks the same all round. And its op in a program.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "program_builder.h"
#include "shader/ies.h"
#include "shader/program.h"

namespace whitted {
namespace {

constexpr float kDeg = kPi / 180.0f;

// A table of `h` (degrees) by `v` (degrees) angles with intensities f(h, v).
template <class F>
std::vector<float> table(const std::vector<float>& h, const std::vector<float>& v, F f) {
  std::vector<float> t = {static_cast<float>(h.size()), static_cast<float>(v.size())};
  for (float a : h) t.push_back(a * kDeg);
  for (float a : v) t.push_back(a * kDeg);
  for (float a : h) {
    for (float b : v) t.push_back(f(a, b));
  }
  return t;
}

const std::vector<float> kRound = {0.0f, 90.0f, 180.0f, 270.0f, 360.0f};
constexpr bool kLegacy = true;   // Cycles 3.x's edges
constexpr bool kBounds = false;  // Cycles 4.x+'s
const std::vector<float> kDown = {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f, 90.0f};

// The direction at vertical angle v from straight down and horizontal angle h (degrees),
// as the node measures them (v = acos(-z), h = atan2(x, y) + pi).
Vec3 direction(float h, float v) {
  const float s = std::sin(v * kDeg);
  const float phi = h * kDeg - kPi;
  return {s * std::sin(phi), s * std::cos(phi), -std::cos(v * kDeg)};
}

TEST(Ies, AConstantProfileIsConstantWithinItsAngles) {
  const auto t = table(kRound, kDown, [](float, float) { return 7.0f; });
  ASSERT_EQ(ies::table_size(t.data(), t.size()), t.size());
  for (float h : {5.0f, 33.0f, 181.0f, 359.0f}) {
    for (float v : {1.0f, 7.5f, 44.0f, 89.0f}) {
      EXPECT_NEAR(ies::lookup(t.data(), direction(h, v), kLegacy), 7.0f, 1e-4f) << h << " " << v;
    }
  }
  // Cycles 4.x+ wraps no edge of a table closed at exactly 360 degrees (its float test
  // against 2 pi - 1e-7) but holds the edge's value: constant too.
  for (float h : {5.0f, 100.0f, 181.0f, 359.0f}) {
    for (float v : {1.0f, 7.5f, 44.0f, 89.0f}) {
      EXPECT_NEAR(ies::lookup(t.data(), direction(h, v), kBounds), 7.0f, 1e-4f) << h << " " << v;
    }
  }
}

TEST(Ies, Cycles4HoldsWhereCycles3WrappedRoundTheCircle) {
  // Brighter at h = 270: wrapped, the interval [0, 90] feels it; held, it does not.
  const auto t = table(kRound, kDown, [](float h, float) { return h == 270.0f ? 3.0f : 1.0f; });
  const float wrapped = ies::intensity(t.data(), 45.0f * kDeg, 30.0f * kDeg, kLegacy);
  const float held = ies::intensity(t.data(), 45.0f * kDeg, 30.0f * kDeg, kBounds);
  EXPECT_LT(wrapped, 1.0f);  // Catmull-Rom dips away from the bright neighbour
  EXPECT_NEAR(held, 1.0f, 1e-5f);
  // Inside, both are the same curve.
  EXPECT_NEAR(ies::intensity(t.data(), 200.0f * kDeg, 30.0f * kDeg, kLegacy),
              ies::intensity(t.data(), 200.0f * kDeg, 30.0f * kDeg, kBounds), 1e-6f);
}

TEST(Ies, MeetsItsValuesAtItsAnglesAndFollowsALineBetweenThem) {
  // Linear in v away from the table's ends: Catmull-Rom reproduces a straight line.
  const auto t = table(kRound, kDown, [](float, float v) { return 100.0f - v; });
  for (float v : {15.0f, 30.0f, 45.0f, 60.0f}) {
    for (bool legacy : {kLegacy, kBounds}) {
      EXPECT_NEAR(ies::intensity(t.data(), 2.0f, v * kDeg, legacy), 100.0f - v, 1e-3f);
    }
  }
  for (float v : {20.0f, 37.0f, 52.5f}) {
    EXPECT_NEAR(ies::intensity(t.data(), 2.0f, v * kDeg, kLegacy), 100.0f - v, 1e-3f) << v;
  }
}

TEST(Ies, NothingBeyondTheLastVerticalAngle) {
  // A downlight's table stops at 90 degrees: no light upwards.
  const auto t = table(kRound, kDown, [](float, float) { return 3.0f; });
  for (bool legacy : {kLegacy, kBounds}) {
    EXPECT_EQ(ies::lookup(t.data(), Vec3(0.3f, 0.2f, 0.5f), legacy), 0.0f);
    EXPECT_EQ(ies::lookup(t.data(), direction(10.0f, 90.0f), legacy), 0.0f);
    EXPECT_EQ(ies::lookup(t.data(), Vec3(0.0f), legacy), 0.0f);
  }
}

TEST(Ies, ARotationallySymmetricProfileIsTheSameAllRoundAsCycles3Had) {
  const auto t = table(kRound, kDown, [](float, float v) { return std::cos(v * kDeg); });
  for (float v : {5.0f, 40.0f, 80.0f}) {
    const float first = ies::lookup(t.data(), direction(1.0f, v), kLegacy);
    for (float h : {45.0f, 123.0f, 250.0f, 359.0f}) {
      EXPECT_NEAR(ies::lookup(t.data(), direction(h, v), kLegacy), first, 1e-5f);
    }
  }
}

TEST(Ies, HorizontalVariationWrapsAroundTheCircleAsCycles3Did) {
  // Brighter towards h = 90: the interpolation is smooth across h = 0 = 360.
  const auto t = table(kRound, kDown, [](float h, float) { return h == 90.0f ? 2.0f : 1.0f; });
  const float before = ies::intensity(t.data(), 359.0f * kDeg, 30.0f * kDeg, kLegacy);
  const float after = ies::intensity(t.data(), 1.0f * kDeg, 30.0f * kDeg, kLegacy);
  EXPECT_NEAR(before, after, 0.05f);
  EXPECT_NEAR(ies::intensity(t.data(), 90.0f * kDeg, 30.0f * kDeg, kLegacy), 2.0f, 1e-4f);
  EXPECT_GE(ies::intensity(t.data(), 200.0f * kDeg, 30.0f * kDeg, kLegacy), 0.0f);
}

TEST(Ies, RefusesWhatIsNotAProfile) {
  auto t = table(kRound, kDown, [](float, float) { return 1.0f; });
  EXPECT_EQ(ies::table_size(t.data(), t.size() - 1), 0u);  // cut short
  auto unsorted = t;
  unsorted[3] = unsorted[4];  // two equal horizontal angles
  EXPECT_EQ(ies::table_size(unsorted.data(), unsorted.size()), 0u);
  std::vector<float> one = {1.0f, 2.0f, 0.0f, 0.0f, 1.0f, 5.0f, 5.0f};
  EXPECT_EQ(ies::table_size(one.data(), one.size()), 0u);
  std::vector<float> nan = t;
  nan[2 + 5] = NAN;  // a vertical angle
  EXPECT_EQ(ies::table_size(nan.data(), nan.size()), 0u);
}

TEST(Ies, TheOpScalesTheLookupByStrength) {
  using testing::Row;
  const auto t = table(kRound, kDown, [](float, float v) { return 10.0f - 0.1f * v; });
  const Vec3 d = direction(30.0f, 20.0f);
  // Registers: 0 the vector, 1 Strength, 2 the result.
  const Program program = testing::make({Row{Op::kIes, 0, 2, 0, 1, testing::kU, testing::kU, 0}},
                                        {glm::vec4(d, 0.0f), glm::vec4(2.5f), glm::vec4(0.0f)}, t);
  std::vector<glm::vec4> r(Program::kMaxRegisters + 1);
  program.run(ProgramHit{}, r.data());
  EXPECT_NEAR(r[2].x, 2.5f * ies::lookup(t.data(), d, kLegacy), 1e-5f);
  EXPECT_THROW(testing::make({Row{Op::kIes, 0, 2, 0, 1, testing::kU, testing::kU, 0}},
                             {glm::vec4(0.0f), glm::vec4(1.0f), glm::vec4(0.0f)}, {2.0f, 2.0f}),
               std::invalid_argument);
}

}  // namespace
}  // namespace whitted
