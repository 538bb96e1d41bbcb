// The render job: determinism across threads and tiles, prompt cancellation, validation.
#include "integrator/render.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "scene_builders.h"

namespace whitted {
namespace {

using testing::glass_and_mirror_scene;
using testing::quad;

std::vector<float> render(const Scene& scene, Settings settings) {
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return job.film().pixels();
}

TEST(Render, ImageIsBitIdenticalWhateverTheThreadCountAndTileSize) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 67;
  settings.height = 45;
  settings.aa_samples = 2;
  settings.threads = 1;
  settings.tile_size = 64;
  const std::vector<float> reference = render(scene, settings);
  for (auto [threads, tile] : {std::pair{2, 7}, std::pair{4, 16}, std::pair{3, 1}}) {
    settings.threads = threads;
    settings.tile_size = tile;
    EXPECT_TRUE(render(scene, settings) == reference) << threads << " threads, tile " << tile;
  }
}

TEST(Render, EveryTileIsReportedOnceAndProgressReachesOne) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 50;
  settings.height = 30;
  settings.tile_size = 16;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  int pixels = 0;
  for (const Tile& t : job.take_finished_tiles()) pixels += t.width * t.height;
  EXPECT_EQ(pixels, 50 * 30);
  EXPECT_FLOAT_EQ(job.progress(), 1.0f);
  const RenderStats stats = job.stats();
  EXPECT_EQ(stats.rays.camera, 50u * 30u);
  EXPECT_FALSE(stats.cancelled);
}

TEST(Render, CancelStopsPromptly) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 4096;
  settings.height = 4096;
  settings.aa_samples = 4;  // minutes of work
  settings.threads = 2;
  RenderJob job(scene, settings, scene.camera);
  job.start();
  EXPECT_FALSE(job.wait(0.05));
  const auto t0 = std::chrono::steady_clock::now();
  job.cancel();
  EXPECT_TRUE(job.wait(5.0));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 0.2);
  EXPECT_TRUE(job.stats().cancelled);
  EXPECT_LT(job.progress(), 1.0f);
}

TEST(Render, BadSettingsAreRefusedWithAMessage) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 0;
  EXPECT_THROW(RenderJob(scene, settings, scene.camera), std::invalid_argument);
  settings.width = 65536;
  settings.height = 65536;  // 64 GiB of pixels
  EXPECT_THROW(RenderJob(scene, settings, scene.camera), std::invalid_argument);
  settings = Settings{};
  settings.max_depth = 100000;
  EXPECT_THROW(RenderJob(scene, settings, scene.camera), std::invalid_argument);
}

TEST(Render, MissingMeshOrMaterialIsAClearError) {
  Scene scene;
  scene.set_instance("orphan", Instance{"nothing", glm::mat4(1.0f), {}});
  EXPECT_THROW(RenderJob(scene, Settings{}, scene.camera), std::invalid_argument);
  Scene scene2;
  scene2.set_mesh("m", quad(0, 1, 0, 1, 0));
  scene2.set_instance("i", Instance{"m", glm::mat4(1.0f), {"no such material"}});
  EXPECT_THROW(RenderJob(scene2, Settings{}, scene2.camera), std::invalid_argument);
}

TEST(Render, AnEmptySceneRendersTheBackground) {
  Scene scene;
  scene.set_background(Color(0.1f, 0.2f, 0.3f));
  Settings settings;
  settings.width = 8;
  settings.height = 8;
  const std::vector<float> pixels = render(scene, settings);
  EXPECT_FLOAT_EQ(pixels[0], 0.1f);
  EXPECT_FLOAT_EQ(pixels[4 * 63 + 2], 0.3f);
  EXPECT_FLOAT_EQ(pixels[3], 1.0f);
}

