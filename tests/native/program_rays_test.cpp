// The ops that trace rays from a hit (shader/program.h HitRays) in renders. AMBIENT_OCCLUSION:
// a floor whose emission is the op's value, beside a wall, against the analytic share of
// the cosine-weighted hemisphere the wall hides; inside a closed box; Only Local and Inside;
// the inputs that trace nothing; the same pixels whatever the threads and tiles; its rays
// counted. BEVEL: its normal as emission, unchanged on a flat floor, turned towards the
// side across a box's edge, symmetric about it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "program_builder.h"
#include "scene_builders.h"
#include "shader/program.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::kU;
using testing::make;

// A material whose emission is AMBIENT_OCCLUSION of distance `distance` about the shading
// normal (`samples` rays, Inside, Only Local), and nothing else.
Material occlusion_emitter(float distance, uint32_t samples, bool inside = false,
                           bool local = false) {
  const uint32_t mode = samples | (inside ? 1u << 8 : 0u) | (local ? 1u << 9 : 0u);
  MaterialParams m;
  m.diffuse = Color(0.0f);
  m.ambient = 0.0f;
  m.program = std::make_shared<const Program>(
      make({{Op::kAmbientOcclusion, mode, 1, 0, kU}}, {glm::vec4(distance), glm::vec4(0.0f)}));
  m.outputs[kEmissionField] = 1;
  return Material(m);
}

Material black() {
  MaterialParams m;
  m.diffuse = Color(0.0f);
  m.ambient = 0.0f;
  return Material(m);
}

// A wall in the plane x = `x` from z = 0 up to z = 100, 200 wide along y, facing -x.
Mesh wall(float x) {
  const float p[] = {x, -100, 0, x, 100, 0, x, 100, 100, x, -100, 100};
  const uint32_t t[] = {0, 2, 1, 0, 3, 2};
  return make_mesh(p, 4, t, 2, nullptr, nullptr);
}

// The floor (z = 0) of `floor` under a camera looking straight down at the origin from
// z = 5 over a window 0.002 wide (every sample meets the floor within 0.001 of it), a
// wall `gap` from it (none: 0).
Scene floor_beside_wall(const Material& floor, float gap) {
  Scene scene;
  add_object(&scene, "floor", testing::quad(-100, 100, -100, 100, 0), floor);
  if (gap > 0.0f) add_object(&scene, "wall", wall(gap), black());
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 5.0f), 2e-4f);
  return scene;
}

// The mean of a render's red channel and its statistics.
struct Rendered {
  float mean = 0.0f;
  std::vector<float> pixels;
  RenderStats stats;
};
Rendered render(const Scene& scene, int samples = 4, int threads = 1, int tile = 8) {
  const Settings settings = testing::small_render(2, 2, samples, threads, tile);
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  Rendered out;
  out.pixels = job.film().pixels();
  for (size_t i = 0; i < out.pixels.size(); i += 4) out.mean += out.pixels[i];
  out.mean /= static_cast<float>(out.pixels.size() / 4);
  out.stats = job.stats();
  return out;
}

// The share of the cosine-weighted hemisphere of a floor point whose rays meet a wall
// `gap` away within `distance`: the directions project to the unit disc uniformly, and
// those with x > gap / distance reach the wall in time; 1 minus that segment's share of
// the disc.
double analytic_occlusion(double gap, double distance) {
  const double c = std::min(gap / distance, 1.0);
  return 1.0 - (std::acos(c) - c * std::sqrt(1.0 - c * c)) / std::numbers::pi;
}

