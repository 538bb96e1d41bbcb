// Vector helpers, reflection, refraction and Fresnel against textbook values.
#include "core/math.h"

#include <gtest/gtest.h>

#include <cmath>

namespace whitted {
namespace {

TEST(Math, ReflectMirrorsAboutTheNormal) {
  const Vec3 u = glm::normalize(Vec3(1.0f, -1.0f, 0.0f));
  const Vec3 r = reflect(u, Vec3(0.0f, 1.0f, 0.0f));
  EXPECT_NEAR(r.x, u.x, 1e-6f);
  EXPECT_NEAR(r.y, -u.y, 1e-6f);
  EXPECT_NEAR(glm::length(r), 1.0f, 1e-6f);
}

TEST(Math, RefractObeysSnellsLaw) {
  const float eta1 = 1.0f;
  const float eta2 = 1.5f;
  for (float theta_i : {0.0f, 0.3f, 0.7f, 1.2f, 1.5f}) {
    const Vec3 u(std::sin(theta_i), -std::cos(theta_i), 0.0f);
    Vec3 t;
    ASSERT_TRUE(refract(u, Vec3(0.0f, 1.0f, 0.0f), eta1 / eta2, &t));
    const float sin_t = t.x;  // the tangential component of a unit vector
    EXPECT_NEAR(eta1 * std::sin(theta_i), eta2 * sin_t, 1e-5f) << theta_i;
    EXPECT_LT(t.y, 0.0f);
    EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f);
  }
}

TEST(Math, TotalInternalReflectionBeyondTheCriticalAngle) {
  const float eta = 1.5f;  // glass to air
  const float critical = std::asin(1.0f / eta);
  const Vec3 n(0.0f, 1.0f, 0.0f);
  Vec3 t;
  const auto dir = [](float a) { return Vec3(std::sin(a), -std::cos(a), 0.0f); };
  EXPECT_TRUE(refract(dir(critical - 1e-3f), n, eta, &t));
  EXPECT_FALSE(refract(dir(critical + 1e-3f), n, eta, &t));
  EXPECT_FALSE(refract(dir(1.4f), n, eta, &t));
}

TEST(Math, FresnelAtNormalIncidenceAndAtTotalInternalReflection) {
  // ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass.
  EXPECT_NEAR(fresnel_exact(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnel_schlick(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  EXPECT_FLOAT_EQ(fresnel_exact(0.2f, 1.5f), 1.0f);
  EXPECT_FLOAT_EQ(fresnel_schlick(0.2f, 1.5f), 1.0f);
  // Grazing incidence reflects everything, without NaN.
  EXPECT_NEAR(fresnel_exact(0.0f, 1.0f / 1.5f), 1.0f, 1e-6f);
  // Index 1: nothing reflects.
  EXPECT_NEAR(fresnel_exact(0.5f, 1.0f), 0.0f, 1e-7f);
}

TEST(Math, SchlickTracksTheExactCurve) {
  // Schlick's approximation for glass strays furthest (about 0.035) near grazing incidence.
  for (float c = 0.05f; c <= 1.0f; c += 0.05f) {
    EXPECT_NEAR(fresnel_schlick(c, 1.0f / 1.5f), fresnel_exact(c, 1.0f / 1.5f), 0.04f) << c;
  }
}

}  // namespace
}  // namespace whitted
