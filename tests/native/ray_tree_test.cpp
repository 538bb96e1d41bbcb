// The inspector's ray tree against analytic scenes: the rays a Whitted recursion must
// trace (kinds, depths, directions by the reflection law and Snell's law, total internal
// reflection), and contributions that sum to the pixel the render computes.
#include "integrator/ray_tree.h"

#include <gtest/gtest.h>

#include <cmath>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::clear;
using testing::glass_and_mirror_scene;
using testing::looking_down;
using testing::occluder_over_floor;
using testing::quad;

void finish(RenderJob* job) {
  job->start();
  while (!job->wait(1.0)) {
  }
}

Color film_pixel(const RenderJob& job, int x, int y) {
  const size_t i = 4 * (static_cast<size_t>(y) * job.settings().width + x);
  const auto& p = job.film().pixels();
  return {p[i], p[i + 1], p[i + 2]};
}

void expect_near(const Color& a, const Color& b, float tolerance, const char* what) {
  EXPECT_NEAR(a.x, b.x, tolerance) << what;
  EXPECT_NEAR(a.y, b.y, tolerance) << what;
  EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

// The rays of one kind that were traced (not cut), in the order recorded.
std::vector<const RayTreeNode*> of_kind(const RayTree& tree, TreeRayKind kind) {
  std::vector<const RayTreeNode*> out;
  for (const RayTreeNode& node : tree.nodes) {
    if (node.kind == kind && node.cut == TreeCut::kNone) out.push_back(&node);
  }
  return out;
}

// Every pixel of a scene with every effect, in each anti-aliasing mode: the tree's
// contributions sum to the pixel the render wrote, and the tree's own pixel is the same.
TEST(RayTree, ContributionsSumToTheRenderedPixel) {
  const Scene scene = glass_and_mirror_scene();
  for (AntiAliasing mode :
       {AntiAliasing::kRegular, AntiAliasing::kJittered, AntiAliasing::kAdaptive}) {
    Settings settings;
    settings.width = 24;
    settings.height = 16;
    settings.aa_mode = mode;
    settings.aa_samples = mode == AntiAliasing::kAdaptive ? 1 : 2;
    settings.aa_threshold = 0.05f;
    RenderJob job(scene, settings, scene.camera);
    finish(&job);
    for (int y = 0; y < settings.height; y += 3) {
      for (int x = 0; x < settings.width; x += 2) {
        const RayTree tree = job.inspect(x, y);
        const Color rendered = film_pixel(job, x, y);
        const float tolerance = 1e-5f * std::max(1.0f, max_component(rendered));
        expect_near(tree.pixel, rendered, tolerance, "the inspector's pixel is the render's");
        expect_near(tree.total(), rendered, tolerance, "the contributions sum to the pixel");
      }
    }
  }
}

// A mirror (z = 0) under a camera looking straight down, a diffuse ceiling (z = 3,
// facing down) behind the camera, a point light between: camera ray, its reflection by
// r = u - 2(u.n)n, a feeler from each surface, and the ceiling's light in the pixel.
TEST(RayTree, MirrorReflectsTheCameraRayByTheReflectionLaw) {
  Scene scene;
  Material mirror;
  mirror.diffuse = Color(0.0f);
  mirror.ambient = 0.0f;
  mirror.reflectivity = Color(0.8f);
  add_object(&scene, "mirror", quad(-4, 4, -4, 4, 0), mirror);
  Material ceiling;
  ceiling.diffuse = Color(0.5f);
  ceiling.ambient = 0.0f;
  // Wound to face down (towards the mirror).
  const glm::mat4 flip = glm::rotate(glm::mat4(1.0f), kPi, Vec3(1.0f, 0.0f, 0.0f));
  add_object(&scene, "ceiling", quad(-40, 40, -40, 40, -3), ceiling, flip);
  Light light;
  light.color = Color(20.0f);
  light.position = Vec3(0.5f, 0.5f, 1.5f);
  scene.set_light("lamp", light);
  scene.set_background(Color(0.0f));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 2.0f), 0.5f);
  Settings settings;
  settings.width = settings.height = 8;
  const RenderJob job(scene, settings, scene.camera);
  const RayTree tree = job.inspect(5, 2);

  const auto cameras = of_kind(tree, TreeRayKind::kCamera);
  const auto reflections = of_kind(tree, TreeRayKind::kReflection);
  ASSERT_EQ(cameras.size(), 1u);
  ASSERT_EQ(reflections.size(), 1u);
  // A feeler from each surface; only the ceiling's is sent: the mirror has no diffuse
  // or specular term, so its light cannot change the pixel (cut as "unshadowed").
  ASSERT_EQ(of_kind(tree, TreeRayKind::kShadow).size(), 1u);
  EXPECT_EQ(tree.nodes.size(), 4u);
  const RayTreeNode& camera = *cameras[0];
  const RayTreeNode& reflection = *reflections[0];
  EXPECT_EQ(camera.depth, 0);
  EXPECT_TRUE(camera.hit);
  EXPECT_EQ(reflection.depth, 1);
  EXPECT_EQ(&tree.nodes[static_cast<size_t>(reflection.parent)], &camera);
  const Vec3 n(0.0f, 0.0f, 1.0f);
  const Vec3 expected = camera.direction - 2.0f * glm::dot(camera.direction, n) * n;
  EXPECT_NEAR(glm::dot(reflection.direction, expected), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(reflection.origin - camera.end), 0.0f, 1e-4f);
  expect_near(reflection.weight, Color(0.8f), 1e-6f, "sigma_r on the pixel");
  EXPECT_TRUE(reflection.hit);
  EXPECT_NEAR(reflection.end.z, 3.0f, 1e-4f);
  // The ceiling's diffuse term: kd/pi * I cos / r^2, times sigma_r.
  const Vec3 to_light = light.position - reflection.end;
  const float r2 = glm::dot(to_light, to_light);
  const float cos_l = -to_light.z / std::sqrt(r2) * -1.0f;
  const float expected_diffuse = 0.8f * 0.5f / kPi * 20.0f * std::abs(cos_l) / r2;
  EXPECT_NEAR(tree.total().x, expected_diffuse, 1e-4f * expected_diffuse);
  EXPECT_NEAR(tree.pixel.x, expected_diffuse, 1e-4f * expected_diffuse);
}