TEST(Render, BadMeshesAreRefusedWithAMessage) {
  const float nan = std::nanf("");
  const float p[] = {0, 0, 0, 1, 0, 0, nan, 1, 0};
  const uint32_t t[] = {0, 1, 2};
  EXPECT_THROW(make_mesh(p, 3, t, 1, nullptr, nullptr), std::invalid_argument);
  const float q[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t bad[] = {0, 1, 3};
  EXPECT_THROW(make_mesh(q, 3, bad, 1, nullptr, nullptr), std::invalid_argument);
}

// Camera rays traced as a packet find exactly the hits single-ray queries find.
TEST(Render, PacketHitsAreTheSingleRayHits) {
  const Scene source = glass_and_mirror_scene();
  const auto scene = source.compile();
  constexpr int kPacket = SceneAccel::kIntersectPacketSize;
  for (int count = 1; count <= kPacket; ++count) {  // 4-, 8- and 16-wide packets
    for (int row = 0; row < 16; ++row) {
      Ray rays[kPacket];
      Hit hits[kPacket];
      for (int i = 0; i < count; ++i) {
        rays[i] = source.camera.generate_ray((static_cast<float>(i) + 0.5f) / kPacket,
                                             (static_cast<float>(row) + 0.5f) / 16.0f);
      }
      scene->accel->intersect_packet(rays, count, hits);
      for (int i = 0; i < count; ++i) {
        Hit single;
        const bool found = scene->accel->intersect(rays[i], &single);
        ASSERT_EQ(found, hits[i].t < kInfinity) << "row " << row << " lane " << i;
        if (!found) continue;
        EXPECT_EQ(hits[i].instance, single.instance);
        EXPECT_EQ(hits[i].primitive, single.primitive);
        EXPECT_NEAR(hits[i].t, single.t, 1e-5f * single.t);
      }
    }
  }
}

// Camera-ray packets change how rays are traced, not the image.
TEST(Render, PacketsDoNotChangeTheImage) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 60;  // three instances in 2,400 pixels: packets chosen
  settings.height = 40;
  // Blocks of 4 pixels of 4 rays (one 16-wide packet); one pixel of 9 rays (a part-filled
  // one); one pixel of 25 rays (a full one and a part-filled one).
  for (int n : {2, 3, 5}) {
    settings.aa_samples = n;
    settings.packets = true;
    ASSERT_TRUE(RenderJob(scene, settings, scene.camera).stats().camera_packets);  // chosen
    const std::vector<float> packets = render(scene, settings);
    settings.packets = false;
    EXPECT_EQ(render(scene, settings), packets) << n << "x" << n << " samples";
  }
}

// The packet choice (choose_packets, sampler.h) counts the instances the camera sees.
TEST(Render, PacketChoiceCountsTheInstancesInView) {
  Scene scene;
  testing::add_object(&scene, "quad", quad(-1, 1, -1, 1, 0), Material{});
  const Camera camera = testing::looking_down(Vec3(0.0f, 0.0f, 10.0f), 0.5f);
  Settings settings;
  settings.width = 100;
  settings.height = 100;
  const RenderStats seen = RenderJob(scene, settings, camera).stats();
  EXPECT_EQ(seen.visible_instances, 1u);
  EXPECT_FLOAT_EQ(seen.instances_per_pixel, 1e-4f);
  EXPECT_TRUE(seen.camera_packets);
  // Behind the camera, beside the image, or around the camera.
  const auto seen_from = [&](Vec3 position) {
    return RenderJob(scene, settings, testing::looking_down(position, 0.5f))
        .stats()
        .visible_instances;
  };
  EXPECT_EQ(seen_from(Vec3(0.0f, 0.0f, -10.0f)), 0u);
  EXPECT_EQ(seen_from(Vec3(30.0f, 0.0f, 10.0f)), 0u);
  EXPECT_EQ(seen_from(Vec3(0.5f, 0.0f, 0.5f)), 1u);
  // Packets off in the settings: never packets.
  settings.packets = false;
  EXPECT_FALSE(RenderJob(scene, settings, camera).stats().camera_packets);
}

// 400 instances in a 20x20 image: each pixel's rays go to Embree one by one; in a
// 1000x1000 image, one instance per 2,500 pixels, as packets.
TEST(Render, PacketsAreLeftOutWhereInstancesAreDenserThanPixels) {
  Scene scene;
  scene.set_mesh("tile", quad(-0.05f, 0.05f, -0.05f, 0.05f, 0));
  scene.set_material("tile", Material{});
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      const Vec3 at(-0.95f + 0.1f * static_cast<float>(i), -0.95f + 0.1f * static_cast<float>(j),
                    0);
      const std::string name = "tile" + std::to_string(i) + "_" + std::to_string(j);
      scene.set_instance(name, Instance{"tile", glm::translate(glm::mat4(1.0f), at), {"tile"}});
    }
  }
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 2.0f), 0.5f);
  Settings settings;
  settings.width = 20;
  settings.height = 20;
  const RenderStats coarse = RenderJob(scene, settings, scene.camera).stats();
  EXPECT_EQ(coarse.visible_instances, 400u);
  EXPECT_FALSE(coarse.camera_packets);
  settings.width = 1000;
  settings.height = 1000;
  EXPECT_TRUE(RenderJob(scene, settings, scene.camera).stats().camera_packets);
}

