// Open Image Denoise loaded at run time: a clear report when it is missing, and real
// denoising when scripts/stage_oidn.sh (or $WHITTED_OIDN_LIBRARY) provides it.
#include "denoise/oidn.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <vector>

namespace whitted::oidn {
namespace {

TEST(Oidn, AMissingLibraryIsNotOkAndItsReportNamesEveryPathLookedAt) {
  const Library lib = Library::open({"/nonexistent/a/libOpenImageDenoise.so.2", "/nonexistent/b"});
  EXPECT_FALSE(lib.status().ok);
  EXPECT_EQ(lib.status().version, 0);
  EXPECT_TRUE(lib.status().path.empty());
  EXPECT_NE(lib.status().report.find("/nonexistent/a/libOpenImageDenoise.so.2"), std::string::npos);
  EXPECT_NE(lib.status().report.find("/nonexistent/b"), std::string::npos);
  std::vector<float> image(4 * 4 * 3, 1.0f);
  EXPECT_EQ(lib.denoise(image.data(), nullptr, nullptr, image.data(), 4, 4, {}),
            lib.status().report);
  EXPECT_EQ(image[0], 1.0f);  // untouched
}

TEST(Oidn, AFileThatIsNotTheLibraryIsReportedWithTheLoaderError) {
  const Library lib = Library::open({"/etc/hostname"});
  EXPECT_FALSE(lib.status().ok);
  EXPECT_EQ(lib.status().path, "/etc/hostname");
  EXPECT_NE(lib.status().report.find("could not be loaded from /etc/hostname"), std::string::npos)
      << lib.status().report;
}

TEST(Oidn, TheDefaultSearchEndsAtTheBuildTreesStagedCopy) {
  const auto candidates = Library::default_candidates();
  ASSERT_FALSE(candidates.empty());
  EXPECT_EQ(candidates.back(), WHITTED_TEST_OIDN_STAGED);
}

// A noisy image: each pixel's channels are the truth times a random factor of mean 1
// (uniform in [0, 2)), as a one-sample Monte Carlo estimate scatters.
struct Noisy {
  std::vector<float> truth, color;
};
Noisy noisy(int w, int h, bool gradient) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> factor(0.0f, 2.0f);
  Noisy n;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float t =
          gradient ? 0.2f + 0.6f * static_cast<float>(x) / static_cast<float>(w - 1) : 0.5f;
      for (int c = 0; c < 3; ++c) {
        n.truth.push_back(t);
        n.color.push_back(t * factor(rng));
      }
    }
  }
  return n;
}

double mean_abs_error(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::abs(double(a[i]) - double(b[i]));
  return sum / static_cast<double>(a.size());
}

class OidnFound : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!Library::shared().status().ok) GTEST_SKIP() << Library::shared().status().report;
  }
  static const Library& lib() { return Library::shared(); }
};

TEST_F(OidnFound, TheStatusNamesTheLoadedLibraryAndA2xVersion) {
  EXPECT_GE(lib().status().version, 20000);
  EXPECT_FALSE(lib().status().path.empty());
  EXPECT_NE(lib().status().report.find(lib().status().path), std::string::npos);
}

TEST_F(OidnFound, WithAlbedoAndNormalANoisyConstantImagesErrorDropsMoreThanFiveTimes) {
  const int w = 64, h = 64;
  const Noisy n = noisy(w, h, false);
  const std::vector<float> albedo(n.color.size(), 0.8f);
  std::vector<float> normal(n.color.size(), 0.0f);
  for (size_t i = 2; i < normal.size(); i += 3) normal[i] = 1.0f;
  for (Prefilter p : {Prefilter::kNone, Prefilter::kFast, Prefilter::kAccurate}) {
    std::vector<float> out(n.color.size(), -1.0f);
    Options o;
    o.threads = 2;
    o.prefilter = p;
    ASSERT_EQ(lib().denoise(n.color.data(), albedo.data(), normal.data(), out.data(), w, h, o), "");
    const double before = mean_abs_error(n.color, n.truth), after = mean_abs_error(out, n.truth);
    EXPECT_LT(after * 5.0, before) << "prefilter " << int(p) << ": " << before << " -> " << after;
  }
}

TEST_F(OidnFound, ColourAloneANoisyGradientsErrorDropsSeveralTimesAtEveryQuality) {
  const int w = 80, h = 48;
  const Noisy n = noisy(w, h, true);
  for (Quality q : {Quality::kHigh, Quality::kBalanced, Quality::kFast}) {
    std::vector<float> out(n.color.size(), -1.0f);
    Options o;
    o.threads = 2;
    o.quality = q;
    ASSERT_EQ(lib().denoise(n.color.data(), nullptr, nullptr, out.data(), w, h, o), "");
    const double before = mean_abs_error(n.color, n.truth), after = mean_abs_error(out, n.truth);
    EXPECT_LT(after * 3.0, before) << "quality " << int(q) << ": " << before << " -> " << after;
  }
}

TEST_F(OidnFound, ANormalWithoutAlbedoWorksAndTheOutputMayBeTheInput) {
  const int w = 32, h = 32;
  const Noisy n = noisy(w, h, false);
  std::vector<float> normal(n.color.size(), 0.0f);
  for (size_t i = 2; i < normal.size(); i += 3) normal[i] = 1.0f;
  std::vector<float> image = n.color;
  ASSERT_EQ(lib().denoise(image.data(), nullptr, normal.data(), image.data(), w, h, {}), "");
  EXPECT_LT(mean_abs_error(image, n.truth) * 3.0, mean_abs_error(n.color, n.truth));
}

TEST_F(OidnFound, ACancelledDenoiseReturnsOidnsCancelledError) {
  const int w = 32, h = 32;
  const Noisy n = noisy(w, h, false);
  std::vector<float> out(n.color.size(), -1.0f);
  std::atomic<bool> cancel{true};
  Options o;
  o.cancel = &cancel;
  const std::string error = lib().denoise(n.color.data(), nullptr, nullptr, out.data(), w, h, o);
  EXPECT_NE(error.find("cancel"), std::string::npos) << error;
  cancel = false;  // the same options run to the end once the flag is down
  EXPECT_EQ(lib().denoise(n.color.data(), nullptr, nullptr, out.data(), w, h, o), "");
  EXPECT_LT(mean_abs_error(out, n.truth) * 3.0, mean_abs_error(n.color, n.truth));
}

TEST_F(OidnFound, AnEmptyImageIsRefusedWithoutCallingOidn) {
  float pixel[3] = {1, 1, 1};
  EXPECT_NE(lib().denoise(pixel, nullptr, nullptr, pixel, 0, 1, {}), "");
}

}  // namespace
}  // namespace whitted::oidn