// A camera ray into a glass slab (ior 1.5) at 30 degrees: the refracted ray bends by
// Snell's law, sin(t) = sin(30) / 1.5, and leaves the slab parallel to where it came in.
TEST(RayTree, GlassSlabRefractsBySnellsLaw) {
  Scene scene;
  // One mesh, so both faces bound one medium: the top (z = 0) facing +z, the bottom
  // (z = -1) facing -z.
  const float p[] = {-50, -50, 0,  50, -50, 0,  50, 50, 0,  -50, 50, 0,
                     -50, -50, -1, 50, -50, -1, 50, 50, -1, -50, 50, -1};
  const uint32_t t[] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
  add_object(&scene, "slab", make_mesh(p, 8, t, 4, nullptr, nullptr), clear(1.5f));
  scene.set_background(Color(0.2f, 0.4f, 0.6f));
  Camera camera = looking_down(Vec3(0.0f, 0.0f, 1.0f), 1e-3f);
  // Tilted 30 degrees about x: the camera ray meets the slab at 30 degrees incidence.
  camera.to_world = glm::rotate(camera.to_world, glm::radians(30.0f), Vec3(1.0f, 0.0f, 0.0f));
  Settings settings;
  settings.width = settings.height = 1;
  const RenderJob job(scene, settings, camera);
  const RayTree tree = job.inspect(0, 0);
  // Into the slab, and out of it through the bottom (the first ray the refracted one
  // spawns is its reflection inside the slab, whose own ray leaves through the top).
  const auto refractions = of_kind(tree, TreeRayKind::kRefraction);
  ASSERT_GE(refractions.size(), 2u);
  const RayTreeNode& in = *refractions[0];
  const RayTreeNode* child = nullptr;
  for (const RayTreeNode* r : refractions) {
    if (r->parent >= 0 && &tree.nodes[static_cast<size_t>(r->parent)] == &in) child = r;
  }
  ASSERT_NE(child, nullptr);
  const RayTreeNode& out = *child;
  EXPECT_EQ(in.depth, 1);
  EXPECT_EQ(out.depth, 2);
  const float sin_in = std::sqrt(1.0f - in.direction.z * in.direction.z);
  EXPECT_NEAR(sin_in, 0.5f / 1.5f, 1e-5f);
  const RayTreeNode& camera_ray = *of_kind(tree, TreeRayKind::kCamera)[0];
  EXPECT_NEAR(glm::dot(out.direction, camera_ray.direction), 1.0f, 1e-5f);
  EXPECT_FALSE(out.hit);
  EXPECT_GT(out.background.z, 0.0f);  // what comes through is the background
  // Each surface also reflects (Fresnel): reflection rays exist at both interfaces.
  EXPECT_GE(of_kind(tree, TreeRayKind::kReflection).size(), 2u);
  expect_near(tree.total(), tree.pixel, 1e-6f, "the contributions sum to the pixel");
}

