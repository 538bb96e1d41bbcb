// Curves (hair strands) and points (a point cloud) beside a mesh's triangles: a ray meets
// a strand's round tube (Catmull-Rom, or linear with round ends) and a point's sphere
// where the geometry says, with a normal from the axis or the centre; a flat strand (a
// ribbon) faces the ray, shaded as a tube; a lit strand shades without acne, round or
// flat, also lying half in a floor, and shadows the floor; strands far thinner
// than a pixel, zero radii and degenerate segments stay finite; a strand shows through
// glass and in a mirror; materials follow each strand's slot; threads and tiles change
// no pixel.
#include <gtest/gtest.h>

#include <cmath>

#include "integrator/whitted.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::looking_down;
using testing::quad;

Material white() {
  Material m;
  m.ambient = 0.0f;
  return m;
}

// A mesh holding only strands: `strands` of keys (x, y, z, radius).
Mesh strands_mesh(const std::vector<std::vector<float>>& strands,
                  const std::vector<int32_t>& slots = {}, bool linear = false, bool flat = false) {
  std::vector<float> keys;
  std::vector<uint32_t> counts;
  for (const std::vector<float>& s : strands) {
    keys.insert(keys.end(), s.begin(), s.end());
    counts.push_back(static_cast<uint32_t>(s.size() / 4));
  }
  Mesh mesh = make_mesh(nullptr, 0, nullptr, 0, nullptr, nullptr);
  mesh.curves = make_curves(keys.data(), keys.size() / 4, counts.data(), counts.size(),
                            slots.empty() ? nullptr : slots.data(), linear, flat);
  return mesh;
}

Mesh points_mesh(const std::vector<float>& spheres) {
  Mesh mesh = make_mesh(nullptr, 0, nullptr, 0, nullptr, nullptr);
  mesh.points = make_points(spheres.data(), spheres.size() / 4, nullptr);
  return mesh;
}

