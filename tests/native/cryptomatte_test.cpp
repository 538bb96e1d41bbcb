// Cryptomatte ranking: equal ids summed, largest coverage first, depth kept, no id 0.
#include "integrator/cryptomatte.h"

#include <gtest/gtest.h>

namespace whitted {
namespace {

TEST(Cryptomatte, RanksSumEqualIdsAndKeepTheLargestFirst) {
  std::vector<std::array<float, 2>> weights = {
      {2.0f, 0.25f}, {0.0f, 0.5f}, {3.0f, 0.25f}, {2.0f, 0.25f}, {5.0f, 0.125f}};
  float out[6];
  rank_ids(&weights, 3, 0.5f, out);
  // id 2 covers 0.5 of the samples, then 3 (0.25) before 5 (0.125); the world (0) none.
  EXPECT_FLOAT_EQ(out[0], 2.0f);
  EXPECT_FLOAT_EQ(out[1], 0.25f);
  EXPECT_FLOAT_EQ(out[2], 3.0f);
  EXPECT_FLOAT_EQ(out[3], 0.125f);
  EXPECT_FLOAT_EQ(out[4], 5.0f);
  EXPECT_FLOAT_EQ(out[5], 0.0625f);
}

TEST(Cryptomatte, RanksPastTheLastIdAreZero) {
  std::vector<std::array<float, 2>> weights = {{7.0f, 1.0f}};
  float out[4] = {9.0f, 9.0f, 9.0f, 9.0f};
  rank_ids(&weights, 2, 1.0f, out);
  EXPECT_FLOAT_EQ(out[0], 7.0f);
  EXPECT_FLOAT_EQ(out[1], 1.0f);
  EXPECT_FLOAT_EQ(out[2], 0.0f);
  EXPECT_FLOAT_EQ(out[3], 0.0f);
}

TEST(Cryptomatte, OffUnlessKindsAndDepthAreSet) {
  Settings settings;
  settings.width = 4;
  settings.height = 2;
  EXPECT_FALSE(CryptomatteFilm(settings).enabled());
  settings.cryptomatte_kinds = 1u << static_cast<int>(CryptomatteKind::kMaterial);
  settings.cryptomatte_depth = 3;
  const CryptomatteFilm film(settings);
  EXPECT_TRUE(film.enabled());
  EXPECT_TRUE(film.has(CryptomatteKind::kMaterial));
  EXPECT_FALSE(film.has(CryptomatteKind::kObject));
  EXPECT_EQ(film.ranks(CryptomatteKind::kMaterial).size(), 4u * 2u * 6u);
  EXPECT_TRUE(film.ranks(CryptomatteKind::kObject).empty());
}

}  // namespace
}  // namespace whitted
