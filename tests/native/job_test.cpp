// The job driving the passes: progressive refinement ends where a pass of whole pixels
// does, passes complete in order, statistics are live, cancel is prompt in every kind of
// pass, and a failing worker stops the job instead of the process.
#include <gtest/gtest.h>

#include <chrono>
#include <new>
#include <thread>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::glass_and_mirror_scene;

void finish(RenderJob* job) {
  job->start();
  while (!job->wait(1.0)) {
  }
}

Settings small(int aa_samples, AntiAliasing mode) {
  Settings settings;
  settings.width = 37;
  settings.height = 23;
  settings.aa_samples = aa_samples;
  settings.aa_mode = mode;
  return settings;
}

// Regular and jittered: the last sample pass leaves each pixel the mean of the same
// samples, summed in the same order, as a pass of whole pixels traced one ray at a time
// (packets off: a packet may break a tie between coplanar faces differently). Exact, for
// any threads, tiles, border and start size; the ray counts match too.
TEST(Job, ProgressiveEndsBitIdenticalToWholePixels) {
  const Scene scene = glass_and_mirror_scene();
  for (AntiAliasing mode : {AntiAliasing::kRegular, AntiAliasing::kJittered}) {
    for (int n : {1, 3}) {
      Settings settings = small(n, mode);
      settings.packets = false;
      settings.border[0] = 2;
      settings.border[1] = 1;
      settings.border[2] = 35;
      settings.border[3] = 22;
      RenderJob whole(scene, settings, scene.camera);
      finish(&whole);
      settings.progressive = true;
      for (auto [threads, tile, start] :
           {std::tuple{1, 64, 8}, std::tuple{3, 5, 64}, std::tuple{2, 16, 1}}) {
        settings.threads = threads;
        settings.tile_size = tile;
        settings.start_pixel_size = start;
        RenderJob progressive(scene, settings, scene.camera);
        finish(&progressive);
        EXPECT_EQ(progressive.film().pixels(), whole.film().pixels())
            << "mode " << static_cast<int>(mode) << ", " << n << "x" << n << ", " << threads
            << " threads, tile " << tile << ", start " << start;
        EXPECT_EQ(progressive.film().cost(), whole.film().cost());
        EXPECT_EQ(progressive.stats().pixels, whole.stats().pixels);
      }
    }
  }
}

// Adaptive anti-aliasing is sampled as jittered when progressive.
TEST(Job, ProgressiveAdaptiveIsJittered) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings = small(2, AntiAliasing::kJittered);
  settings.packets = false;
  RenderJob jittered(scene, settings, scene.camera);
  finish(&jittered);
  settings.aa_mode = AntiAliasing::kAdaptive;
  settings.progressive = true;
  RenderJob progressive(scene, settings, scene.camera);
  finish(&progressive);
  EXPECT_EQ(progressive.film().pixels(), jittered.film().pixels());
}

TEST(Job, FramesCountCompletedPassesInOrder) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings = small(2, AntiAliasing::kRegular);
  settings.width = 200;
  settings.height = 150;
  settings.progressive = true;
  settings.start_pixel_size = 16;
  settings.tile_size = 8;
  settings.threads = 3;
  RenderJob job(scene, settings, scene.camera);
  EXPECT_EQ(job.frame(), 0);
  EXPECT_EQ(job.pass_info().passes, 4 + 4);
  EXPECT_EQ(job.pass_info().pixel_size, 0);
  job.start();
  int last = 0;
  float progress = 0.0f;
  while (!job.wait(0.0005)) {
    const int frame = job.frame();
    EXPECT_GE(frame, last);
    EXPECT_GE(job.progress(), progress);
    const PassInfo info = job.pass_info();
    EXPECT_GE(info.pass, frame);
    if (info.pass >= 1 && info.pass <= 4) EXPECT_EQ(info.pixel_size, 16 >> (info.pass - 1));
    if (info.pass > 4) EXPECT_EQ(info.samples, info.pass - 4);
    last = frame;
    progress = job.progress();
  }
  EXPECT_EQ(job.frame(), 8);
  const PassInfo info = job.pass_info();
  EXPECT_EQ(info.pass, 8);
  EXPECT_EQ(info.pixel_size, 1);
  EXPECT_EQ(info.samples, 4);
  EXPECT_FLOAT_EQ(job.progress(), 1.0f);
  int pixels = 0;  // tiles are reported once, when their last pass is done
  for (const Tile& t : job.take_finished_tiles()) pixels += t.width * t.height;
  EXPECT_EQ(pixels, 200 * 150);
}