TEST(AmbientOcclusion, AFloorBesideAWallSeesTheAnalyticShare) {
  // 16 camera samples of 64 rays each at every pixel: 1024 draws stratified over the
  // pixel's samples (Sobol), within 1% of the integral where independent draws would
  // err by 1.2% (one standard deviation).
  for (const float distance : {1.0f, 2.0f, 1e30f}) {
    const Rendered r = render(floor_beside_wall(occlusion_emitter(distance, 64), 0.5f));
    const double expected = analytic_occlusion(0.5, distance);
    EXPECT_NEAR(r.mean, expected, 0.01) << "distance " << distance;
    // 4 pixels of 16 samples, 64 rays each.
    EXPECT_EQ(r.stats.rays.ambient_occlusion, 4u * 16u * 64u);
  }
  // An infinite wall hides half the hemisphere whatever the gap.
  EXPECT_NEAR(analytic_occlusion(0.5, 1e30), 0.5, 1e-6);
}

TEST(AmbientOcclusion, InsideAClosedBoxEveryRayIsOccluded) {
  Scene scene;
  add_object(&scene, "box", testing::box(Vec3(-1.0f), Vec3(1.0f)), occlusion_emitter(1e30f, 16));
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 0.5f), 0.1f);
  const Rendered r = render(scene, 2);
  EXPECT_EQ(r.mean, 0.0f);
  EXPECT_EQ(r.stats.rays.ambient_occlusion, 4u * 4u * 16u);
}

TEST(AmbientOcclusion, OnlyLocalAndInsideLeaveTheWallOut) {
  // The wall is another object (Only Local), and behind the floor (Inside) there is
  // nothing: no ray is occluded either way.
  EXPECT_EQ(render(floor_beside_wall(occlusion_emitter(1.0f, 16, false, true), 0.5f)).mean, 1.0f);
  EXPECT_EQ(render(floor_beside_wall(occlusion_emitter(1.0f, 16, true, false), 0.5f)).mean, 1.0f);
  // Only Local sees the object's own faces: a floor joined to its wall.
  Scene joined;
  const float p[] = {-100, -100, 0, 100,  -100, 0, 100,  100, 0,   -100, 100,  0,
                     0.5f, -100, 0, 0.5f, 100,  0, 0.5f, 100, 100, 0.5f, -100, 100};
  const uint32_t t[] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
  add_object(&joined, "ground", make_mesh(p, 8, t, 4, nullptr, nullptr),
             occlusion_emitter(1.0f, 64, false, true));
  joined.camera = testing::looking_down(Vec3(0.0f, 0.0f, 5.0f), 2e-4f);
  EXPECT_NEAR(render(joined).mean, analytic_occlusion(0.5, 1.0), 0.01);
}

TEST(AmbientOcclusion, NoSampleOrNoDistanceTracesNothingAndGivesOne) {
  for (const auto& [distance, samples] : {std::pair{1.0f, 0u}, {0.0f, 16u}, {-1.0f, 16u}}) {
    const Rendered r = render(floor_beside_wall(occlusion_emitter(distance, samples), 0.5f));
    EXPECT_EQ(r.mean, 1.0f) << distance << " " << samples;
    EXPECT_EQ(r.stats.rays.ambient_occlusion, 0u);
  }
}

TEST(AmbientOcclusion, ThePixelsAreTheSameWhateverTheThreadsAndTiles) {
  const Scene scene = floor_beside_wall(occlusion_emitter(1.0f, 16), 0.5f);
  const Rendered one = render(scene, 3, 1, 1);
  const Rendered two = render(scene, 3, 2, 2);
  EXPECT_EQ(one.pixels, two.pixels);
  EXPECT_LT(one.mean, 1.0f);
}

// A material whose emission is BEVEL's normal n (radius `radius`, `samples` probes) as
// the colour n / 2 + 1/2 (no negative radiance).
Material bevel_emitter(float radius, uint32_t samples) {
  MaterialParams m;
  m.diffuse = Color(0.0f);
  m.ambient = 0.0f;
  const auto multiply_add = static_cast<uint32_t>(VectorMathOp::kMultiplyAdd);
  m.program =
      std::make_shared<const Program>(make({{Op::kInput, kInputPosition, 1},
                                            {Op::kInput, kInputTrueNormal, 2},
                                            {Op::kBevel, samples, 3, 0, 1, 2, kU},
                                            {Op::kVectorMath, multiply_add, 5, 3, 4, 4}},
                                           {glm::vec4(radius), glm::vec4(0.0f), glm::vec4(0.0f),
                                            glm::vec4(0.0f), glm::vec4(0.5f), glm::vec4(0.0f)}));
  m.outputs[kEmissionField] = 5;
  return Material(m);
}

