// Material's constructor: what cannot be a material is refused with the reason, alpha is
// clamped, and program outputs must name registers the program has.
#include "scene/material.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrator/lobes.h"

namespace whitted {
namespace {

std::string refusal(const MaterialParams& params) {
  try {
    const Material material(params);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(Material, ConstructorRefusesWhatCannotBeAMaterial) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(refusal({}), "");
  EXPECT_EQ(refusal({.emission = Color(0.0f, inf, 0.0f)}), "material colours must be finite");
  EXPECT_EQ(refusal({.shininess = nan}),
            "material shininess, ambient and ior must be finite and ior positive");
  EXPECT_EQ(refusal({.ior = 0.0f}),
            "material shininess, ambient and ior must be finite and ior positive");
  EXPECT_EQ(refusal({.alpha = nan}), "alpha must be finite");
  EXPECT_EQ(refusal({.coat_shininess = inf}), "coat values must be finite");
  EXPECT_EQ(refusal({.coat_ior = -1.0f}), "coat_ior must be positive");
  EXPECT_EQ(refusal({.diffuse_model = static_cast<DiffuseModel>(5)}),
            "diffuse_model is not a DiffuseModel");
  EXPECT_EQ(refusal({.diffuse_roughness = nan}), "diffuse_roughness must be finite");
  MaterialParams driven;
  driven.outputs[kAlphaField] = 0;
  EXPECT_EQ(refusal(driven), "material outputs need a program");
}

TEST(Material, ConstructorChecksOutputsAgainstTheProgramsRegisters) {
  // One instruction-free program with two registers: outputs 0 and 1 exist, 2 does not.
  MaterialParams params;
  const std::vector<float> registers(2 * 4, 0.0f);
  params.program = std::make_shared<Program>(nullptr, 0, registers.data(), 2, std::vector<float>{},
                                             std::vector<std::string>{});
  params.outputs[kDiffuseField] = 1;
  EXPECT_EQ(refusal(params), "");
  params.outputs[kIorField] = 2;
  EXPECT_EQ(refusal(params), "output 'ior' register 2 out of range (2 registers)");
}

TEST(Material, ConstructorClampsAlphaAndDiffuseRoughness) {
  EXPECT_EQ(Material({.alpha = 3.0f}).alpha, 1.0f);
  EXPECT_EQ(Material({.alpha = -1.0f}).alpha, 0.0f);
  EXPECT_EQ(Material({.diffuse_roughness = 2.0f}).diffuse_roughness, 1.0f);
  EXPECT_EQ(Material({.diffuse_roughness = -1.0f}).diffuse_roughness, 0.0f);
}

// Burley's diffuse shape by hand: Schlick weights F = (1 - cos)^5, R = r (1 + l.v),
// (1 - F_l/2)(1 - F_v/2) + R (F_l + F_v + F_l F_v (R - 1)).
TEST(Material, BurleyDiffuseShape) {
  // Light and view along the normal: Lambert's lobe, whatever the roughness.
  EXPECT_FLOAT_EQ(burley_diffuse(1.0f, 1.0f, 1.0f, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(burley_diffuse(1.0f, 1.0f, 1.0f, 1.0f), 1.0f);
  // Light at the horizon, smooth: half of Lambert's.
  EXPECT_FLOAT_EQ(burley_diffuse(0.0f, 1.0f, 0.0f, 0.0f), 0.5f);
  // Light at 60 degrees, view along the normal, rough: F_l = 1/32, R = 1.5,
  // (1 - 1/64) + 1.5/32.
  EXPECT_FLOAT_EQ(burley_diffuse(0.5f, 1.0f, 0.5f, 1.0f), 1.0f - 1.0f / 64.0f + 1.5f / 32.0f);
  // Light and view both at the horizon, together (retro-reflection), rough: R = 2,
  // 1/4 + 2 (1 + 1 + 1).
  EXPECT_FLOAT_EQ(burley_diffuse(0.0f, 0.0f, 1.0f, 1.0f), 6.25f);
  // Cosines beyond [0, 1] (rounding) count as their bound.
  EXPECT_FLOAT_EQ(burley_diffuse(1.0000001f, -1e-7f, 0.0f, 0.0f), 0.5f);
}

// Oren-Nayar in Fujii's form by hand: pi (1 + r s) / (pi + (pi/2 - 2/3) r), with
// s = l.v - (n.l)(n.v), over max(n.l, n.v) where positive.
TEST(Material, OrenNayarDiffuseShape) {
  const float pi = 3.14159265358979f;
  const float c = pi / 2.0f - 2.0f / 3.0f;
  // Roughness 0: Lambert.
  EXPECT_FLOAT_EQ(oren_nayar_diffuse(0.3f, 0.8f, -0.2f, 0.0f), 1.0f);
  // Light and view along the normal: s = 0, only the normalisation.
  EXPECT_FLOAT_EQ(oren_nayar_diffuse(1.0f, 1.0f, 1.0f, 1.0f), pi / (pi + c));
  // Light at 60 degrees, view along the normal, in the same plane: l.v = 0.5 = n.l n.v,
  // s = 0. Behind the view (light at 60 degrees on the viewer's side, view at 60 too,
  // l = v): s = 1 - 1/4 = 3/4, over 1/2: 3/2.
  EXPECT_FLOAT_EQ(oren_nayar_diffuse(0.5f, 1.0f, 0.5f, 1.0f), pi / (pi + c));
  EXPECT_FLOAT_EQ(oren_nayar_diffuse(0.5f, 0.5f, 1.0f, 0.5f),
                  pi * (1.0f + 0.5f * 1.5f) / (pi + 0.5f * c));
  // Cycles 4.3+'s multiple scattering: none at roughness 0 (Lambert loses nothing; no
  // 0/0 either), at normal incidence 1 - pi A (G(1) = 0), and more for a brighter albedo.
  EXPECT_NEAR(oren_nayar_loss(0.7f, 0.0f), 0.0f, 1e-6f);
  EXPECT_EQ(oren_nayar_multiscatter(Color(0.5f), 0.0f, 0.7f), Color(0.0f));
  EXPECT_NEAR(oren_nayar_loss(1.0f, 1.0f), 1.0f - pi / (pi + c), 1e-6f);
  const Color ms = oren_nayar_multiscatter(Color(0.9f, 0.5f, 0.1f), 1.0f, 1.0f);
  EXPECT_GT(ms.x, ms.y);
  EXPECT_GT(ms.y, ms.z);
  // Light opposite the view: s negative, not divided: darker than Lambert.
  EXPECT_FLOAT_EQ(oren_nayar_diffuse(0.5f, 0.5f, -0.5f, 1.0f), pi * (1.0f - 0.75f) / (pi + c));
}

}  // namespace
}  // namespace whitted