TEST(Job, AWholePixelPassIsOneFrame) {
  const Scene scene = glass_and_mirror_scene();
  RenderJob job(scene, small(1, AntiAliasing::kRegular), scene.camera);
  finish(&job);
  EXPECT_EQ(job.frame(), 1);
  EXPECT_EQ(job.pass_info().passes, 1);
  EXPECT_EQ(job.pass_info().samples, 1);
}

// A render long enough to be watched: statistics show rays while it runs.
TEST(Job, RaysAreCountedWhileTheRenderRuns) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings;
  settings.width = 2048;
  settings.height = 2048;
  settings.aa_samples = 3;
  settings.threads = 2;
  settings.tile_size = 16;
  RenderJob job(scene, settings, scene.camera);
  job.start();
  uint64_t seen = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (seen == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    seen = job.stats().rays.camera;
  }
  EXPECT_FALSE(job.wait(0.0));  // still running
  EXPECT_GT(seen, 0u);
  EXPECT_GT(job.stats().rays.total(), seen / 2);
  job.cancel();
  EXPECT_TRUE(job.wait(5.0));
}

// Esc is prompt in previews and in sample passes alike.
TEST(Job, CancelStopsProgressivePassesPromptly) {
  const Scene scene = glass_and_mirror_scene();
  for (int start : {64, 1}) {
    Settings settings;
    settings.width = 4096;
    settings.height = 4096;
    settings.aa_samples = 4;
    settings.threads = 2;
    settings.progressive = true;
    settings.start_pixel_size = start;
    RenderJob job(scene, settings, scene.camera);
    job.start();
    EXPECT_FALSE(job.wait(0.05));
    const auto t0 = std::chrono::steady_clock::now();
    job.cancel();
    EXPECT_TRUE(job.wait(5.0));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 0.2) << "start " << start;
    EXPECT_TRUE(job.stats().cancelled);
    EXPECT_LT(job.frame(), 16 + 7);
  }
}

// A worker that throws stops the job: the others stop too, wait() rethrows once they
// all have, and the job can still be destroyed and another one run.
TEST(Job, AFailingWorkerStopsTheJobAndWaitRethrows) {
  const Scene scene = glass_and_mirror_scene();
  for (bool progressive : {false, true}) {
    Settings settings;
    settings.width = 1024;
    settings.height = 1024;
    settings.aa_samples = 2;
    settings.tile_size = 8;  // 16384 tiles: the others would take a while
    settings.threads = 4;
    settings.fault_tile = 300;
    settings.progressive = progressive;
    {
      RenderJob job(scene, settings, scene.camera);
      job.start();
      bool done = false;
      const auto t0 = std::chrono::steady_clock::now();
      EXPECT_THROW(
          {
            while (!done) done = job.wait(1.0);
          },
          std::bad_alloc);
      EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
      EXPECT_THROW(job.wait(0.0), std::bad_alloc);  // every later wait says so too
      const RenderStats stats = job.stats();
      EXPECT_TRUE(stats.cancelled);
      EXPECT_EQ(stats.error, std::bad_alloc().what());
      EXPECT_LT(job.progress(), 0.5f);
    }
    settings.fault_tile = -1;
    settings.width = 16;
    settings.height = 16;
    RenderJob again(scene, settings, scene.camera);
    finish(&again);
    EXPECT_EQ(again.stats().error, "");
    EXPECT_FALSE(again.stats().cancelled);
  }
}

}  // namespace
}  // namespace whitted
