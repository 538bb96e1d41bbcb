// blackbody_rgb (shader/blackbody.h) against Cycles' own Blackbody node, and op BLACKBODY.
#include "shader/blackbody.h"

#include <gtest/gtest.h>

#include <vector>

#include "program_builder.h"
#include "shader/program.h"

namespace whitted {
namespace {

// The Blackbody node's colour as Blender 3.4.1's Cycles rendered it (an emission plane of
// strength 1 filling an orthographic camera, read from a 32-bit EXR). Blender 5.0.1's
// differs from it by at most 2.2e-6 relative, or 1.1e-6 where the fit's terms cancel (green
// at 1000 K: 0.0390419066 in 5.0.1, ours to the last digit printed). The node clamps each
// channel at 0: 0 here stands for a channel below it.
struct Seen {
  float kelvin;
  Vec3 rgb;
};
constexpr Seen kCycles[] = {
    {650.0f, {5.41329479f, 0.0f, 0.0f}},
    {800.0f, {5.41385984f, 0.0f, 0.0f}},
    {1000.0f, {4.60136175f, 0.0390407927f, 0.0f}},
    {1500.0f, {3.26430678f, 0.434045345f, 0.0f}},
    {1800.0f, {2.77111506f, 0.576142192f, 0.0f}},
    {3000.0f, {1.77084017f, 0.844283938f, 0.272222906f}},
    {6500.0f, {1.04255068f, 0.984051466f, 1.03527117f}},
    {11999.0f, {0.826997817f, 0.994074464f, 1.56678832f}},
    {12000.0f, {0.826293707f, 0.994506836f, 1.56630695f}},
    {15000.0f, {0.826293707f, 0.994506836f, 1.56630695f}},
};

TEST(Blackbody, MatchesCyclesNode) {
  for (const Seen& seen : kCycles) {
    const Vec3 got = blackbody_rgb(seen.kelvin);
    for (int k = 0; k < 3; ++k) {
      if (seen.rgb[k] == 0.0f) {
        EXPECT_LE(got[k], 0.0f) << seen.kelvin << " K, channel " << k;
      } else {
        EXPECT_NEAR(got[k], seen.rgb[k], 2e-6f + 1e-5f * seen.rgb[k])
            << seen.kelvin << " K, channel " << k;
      }
    }
  }
}

TEST(Blackbody, BelowRec709ItsChannelsGoNegative) {
  // The fit is not clamped (Principled Volume's emission takes it so): blue is below 0
  // under about 1900 K, green under 965 K.
  EXPECT_LT(blackbody_rgb(1500.0f).z, 0.0f);
  EXPECT_LT(blackbody_rgb(900.0f).y, 0.0f);
  EXPECT_GT(blackbody_rgb(1000.0f).y, 0.0f);
  EXPECT_GT(blackbody_rgb(2000.0f).z, 0.0f);
}

TEST(Blackbody, SpansMeetAndLuminanceIsAboutOne) {
  // Each span's fit meets the next at their shared temperature (within the fit's error),
  // and the colour is normalised to luminance 1 (Rec.709 weights).
  for (float edge : {965.0f, 1167.0f, 1449.0f, 1902.0f, 3315.0f, 6365.0f}) {
    const Vec3 below = blackbody_rgb(edge * (1.0f - 1e-6f));
    const Vec3 at = blackbody_rgb(edge);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(below[k], at[k], 2e-3f) << edge << " K";
  }
  for (float kelvin = 800.0f; kelvin < 12000.0f; kelvin += 250.0f) {
    const Vec3 c = blackbody_rgb(kelvin);
    EXPECT_NEAR(0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z, 1.0f, 0.01f) << kelvin << " K";
  }
}

TEST(Blackbody, OpComputesTheSameAndFolds) {
  using testing::make;
  using testing::Row;
  const Program program =
      make({Row{Op::kBlackbody, 0, 1, 0}}, {glm::vec4(1500.0f), glm::vec4(0.0f)});
  std::vector<glm::vec4> r(Program::kMaxRegisters + 1);
  program.run(ProgramHit{}, r.data());
  EXPECT_EQ(r[1], glm::vec4(blackbody_rgb(1500.0f), 1.0f));
  const std::optional<glm::vec4> operand = glm::vec4(6500.0f);
  const auto folded = Program::fold(static_cast<uint32_t>(Op::kBlackbody), 0, {&operand, 1}, {});
  ASSERT_TRUE(folded.has_value());
  EXPECT_EQ(*folded, glm::vec4(blackbody_rgb(6500.0f), 1.0f));
}

}  // namespace
}  // namespace whitted