// Inside glass (ior 1.5), a ray meeting the surface at 60 degrees (beyond the critical
// angle, 41.8) cannot leave: its one secondary ray is a total internal reflection.
TEST(RayTree, SteepRayInsideGlassIsTotallyReflected) {
  Scene scene;
  const Material glass = clear(1.5f);
  // A closed box of glass around the camera, wide enough that the ray meets its bottom
  // first: its faces wound outwards.
  const float p[] = {-20, -20, -5, 20, -20, -5, 20, 20, -5, -20, 20, -5,
                     -20, -20, 5,  20, -20, 5,  20, 20, 5,  -20, 20, 5};
  const uint32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                        2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
  add_object(&scene, "box", make_mesh(p, 8, t, 12, nullptr, nullptr), glass);
  Camera camera = looking_down(Vec3(0.0f, 0.0f, 0.0f), 1e-3f);
  camera.to_world = glm::rotate(camera.to_world, glm::radians(60.0f), Vec3(1.0f, 0.0f, 0.0f));
  Settings settings;
  settings.width = settings.height = 1;
  settings.max_depth = 1;
  const RenderJob job(scene, settings, camera);
  const RayTree tree = job.inspect(0, 0);
  ASSERT_EQ(of_kind(tree, TreeRayKind::kRefraction).size(), 0u);
  const auto tir = of_kind(tree, TreeRayKind::kTotalInternalReflection);
  ASSERT_EQ(tir.size(), 1u);
  EXPECT_EQ(tir[0]->depth, 1);
  expect_near(tir[0]->weight, Color(1.0f), 1e-6f, "all of it is reflected");
  // Depth 1 is the limit: the reflected ray's own secondary rays are cut, and said so.
  bool depth_cut = false;
  for (const RayTreeNode& node : tree.nodes) depth_cut |= node.cut == TreeCut::kDepth;
  EXPECT_TRUE(depth_cut);
}

TEST(RayTree, FeelerNamesItsBlockerAndPixelsOutsideTheImageAreRefused) {
  const Scene scene = occluder_over_floor(3.0f);
  Settings settings;
  settings.width = settings.height = 31;
  const RenderJob job(scene, settings, scene.camera);
  // The blocker hides |y| < 0.125 of the view at unit distance; its shadow on the floor
  // is |y| < 0.2 there. Pixel row 16 looks at y = 0.194: the floor, in the shadow.
  const RayTree shadowed = job.inspect(15, 16);
  const CompiledScene& compiled = job.scene();
  bool blocked = false;
  for (const RayTreeNode& node : shadowed.nodes) {
    if (node.kind != TreeRayKind::kShadow || node.cut != TreeCut::kNone) continue;
    if (is_black(node.transmittance)) {
      blocked = true;
      ASSERT_TRUE(node.hit);
      EXPECT_EQ(compiled.instances[static_cast<size_t>(node.instance)].name, "blocker");
      EXPECT_EQ(compiled.light_names[static_cast<size_t>(node.light)], "light");
    }
  }
  EXPECT_TRUE(blocked);
  EXPECT_THROW(job.inspect(31, 0), std::out_of_range);
  EXPECT_THROW(job.inspect(0, 0, 1), std::out_of_range);  // one sample per pixel
}