// The first hit of a ray straight down from (x, y, 10).
bool hit_from_above(const Scene& scene, float x, float y, Interaction* out) {
  const auto compiled = scene.compile();
  const Ray ray{Vec3(x, y, 10.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
  Hit hit;
  if (!compiled->accel->intersect(ray, &hit)) return false;
  *out = compiled->interaction(ray, hit);
  return true;
}

TEST(Curves, ARayMeetsAStrandsTubeWhereItIs) {
  Scene scene;
  // Along X at height 1, radius 0.1 (three keys: a straight Catmull-Rom line).
  add_object(&scene, "hair", strands_mesh({{-1, 0, 1, 0.1f, 0, 0, 1, 0.1f, 1, 0, 1, 0.1f}}),
             white());
  Interaction it;
  ASSERT_TRUE(hit_from_above(scene, 0.3f, 0.0f, &it));
  EXPECT_NEAR(it.position.z, 1.1f, 1e-3f);  // the top of the tube
  EXPECT_NEAR(it.geometric_normal.z, 1.0f, 1e-3f);
  // Off the axis by half the radius: the tube's surface there, its normal leaning out.
  ASSERT_TRUE(hit_from_above(scene, 0.3f, 0.05f, &it));
  const float expected = 1.0f + std::sqrt(0.01f - 0.0025f);
  EXPECT_NEAR(it.position.z, expected, 1e-3f);
  EXPECT_NEAR(it.geometric_normal.y, 0.5f, 2e-2f);
  EXPECT_GT(it.position_error.x, 0.0f);
  // Beside it: nothing.
  EXPECT_FALSE(hit_from_above(scene, 0.3f, 0.2f, &it));
}

// Linear strands (Cycles 5.x's Thick Linear) are cones with round joints and ends.
TEST(Curves, ALinearStrandHasRoundEnds) {
  Scene scene;
  add_object(&scene, "hair",
             strands_mesh({{-1, 0, 1, 0.1f, 0, 0, 1, 0.1f, 1, 0, 1, 0.1f}}, {}, true), white());
  Interaction it;
  ASSERT_TRUE(hit_from_above(scene, 0.3f, 0.0f, &it));
  EXPECT_NEAR(it.position.z, 1.1f, 1e-4f);
  EXPECT_NEAR(it.geometric_normal.z, 1.0f, 1e-4f);
  // Past the last key by half the radius: its round end.
  ASSERT_TRUE(hit_from_above(scene, 1.05f, 0.0f, &it));
  EXPECT_NEAR(it.position.z, 1.0f + std::sqrt(0.01f - 0.0025f), 1e-4f);
  EXPECT_NEAR(it.geometric_normal.x, 0.5f, 1e-3f);
}

// A flat strand (Cycles' Ribbons) is a ribbon through its axis turned to face the ray:
// the hit lies at the axis's depth, the geometric normal is -d, and the shading normal is
// the round tube's where its outline meets the hit (half the radius off the axis: leaning
// out by 30 degrees, sin = 0.5).
TEST(Curves, AFlatStrandFacesTheRayAndShadesAsATube) {
  for (const bool linear : {false, true}) {
    Scene scene;
    add_object(&scene, "hair",
               strands_mesh({{-1, 0, 1, 0.1f, 0, 0, 1, 0.1f, 1, 0, 1, 0.1f}}, {}, linear, true),
               white());
    Interaction it;
    ASSERT_TRUE(hit_from_above(scene, 0.3f, 0.0f, &it)) << linear;
    EXPECT_NEAR(it.position.z, 1.0f, 1e-4f);  // the axis's depth, not the tube's top
    EXPECT_NEAR(it.geometric_normal.z, 1.0f, 1e-6f);
    EXPECT_NEAR(it.shading_normal.z, 1.0f, 1e-4f);
    EXPECT_NEAR(glm::length(it.shading_normal), 1.0f, 1e-5f);
    for (const float y : {0.05f, -0.05f}) {
      ASSERT_TRUE(hit_from_above(scene, 0.3f, y, &it)) << linear << " " << y;
      EXPECT_NEAR(it.position.z, 1.0f, 1e-4f);
      EXPECT_NEAR(it.geometric_normal.z, 1.0f, 1e-6f);
      EXPECT_NEAR(it.shading_normal.y, y / 0.1f, 1e-3f);
      EXPECT_NEAR(it.shading_normal.z, std::sqrt(0.75f), 1e-3f);
    }
    EXPECT_FALSE(hit_from_above(scene, 0.3f, 0.11f, &it));
    // A ray at 60 degrees to the strand's normal plane still meets a ribbon facing it: the
    // geometric normal is -d, the shading normal faces it (square to the strand).
    const auto compiled = scene.compile();
    const Vec3 d = glm::normalize(Vec3(0.0f, 1.0f, -0.6f));
    const Ray ray{Vec3(0.3f, 0.0f, 1.0f) - 5.0f * d, d, 0.0f, kInfinity, kCameraRay};
    Hit hit;
    ASSERT_TRUE(compiled->accel->intersect(ray, &hit)) << linear;
    it = compiled->interaction(ray, hit);
    EXPECT_NEAR(glm::dot(it.geometric_normal, -d), 1.0f, 1e-5f);
    EXPECT_GT(glm::dot(it.shading_normal, -d), 0.99f);
    EXPECT_NEAR(it.shading_normal.x, 0.0f, 1e-4f);
  }
}

// A ribbon's shadow feelers leave from the hit, as Cycles' do, and never meet the ribbon
// they leave (Embree ignores it within twice its radius of their origin), wherever across
// the ribbon the hit lies and whatever the light's direction but within 30 degrees of the
// strand (there the ribbon further along lies in the way: a ribbon's own shadow, which
// Cycles' ribbons show too); a feeler towards another strand beside it is still blocked.
TEST(Curves, AFlatStrandsFeelersLeaveIt) {
  Scene scene;
  // A strand of five keys along X at height 1, radius 0.05.
  add_object(&scene, "hair",
             strands_mesh({{-1, 0,     1,    0.05f, -0.5f, 0,     1, 0.05f, 0, 0,
                            1,  0.05f, 0.5f, 0,     1,     0.05f, 1, 0,     1, 0.05f}},
                          {}, false, true),
             white());
  const auto compiled = scene.compile();
  int feelers = 0;
  for (float y = -0.04f; y <= 0.04f; y += 0.01f) {
    for (float x = -0.6f; x <= 0.6f; x += 0.15f) {
      const Ray down{Vec3(x, y, 10.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
      Hit hit;
      if (!compiled->accel->intersect(down, &hit)) continue;
      const Interaction it = compiled->interaction(down, hit);
      for (float theta = 0.05f; theta < kPi; theta += 0.2f) {
        for (float phi = 0.0f; phi < 2.0f * kPi; phi += 0.3f) {
          const Vec3 wi(std::cos(theta), std::sin(theta) * std::cos(phi),
                        std::sin(theta) * std::sin(phi));
          if (std::abs(wi.x) > std::cos(kPi / 6)) continue;
          const Ray feeler = spawn_ray(it.shadow_origin, it.position_error, it.geometric_normal,
                                       it.time, wi, kShadowRay);
          EXPECT_FALSE(compiled->accel->occluded(feeler))
              << x << " " << y << " towards " << wi.x << " " << wi.y << " " << wi.z;
          ++feelers;
        }
      }
    }
  }
  EXPECT_GT(feelers, 500);
  // A second strand beside the first (y = 0.3): a feeler towards it is blocked.
  add_object(&scene, "other",
             strands_mesh({{-1, 0.3f, 1, 0.05f, 1, 0.3f, 1, 0.05f}}, {}, false, true), white());
  const auto both = scene.compile();
  const Ray down{Vec3(0.05f, 0.0f, 10.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
  Hit hit;
  ASSERT_TRUE(both->accel->intersect(down, &hit));
  const Interaction it = both->interaction(down, hit);
  EXPECT_TRUE(
      both->accel->occluded(spawn_ray(it.shadow_origin, it.position_error, it.geometric_normal,
                                      it.time, Vec3(0, 1, 0), kShadowRay)));
}

TEST(Points, ARayMeetsAPointsSphere) {
  Scene scene;
  add_object(&scene, "dust", points_mesh({0, 0, 1, 0.25f, 2, 0, 1, 0.25f}), white());
  Interaction it;
  ASSERT_TRUE(hit_from_above(scene, 2.0f, 0.0f, &it));
  EXPECT_NEAR(it.position.z, 1.25f, 1e-4f);
  EXPECT_NEAR(it.geometric_normal.z, 1.0f, 1e-4f);
  ASSERT_TRUE(hit_from_above(scene, 0.1f, 0.0f, &it));
  EXPECT_NEAR(it.geometric_normal.x, 0.4f, 1e-3f);
  EXPECT_FALSE(hit_from_above(scene, 1.0f, 0.0f, &it));
}

// A thick strand under a sun, seen from above: its lit top shades evenly (no speck of
// self-shadow), and the floor under it shows its shadow.
Scene lit_strand(float radius) {
  Scene scene;
  add_object(&scene, "floor", quad(-5, 5, -5, 5, 0), white());
  add_object(&scene, "hair",
             strands_mesh({{-2, 0, 0.5f, radius, 0, 0, 0.5f, radius, 2, 0, 0.5f, radius}}),
             white());
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = Vec3(0.0f, 0.0f, -1.0f);
  scene.set_light("sun", sun);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.6f);
  return scene;
}

Settings small(int threads, int tile) {
  return testing::small_render(41, 41, 2, threads, tile);
}

TEST(Curves, ALitStrandShadesWithoutAcneAndCastsItsShadow) {
  const Scene scene = lit_strand(0.2f);
  const std::vector<float> pixels = testing::render_pixels(scene, small(1, 64));
  // The middle row runs along the strand's top (the view is 2.7 m across there, a row
  // 0.07 m); facing the sun, the tube's top is about as bright as the unshadowed floor
  // (0.8 / pi * 3), and no pixel there is dark.
  const int row = 20;
  for (int x = 0; x < 41; ++x) {
    const float v = pixels[4 * (row * 41 + x)];
    EXPECT_NEAR(v, 0.8f / kPi * 3.0f, 0.01f) << x;
  }
  // Just outside the tube, the floor is in its shadow: dark.
  Scene floor_only = lit_strand(0.2f);
  Interaction it;
  const auto compiled = floor_only.compile();
  const Ray down{Vec3(0.0f, 0.25f, 3.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
  Hit hit;
  ASSERT_TRUE(compiled->accel->intersect(down, &hit));
  it = compiled->interaction(down, hit);
  EXPECT_NEAR(it.position.z, 0.0f, 1e-5f);  // the floor, beside the strand
  const Ray up{Vec3(0.0f, 0.1f, 0.0f) + Vec3(0.0f, 0.0f, 1e-4f), Vec3(0.0f, 0.0f, 1.0f), 0.0f,
               kInfinity, kShadowRay};
  EXPECT_TRUE(compiled->accel->occluded(up));  // under the strand: shadowed
}

// A ribbon lit by a sun from the side (45 degrees from the view, across the strand),
// seen from above, the view (0.36 m across at the strand) within its 0.4 m width: each row
// of pixels looks at one place across it and shades as the tube it stands for, by the
// cosine of its bent normal: every pixel of a row alike (no speck of self-shadow), up to
// the full 0.8/pi*3 where the normal faces the sun and 0 past the tube's terminator, one
// rise and one fall between.
TEST(Curves, ALitRibbonShadesAsATubeWithoutAcne) {
  Scene scene;
  add_object(&scene, "floor", quad(-5, 5, -5, 5, 0), white());
  add_object(
      &scene, "hair",
      strands_mesh({{-2, 0, 0.5f, 0.2f, 0, 0, 0.5f, 0.2f, 2, 0, 0.5f, 0.2f}}, {}, false, true),
      white());
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = -glm::normalize(Vec3(0.0f, 1.0f, 1.0f));
  scene.set_light("sun", sun);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.04f);
  const std::vector<float> pixels = testing::render_pixels(scene, small(2, 16));
  std::vector<float> across;
  for (int row = 0; row < 41; ++row) {
    const float first = pixels[4 * (row * 41)];
    for (int x = 1; x < 41; ++x) EXPECT_NEAR(pixels[4 * (row * 41 + x)], first, 1e-4f) << row;
    across.push_back(first);
  }
  const float brightest = *std::max_element(across.begin(), across.end());
  EXPECT_NEAR(brightest, 0.8f / kPi * 3.0f, 0.01f);
  EXPECT_EQ(*std::min_element(across.begin(), across.end()), 0.0f);
  int turns = 0;  // rises then falls (or falls then rises, by the image's row order)
  for (size_t i = 2; i < across.size(); ++i) {
    const float before = across[i - 1] - across[i - 2], after = across[i] - across[i - 1];
    if ((before > 1e-4f && after < -1e-4f) || (before < -1e-4f && after > 1e-4f)) ++turns;
  }
  EXPECT_EQ(turns, 1);
}

TEST(Curves, ThinZeroAndDegenerateStrandsStayFinite) {
  Scene scene = lit_strand(1e-4f);  // far thinner than a pixel (0.03 wide)
  add_object(&scene, "zero", strands_mesh({{-1, 1, 0.5f, 0, 1, 1, 0.5f, 0}}), white());
  // Repeated keys (a zero-length segment), a strand of one key, a point of radius 0.
  add_object(&scene, "degenerate",
             strands_mesh({{0, -1, 0.5f, 0.05f, 0, -1, 0.5f, 0.05f}, {1, -1, 0.5f, 0.05f}}),
             white());
  add_object(&scene, "dot", points_mesh({0.5f, 0.5f, 0.5f, 0.0f}), white());
  for (float v : testing::render_pixels(scene, small(2, 8))) ASSERT_TRUE(std::isfinite(v));
}

TEST(Curves, EachStrandTakesItsSlotsMaterial) {
  Scene scene;
  Material red = white();
  red.diffuse = Color(0.8f, 0.0f, 0.0f);
  Material blue = white();
  blue.diffuse = Color(0.0f, 0.0f, 0.8f);
  scene.set_material("red", red);
  scene.set_material("blue", blue);
  scene.set_mesh("hair", strands_mesh({{-1, -0.5f, 1, 0.1f, 1, -0.5f, 1, 0.1f},
                                       {-1, 0.5f, 1, 0.1f, 1, 0.5f, 1, 0.1f}},
                                      {0, 1}));
  scene.set_instance("hair", Instance{"hair", glm::mat4(1.0f), {"red", "blue"}});
  const auto compiled = scene.compile();
  for (const auto& [y, name] : {std::pair{-0.5f, "red"}, std::pair{0.5f, "blue"}}) {
    const Ray ray{Vec3(0.0f, y, 10.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
    Hit hit;
    ASSERT_TRUE(compiled->accel->intersect(ray, &hit));
    EXPECT_EQ(compiled->material_names[compiled->interaction(ray, hit).material_index], name);
  }
}

// A strand lying in the floor (its axis on the plane: half of it below): the half above
// shades evenly under the sun, without specks of the floor's or its own shadow.
TEST(Curves, AStrandCoincidentWithASurfaceShowsNoAcne) {
  Scene scene;
  add_object(&scene, "floor", quad(-5, 5, -5, 5, 0), white());
  add_object(&scene, "hair", strands_mesh({{-2, 0, 0, 0.2f, 0, 0, 0, 0.2f, 2, 0, 0, 0.2f}}),
             white());
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = glm::normalize(Vec3(0.0f, 0.3f, -1.0f));
  scene.set_light("sun", sun);
  // A narrow view (0.1 m across at the strand): every pixel of row 20 on its top.
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.01f);
  const std::vector<float> pixels = testing::render_pixels(scene, small(2, 16));
  // Row 20 runs along the strand's top: its normal faces up, lit at the sun's cosine.
  const float expected = 0.8f / kPi * 3.0f * glm::dot(Vec3(0, 0, 1), -sun.direction);
  for (int x = 0; x < 41; ++x) EXPECT_NEAR(pixels[4 * (20 * 41 + x)], expected, 0.01f) << x;
}

// Seen through glass and in a mirror, a glowing strand shows as it does directly: the
// same recursion reaches it.
TEST(Curves, AStrandShowsThroughGlassAndInAMirror) {
  const auto centre = [](const Scene& scene) {
    const std::vector<float> pixels = testing::render_pixels(scene, small(1, 64));
    return pixels[4 * (20 * 41 + 20)];
  };
  const auto glowing = [](Vec3 at) {
    Scene scene;
    add_object(&scene, "hair",
               strands_mesh({{at.x - 2, at.y, at.z, 0.2f, at.x, at.y, at.z, 0.2f, at.x + 2, at.y,
                              at.z, 0.2f}}),
               testing::emitter(Color(1.0f)));
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.01f);
    return scene;
  };
  Scene direct = glowing(Vec3(0.0f));
  EXPECT_NEAR(centre(direct), 1.0f, 1e-5f);
  // Under a clear pane of index 1 (no bending, no Fresnel reflection head-on).
  add_object(&direct, "pane", quad(-3, 3, -3, 3, 2.0f), testing::clear(1.0f));
  EXPECT_NEAR(centre(direct), 1.0f, 1e-3f);
  // Off to the side (y = 3), seen in a mirror at 45 degrees under the camera.
  Scene mirrored = glowing(Vec3(0.0f, 3.0f, 0.0f));
  Material mirror = white();
  mirror.diffuse = Color(0.0f);
  mirror.reflectivity = Color(1.0f);
  const float corners[] = {-1, -1, 1, 1, -1, 1, 1, 1, -1, -1, 1, -1};
  const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
  add_object(&mirrored, "mirror", make_mesh(corners, 4, triangles, 2, nullptr, nullptr), mirror);
  EXPECT_NEAR(centre(mirrored), 1.0f, 1e-3f);
}

TEST(Curves, ThreadsAndTilesChangeNoPixel) {
  Scene scene = lit_strand(0.05f);
  add_object(&scene, "dust", points_mesh({0.3f, 0.3f, 0.3f, 0.1f, -0.3f, 0.2f, 0.4f, 0.05f}),
             white());
  const std::vector<float> reference = testing::render_pixels(scene, small(1, 64));
  for (auto [threads, tile] : {std::pair{2, 5}, std::pair{3, 16}}) {
    EXPECT_TRUE(testing::render_pixels(scene, small(threads, tile)) == reference) << threads;
  }
}

}  // namespace
}  // namespace whitted
