// The procedural textures against values Cycles rendered (Blender 5.0.1: an emission
// plane whose colour is the node's output at one constant point), and the ops' modes.
#include "shader/procedural.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "program_builder.h"
#include "shader/program.h"

namespace whitted {
namespace {

using glm::vec4;
using procedural::NoiseSettings;

constexpr float kCycles = 2e-6f;  // float rounding of a different evaluation order
const Vec3 kPoint(0.3f, 0.7f, 1.1f);

NoiseSettings noise(int dimensions, float scale, float detail, bool color = false) {
  NoiseSettings s;
  s.dimensions = dimensions;
  s.scale = scale;
  s.detail = detail;
  s.color = color;
  return s;
}

TEST(Procedural, PerlinNoiseIsZeroOnTheLatticeAndRepeatsEvery100000) {
  EXPECT_EQ(procedural::signed_noise(Vec3(1.0f, -2.0f, 3.0f)), 0.0f);
  EXPECT_EQ(procedural::signed_noise(glm::vec4(1.0f, 2.0f, -3.0f, 4.0f)), 0.0f);
  EXPECT_EQ(procedural::signed_noise(100000.5f), procedural::signed_noise(0.5f));
  EXPECT_NE(procedural::signed_noise(0.5f), 0.0f);
}

TEST(Procedural, NoiseMatchesCycles) {
  const vec4 color = procedural::noise_texture(noise(3, 1.0f, 0.0f, true), kPoint, 0.0f);
  EXPECT_NEAR(color.x, 0.4282638430595398f, kCycles);
  EXPECT_NEAR(color.y, 0.6966240406036377f, kCycles);
  EXPECT_NEAR(color.z, 0.4004368782043457f, kCycles);
  EXPECT_EQ(color.w, color.x);  // Fac
  EXPECT_NEAR(procedural::noise_texture(noise(4, 1.0f, 0.0f), kPoint, 1.9f).w, 0.5184143781661987f,
              kCycles);
  EXPECT_NEAR(procedural::noise_texture(noise(2, 1.0f, 0.0f), kPoint, 0.0f).w, 0.5203718543052673f,
              kCycles);
  EXPECT_NEAR(procedural::noise_texture(noise(1, 1.0f, 0.0f), kPoint, 0.3f).w, 0.674037516117096f,
              kCycles);
  NoiseSettings fbm = noise(3, 2.0f, 2.5f);
  fbm.distortion = 0.5f;
  EXPECT_NEAR(procedural::noise_texture(fbm, kPoint, 0.0f).w, 0.421869158744812f, kCycles);
}

TEST(Procedural, WaveMagicAndBrickMatchCycles) {
  procedural::WaveSettings wave;
  wave.type = 1, wave.direction = 3;  // rings, spherical
  wave.scale = 1.0f, wave.distortion = 1.0f;
  EXPECT_NEAR(procedural::wave_texture(wave, kPoint), 0.4982408285140991f, kCycles);
  const Vec3 magic = procedural::magic_texture(kPoint, 1.0f, 3, 1.5f);
  EXPECT_NEAR(magic.x, 0.06035909056663513f, kCycles);
  EXPECT_NEAR(magic.y, 0.6665380001068115f, kCycles);
  EXPECT_NEAR(magic.z, 0.26157617568969727f, kCycles);
  procedural::BrickSettings brick;
  brick.scale = 1.0f;
  // Cycles' colour: red to green by the tint, no mortar here.
  const glm::vec2 tm = procedural::brick_texture(brick, Vec3(0.61f, 0.37f, 0.0f));
  EXPECT_EQ(tm.y, 0.0f);
  EXPECT_NEAR(1.0f - tm.x, 0.8914384245872498f, kCycles);
  EXPECT_NEAR(tm.x, 0.10856156051158905f, kCycles);
}

TEST(Procedural, VoronoiMatchesCycles) {
  procedural::VoronoiSettings s;
  s.scale = 1.0f;
  s.integer_hash = true;  // Blender 5.0's
  const procedural::VoronoiResult f1 = procedural::voronoi_texture(s, kPoint, 0.0f);
  EXPECT_NEAR(f1.distance, 0.9261961579322815f, kCycles);
  EXPECT_NEAR(f1.color.x, 0.8034278154373169f, kCycles);
  EXPECT_NEAR(f1.color.y, 0.16936178505420685f, kCycles);
  EXPECT_NEAR(f1.color.z, 0.6681750416755676f, kCycles);
  EXPECT_NEAR(f1.position.z, 1.6681749820709229f, kCycles);
  s.dimensions = 2;
  const procedural::VoronoiResult f2d = procedural::voronoi_texture(s, kPoint, 0.0f);
  EXPECT_NEAR(f2d.distance, 0.3696289360523224f, kCycles);
  EXPECT_NEAR(f2d.position.x, 0.6572009921073914f, kCycles);
  EXPECT_NEAR(f2d.position.y, 0.7950422167778015f, kCycles);
  // Blender 3.4 hashes the cells' float bits.
  s.integer_hash = false;
  EXPECT_NEAR(procedural::voronoi_texture(s, kPoint, 0.0f).distance, 0.4766191244125366f, kCycles);
  s.dimensions = 3;
  const procedural::VoronoiResult old = procedural::voronoi_texture(s, kPoint, 0.0f);
  EXPECT_NEAR(old.distance, 0.46928590536117554f, kCycles);
  EXPECT_NEAR(old.color.x, 0.15225376188755035f, kCycles);
  EXPECT_NEAR(old.position.y, 1.0559954643249512f, kCycles);
}

TEST(Procedural, OpsReadTheirModesAndOperands) {
  // NOISE 3D fBM, normalised, with colour: the same as noise_texture.
  const uint32_t mode = 2u | (1u << 8) | (1u << 9);
  const vec4 out = procedural::noise_op(mode, vec4(kPoint, 0.0f), vec4(0.0f, 1.0f, 0.0f, 0.5f),
                                        vec4(2.0f, 0.0f, 1.0f, 0.0f));
  EXPECT_NEAR(out.y, 0.6966240406036377f, kCycles);
  EXPECT_TRUE(valid_mode(mode_fields(Op::kNoise), mode));
  EXPECT_FALSE(valid_mode(mode_fields(Op::kNoise), 5u << 2));   // type 5
  EXPECT_FALSE(valid_mode(mode_fields(Op::kNoise), 1u << 10));  // no field there
  EXPECT_FALSE(valid_mode(mode_fields(Op::kWave), 3u << 3));    // profile 3
  EXPECT_FALSE(valid_mode(mode_fields(Op::kMagic), 11));
  EXPECT_TRUE(valid_mode(mode_fields(Op::kBrick), 2u | (2u << 8)));
  EXPECT_TRUE(mode_fields(Op::kInput).empty());
  // A program refuses a mode the op does not have.
  EXPECT_THROW(testing::make({{Op::kMagic, 11, 0, 0, 0, 0}}, {vec4(0.0f)}), std::invalid_argument);
}

}  // namespace
}  // namespace whitted