// The mean BEVEL normal (decoded from the emission) of a render of `scene`, and its
// statistics.
Vec3 mean_colour(const Scene& scene, RenderStats* stats = nullptr) {
  const Settings settings = testing::small_render(2, 2, 4, 1, 8);
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  const std::vector<float> pixels = job.film().pixels();
  Vec3 sum(0.0f);
  for (size_t i = 0; i < pixels.size(); i += 4)
    sum += Vec3(pixels[i], pixels[i + 1], pixels[i + 2]);
  if (stats != nullptr) *stats = job.stats();
  return 2.0f * sum / static_cast<float>(pixels.size() / 4) - Vec3(1.0f);
}

// The top (z = 0) of a box 2 wide about the origin, 2 deep, seen straight down at
// (x, 0) over a window 0.002 wide.
Scene box_top(const Material& material, float x) {
  Scene scene;
  add_object(&scene, "box", testing::box(Vec3(-1.0f, -1.0f, -2.0f), Vec3(1.0f, 1.0f, 0.0f)),
             material);
  scene.camera = testing::looking_down(Vec3(x, 0.0f, 5.0f), 2e-4f);
  return scene;
}

TEST(Bevel, AFlatFloorKeepsItsNormal) {
  RenderStats stats;
  const Vec3 n = mean_colour(floor_beside_wall(bevel_emitter(0.1f, 8), 0.0f), &stats);
  EXPECT_NEAR(n.x, 0.0f, 1e-5f);
  EXPECT_NEAR(n.y, 0.0f, 1e-5f);
  EXPECT_NEAR(n.z, 1.0f, 1e-5f);
  // 4 pixels of 16 samples, 8 probes each, one query or more each.
  EXPECT_GE(stats.rays.bevel, 4u * 16u * 8u);
}

TEST(Bevel, TheNormalTurnsTowardsTheSideAcrossAnEdgeSymmetrically) {
  // 0.02 from the edge at x = 1 (and at x = -1), radius 0.1: the side's normals (+x)
  // weigh in, and the average turns that way; mirrored, the other way by as much.
  const Vec3 right = mean_colour(box_top(bevel_emitter(0.1f, 16), 0.98f));
  const Vec3 left = mean_colour(box_top(bevel_emitter(0.1f, 16), -0.98f));
  EXPECT_GT(right.x, 0.1f);
  EXPECT_LT(right.z, 0.99f);
  EXPECT_NEAR(left.x, -right.x, 0.02f);
  EXPECT_NEAR(left.z, right.z, 0.02f);
  // Far from every edge, the top's own normal.
  const Vec3 middle = mean_colour(box_top(bevel_emitter(0.1f, 16), 0.0f));
  EXPECT_NEAR(middle.z, 1.0f, 1e-5f);
}

TEST(Bevel, NoRadiusNoSampleOrAHugeRadiusGiveASaneNormal) {
  for (const auto& [radius, samples] : {std::pair{0.0f, 8u}, {0.1f, 0u}, {-1.0f, 8u}}) {
    RenderStats stats;
    const Vec3 n = mean_colour(box_top(bevel_emitter(radius, samples), 0.98f), &stats);
    EXPECT_NEAR(n.x, 0.0f, 1e-6f) << radius << " " << samples;
    EXPECT_NEAR(n.z, 1.0f, 1e-6f) << radius << " " << samples;
    EXPECT_EQ(stats.rays.bevel, 0u);
  }
  // A radius far beyond the object: every probe's points weigh alike; a unit normal.
  const Vec3 n = mean_colour(box_top(bevel_emitter(1e30f, 8), 0.98f));
  EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
  EXPECT_LE(glm::length(n), 1.0f + 1e-3f);
}

}  // namespace
}  // namespace whitted
