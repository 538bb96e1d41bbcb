// A render in progress: tiles traced on worker threads, polled and cancelled from Python.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "integrator/settings.h"
#include "integrator/whitted.h"
#include "scene/scene.h"

namespace whitted {

struct Tile {
  int x, y, width, height;  // pixels; y counts from the bottom row
};

struct RenderStats {
  RayCounts rays;
  double compile_seconds = 0.0;  // name resolution and top-level BVH build
  bool top_level_built = false;  // whether the compile built a top-level BVH (else reused)
  double trace_seconds = 0.0;
  int threads = 0;
  uint64_t samples = 0;  // camera samples taken
  uint64_t pixels = 0;   // pixels rendered
  size_t triangles = 0;
  size_t instances = 0;
  size_t degenerate_instances = 0;  // left out: (near) zero scale
  size_t lights = 0;
  bool cancelled = false;
  std::vector<std::string> effects;  // what the scene analysis simulated and skipped, why
};

// The bare-Embree baseline: the recorded rays traced again with no shading.
struct BareTrace {
  uint64_t rays = 0;
  double seconds = 0.0;
  int threads = 0;
};

class RenderJob {
 public:
  // Renders `scene` as `camera` sees it (the camera is not part of the compiled scene, so
  // a new view reuses the snapshot). With `record_stride` n > 0 the render records the
  // queries of every n-th pixel for trace_bare (a benchmark baseline; recording costs time
  // and memory).
  RenderJob(const Scene& scene, const Settings& settings, const Camera& camera,
            uint32_t record_stride = 0);
  ~RenderJob();  // cancels and joins
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  void start();
  // Waits up to `seconds`; true once every worker has finished (or stopped on cancel).
  bool wait(double seconds);
  void cancel();
  float progress() const;
  std::vector<Tile> take_finished_tiles();
  const Settings& settings() const { return settings_; }
  // RGBA float pixels, rows bottom to top. Read only finished tiles while running.
  const std::vector<float>& pixels() const { return pixels_; }
  // Rays traced for each pixel (all kinds): where the time goes. Rows bottom to top.
  const std::vector<float>& cost() const { return cost_; }
  RenderStats stats() const;
  // After a finished render with recording: the recorded rays traced again by a bare
  // loop of single-ray Embree queries, each thread its own recording, all threads timed
  // from a common start to the last one's end.
  BareTrace trace_bare() const;

 private:
  void work(RayLog* log);
  struct Sample {
    Color radiance;
    float alpha;
  };
  void render_tile(const Tile& tile, const WhittedIntegrator& integrator, RayCounts* counts);
  // The pixel whose bottom-left corner is (x, y), by a regular or jittered n x n grid.
  Sample render_pixel_grid(int x, int y, const WhittedIntegrator& integrator,
                           RayCounts* counts) const;
  // The camera-ray position of grid sample (i, j) of pixel (x, y), in pixels.
  void grid_sample(int x, int y, int i, int j, float* px, float* py) const;
  Ray camera_ray(float px, float py) const;
  // The radiance and coverage of a camera ray whose first hit is known, or not (nullptr).
  Sample shade_camera_ray(const Ray& ray, const Hit* first, const WhittedIntegrator& integrator,
                          RayCounts* counts) const;
  // Whether the queries of pixel (x, y) are recorded.
  bool recorded(int x, int y) const;
  // The pixel whose bottom-left corner is (x, y), by adaptive anti-aliasing.
  Sample render_pixel_adaptive(int x, int y, const WhittedIntegrator& integrator,
                               RayCounts* counts) const;
  // One camera ray through image point (px, py), in pixels from the bottom-left corner.
  Sample camera_sample(float px, float py, const WhittedIntegrator& integrator,
                       RayCounts* counts) const;
  // Whitted's adaptive subdivision of the square at (x0, y0) of side `size` whose corner
  // samples are `corners` (bottom-left, bottom-right, top-left, top-right).
  Sample subdivide(float x0, float y0, float size, const Sample corners[4], int depth,
                   const WhittedIntegrator& integrator, RayCounts* counts) const;

  Settings settings_;
  Camera camera_;
  std::shared_ptr<const CompiledScene> scene_;
  MediumStack camera_media_;  // the glass the camera is inside, if any
  std::vector<Tile> tiles_;
  std::vector<float> pixels_;
  std::vector<float> cost_;
  uint32_t record_stride_;
  std::vector<RayLog> logs_;  // one per worker when recording
  std::vector<std::thread> workers_;
  std::atomic<size_t> next_tile_{0};
  std::atomic<size_t> done_tiles_{0};
  std::atomic<bool> cancel_{false};
  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable finished_cv_;
  int running_ = 0;
  std::vector<Tile> finished_;
  RenderStats stats_;
  double start_time_ = 0.0;
};

}  // namespace whitted