// A tree in fog: each camera ray ends on the fog box's bound and goes on behind it within
// its own sample; each stretch inside the fog is a volume segment under its ray, and the
// feelers from its scatter points start on it, name their light and carry the light
// scattered there; the contributions, the fog's emission and scattering among them, still
// sum to the rendered pixel.
TEST(RayTree, FogSegmentsHoldTheirScatterFeelersAndTheTreeSumsToThePixel) {
  const Scene scene =
      testing::foggy_glass_and_mirror_scene(Color(0.15f, 0.1f, 0.05f), Color(0.05f));
  Settings settings;
  settings.width = 24;
  settings.height = 16;
  settings.aa_samples = 2;
  RenderJob job(scene, settings, scene.camera);
  finish(&job);
  const CompiledScene& compiled = job.scene();
  int segments = 0;
  int scatter_feelers = 0;
  Color scattered(0.0f);
  for (int y = 0; y < settings.height; y += 3) {
    for (int x = 0; x < settings.width; x += 2) {
      const RayTree tree = job.inspect(x, y);
      const Color rendered = film_pixel(job, x, y);
      const float tolerance = 1e-5f * std::max(1.0f, max_component(rendered));
      expect_near(tree.pixel, rendered, tolerance, "the inspector's pixel is the render's");
      expect_near(tree.total(), rendered, tolerance, "the contributions sum to the pixel");
      EXPECT_EQ(tree.roots, 4) << "one camera ray, so one sample, per grid sample";
      for (const RayTreeNode& node : tree.nodes) {
        if (node.kind == TreeRayKind::kCamera) {
          ASSERT_TRUE(node.hit);  // the fog box's top covers the view
          EXPECT_EQ(compiled.instances[static_cast<size_t>(node.instance)].name, "fog");
        }
        if (node.kind == TreeRayKind::kVolume) {
          segments += 1;
          ASSERT_GE(node.parent, 0);
          const RayTreeNode& ray = tree.nodes[static_cast<size_t>(node.parent)];
          EXPECT_NE(ray.kind, TreeRayKind::kShadow);
          EXPECT_NEAR(glm::length(glm::cross(node.origin - ray.origin, ray.direction)), 0.0f, 1e-3f)
              << "a segment lies on its ray";
          EXPECT_LT(max_component(node.transmittance), 1.0f);
        }
        if (node.kind != TreeRayKind::kShadow || node.parent < 0) continue;
        const RayTreeNode& from = tree.nodes[static_cast<size_t>(node.parent)];
        if (from.kind != TreeRayKind::kVolume) continue;
        scatter_feelers += 1;
        // A lamp, or the glowing fog itself (its emission, scattered: glow.h); the scene has
        // no emitter and no world light.
        const bool glow = node.emitter >= 0 &&
                          compiled.instances[static_cast<size_t>(node.emitter)].name == "fog";
        EXPECT_TRUE(node.light >= 0 || glow) << node.light << " " << node.emitter;
        const Vec3 along = node.origin - from.origin;
        EXPECT_NEAR(glm::length(glm::cross(along, from.direction)), 0.0f, 1e-3f)
            << "a scatter point lies on its segment";
        EXPECT_LE(glm::length(along), glm::length(from.end - from.origin) + 1e-3f);
        if (node.cut == TreeCut::kNone) scattered += node.scattered * node.transmittance;
      }
    }
  }
  EXPECT_GT(segments, 0);
  EXPECT_GT(scatter_feelers, 0);
  EXPECT_GT(max_component(scattered), 0.0f);
}

}  // namespace
}  // namespace whitted