// The bare-Embree baseline traces exactly the rays the render traced: all of them with a
// stride of 1, fewer with a larger stride; it needs a finished render made with recording.
TEST(Render, BareTraceRetracesTheRecordedRays) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 40;
  settings.height = 30;
  settings.aa_samples = 2;
  settings.threads = 2;
  RenderJob all(scene, settings, scene.camera, 1);
  EXPECT_THROW(all.trace_bare(), std::logic_error);  // not started
  all.start();
  while (!all.wait(1.0)) {
  }
  const BareTrace bare = all.trace_bare();
  EXPECT_EQ(bare.rays, all.stats().rays.total());
  EXPECT_EQ(bare.threads, all.stats().threads);
  EXPECT_GT(bare.seconds, 0.0);

  RenderJob some(scene, settings, scene.camera, 7);
  some.start();
  while (!some.wait(1.0)) {
  }
  EXPECT_LT(some.trace_bare().rays, bare.rays / 4);
  EXPECT_EQ(render(scene, settings), some.film().pixels());  // recording does not change the image

  RenderJob none(scene, settings, scene.camera);
  none.start();
  while (!none.wait(1.0)) {
  }
  EXPECT_THROW(none.trace_bare(), std::logic_error);  // nothing recorded
}

// A replay answers every query from the recording, not from Embree: the same pixels bit
// for bit, threads taking the tiles they took, with packets or without. Pixels a stride
// left out are not rendered.
TEST(Render, ReplayGivesTheRecordedImage) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 40;
  settings.height = 30;
  settings.aa_samples = 3;
  settings.tile_size = 8;
  for (auto [threads, packets] : {std::pair{1, true}, std::pair{2, true}, std::pair{2, false}}) {
    settings.threads = threads;
    settings.packets = packets;
    RenderJob recorded(scene, settings, scene.camera, 1, true);
    recorded.start();
    while (!recorded.wait(1.0)) {
    }
    RenderJob replay(ReplayOf{recorded});
    replay.start();
    while (!replay.wait(1.0)) {
    }
    EXPECT_EQ(replay.film().pixels(), recorded.film().pixels()) << threads << " threads";
    EXPECT_EQ(replay.stats().rays.total(), recorded.stats().rays.total());
    EXPECT_EQ(replay.stats().threads, threads);
  }
  RenderJob some(scene, settings, scene.camera, 7, true);
  some.start();
  while (!some.wait(1.0)) {
  }
  RenderJob replay(ReplayOf{some});
  replay.start();
  while (!replay.wait(1.0)) {
  }
  const std::vector<float> all = some.film().pixels();
  const std::vector<float> replayed = replay.film().pixels();
  ASSERT_EQ(replayed.size(), all.size());
  const size_t channels = all.size() / (40 * 30);
  for (size_t pixel = 0; pixel < 40 * 30; ++pixel) {
    for (size_t c = 0; c < channels; ++c) {
      const float expected = pixel % 7 == 0 ? all[pixel * channels + c] : 0.0f;
      ASSERT_EQ(replayed[pixel * channels + c], expected) << "pixel " << pixel;
    }
  }
  EXPECT_LT(replay.stats().rays.total(), some.stats().rays.total() / 4);
}

TEST(Render, ReplayNeedsAFinishedRenderRecordedWithResults) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 8;
  settings.height = 8;
  RenderJob unstarted(scene, settings, scene.camera, 1, true);
  EXPECT_THROW(RenderJob{ReplayOf{unstarted}}, std::logic_error);
  for (auto [stride, results] : {std::pair{0u, false}, std::pair{1u, false}}) {
    RenderJob job(scene, settings, scene.camera, stride, results);
    testing::run_to_end(job);
    EXPECT_THROW(RenderJob{ReplayOf{job}}, std::logic_error) << stride;
  }
}

}  // namespace
}  // namespace whitted
