// A render in progress: the passes of its schedule traced tile by tile on worker threads,
// polled, displayed and cancelled from Python.
#pragma once

#include <atomic>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "integrator/cryptomatte.h"
#include "integrator/film.h"
#include "integrator/recorder.h"
#include "integrator/sampler.h"
#include "integrator/schedule.h"
#include "integrator/settings.h"
#include "integrator/whitted.h"
#include "scene/scene.h"

namespace whitted {

struct RenderStats {
  RayCounts rays;                // so far: merged after every tile
  double compile_seconds = 0.0;  // name resolution and top-level BVH build
  // Of compile_seconds, building the world light's map (0 when the compile kept the last).
  double world_light_seconds = 0.0;
  bool top_level_built = false;  // whether the compile built a top-level BVH (else reused)
  double trace_seconds = 0.0;
  int threads = 0;
  uint64_t samples = 0;  // camera samples taken
  uint64_t pixels = 0;   // pixels finished (their last pass done)
  size_t triangles = 0;
  size_t curve_segments = 0;  // of hair and curves
  size_t points = 0;          // of point clouds
  size_t instances = 0;
  size_t degenerate_instances = 0;  // left out: (near) zero scale
  size_t lights = 0;
  // Whether a pixel's camera rays went to Embree as one packet, and the estimate that
  // chose it (choose_packets, sampler.h).
  bool camera_packets = false;
  size_t visible_instances = 0;
  float instances_per_pixel = 0.0f;
  bool cancelled = false;               // stopped before the end: cancel(), or a worker failed
  std::string error;                    // what the first failing worker threw; empty when none did
  std::vector<EffectDecision> effects;  // what the scene analysis simulated and skipped, why
  // Tracing in waves (Settings::waves): whether any pass was, and the most memory one
  // worker's queues held (their capacity, wave.h).
  bool waves = false;
  size_t wave_bytes = 0;
  // Noise-driven sampling (Settings::adaptive_sampling): the pixels still active after the
  // last check (all of the border's before the first), and, once the render has stopped,
  // the samples each pixel of the border took.
  size_t active_pixels = 0;
  // The rounds traced, and whether Settings::time_limit stopped the render before the
  // schedule's last round.
  int rounds = 0;
  bool time_limited = false;
  uint32_t samples_min = 0;
  uint32_t samples_max = 0;
  double samples_mean = 0.0;
  // Once the render has stopped, the final noise estimate (Film::noise: Cycles' metric,
  // which a pixel stops below kNoiseThresholdScale x noise_threshold) over the border's
  // pixels whose estimate is a number (2 samples or more, none NaN); absent without
  // noise-driven sampling, and when no pixel has one.
  struct Noise {
    double mean = 0.0;
    float max = 0.0f;
  };
  std::optional<Noise> noise;
};

// Where a render is in its schedule.
struct PassInfo {
  int pass = 0;        // passes completed
  int passes = 0;      // passes in the schedule
  int pixel_size = 0;  // of the last completed pass (0 before the first)
  int samples = 0;     // camera samples of its own each pixel has after it (Pass::samples)
};

class RenderJob;

// What a replay replays: a finished render recorded with its results.
struct ReplayOf {
  const RenderJob& recorded;
};

class RenderJob {
 public:
  // Renders `scene` as `camera` sees it (the camera is not part of the compiled scene, so
  // a new view reuses the snapshot). With `record_stride` n > 0 the render records the
  // queries of every n-th pixel for trace_bare (a benchmark baseline; recording costs time
  // and memory), and with `record_results` also what they found, for a replay.
  RenderJob(const Scene& scene, const Settings& settings, const Camera& camera,
            uint32_t record_stride = 0, bool record_results = false);
  // A replay (a benchmark of the shading alone): the recorded render's pixels rendered
  // again with its snapshot, settings and camera, each worker taking the tiles the same
  // worker took and every query answered from that worker's recording, not by Embree.
  // Its pixels are the recording's, bit for bit; those not recorded stay empty, and
  // Cryptomatte's own rays are not replayed. The recorded job must outlive it. Throws
  // std::logic_error unless `replay.recorded` finished recorded with its results.
  explicit RenderJob(ReplayOf replay);
  ~RenderJob();  // cancels and joins
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  void start();
  // Waits up to `seconds`; true once every worker has stopped (finished, cancelled or
  // failed). Once they all have, rethrows what the first failing worker threw.
  bool wait(double seconds);
  // Workers stop within a row of pixels (or one preview block) and leave what they were
  // tracing unreported.
  void cancel();
  float progress() const;
  // How many passes have completed: what the film shows moves on each time it grows.
  int frame() const;
  PassInfo pass_info() const;
  // The tiles whose last pass finished since the last call: their pixels are final.
  std::vector<Tile> take_finished_tiles();
  const Settings& settings() const { return settings_; }
  const Film& film() const { return film_; }
  const CryptomatteFilm& cryptomatte() const { return cryptomatte_; }
  RenderStats stats() const;
  // The ray tree of pixel (x, y), traced again apart from the render (inspect_pixel), with
  // its scene, settings and camera; the film is not touched. Callable before, during or
  // after the render.
  RayTree inspect(int x, int y, int sample = -1) const;
  const CompiledScene& scene() const { return *scene_; }
  // After a finished render with recording: the recorded rays traced again by a bare
  // loop of single-ray Embree queries (RayRecorder::trace_bare).
  BareTrace trace_bare() const;

 private:
  RenderJob(const Settings& settings, const Camera& camera, RayRecorder recorder);
  static RayRecorder replay_recorder(const RenderJob& recorded);
  // The snapshot's statistics, its effects and the media around the camera.
  void describe_scene();
  // Passes and tiles are handed out as one sequence of items, pass by pass: item i is
  // tile i % tiles of pass i / tiles (a replay's worker takes those its recording took).
  void work(int worker);
  // Throws std::logic_error unless every worker has stopped.
  void check_finished(const char* what) const;
  // Blocks until every pass before `pass` is complete; false if the job was cancelled
  // or the time limit ended it before `pass`.
  bool wait_for_pass(size_t pass);
  // Whether Settings::time_limit stops the render before `next`, were it to start now.
  bool out_of_time(const Pass& next) const;
  void trace(const Pass& pass, const Tile& tile, const CameraSampler& sampler, RayLog* log,
             Wave* wave, RayCounts* counts);
  // A pass over a tile's whole pixels or grid samples traced in waves, a row at a time.
  void trace_rows(const Pass& pass, const Tile& tile, const CameraSampler& sampler, RayLog* log,
                  Wave* wave, RayCounts* counts);
  // Counts the item done; the last item of a pass followed by the film's noise check runs
  // that check first (under the lock, before the next pass may start).
  void finish_item(size_t item, RayCounts* counts);
  // RenderStats' samples per pixel and final noise, from the film (every worker stopped;
  // under the lock).
  void summarize_film();
  // Keeps the first error for wait() and stops the other workers.
  void fail(std::exception_ptr error);

  Settings settings_;
  Camera camera_;
  std::shared_ptr<const CompiledScene> scene_;
  MediumStack camera_media_;    // the glass the camera is inside, if any
  bool camera_packets_ = true;  // choose_packets' answer for this render
  std::vector<Pass> passes_;
  std::vector<Tile> tiles_;
  Tile area_;  // the border rectangle
  Film film_;
  CryptomatteFilm cryptomatte_;
  RayRecorder recorder_;
  std::vector<std::thread> workers_;
  std::atomic<size_t> next_item_{0};
  // Items done: passes complete in order, so the first done / tiles passes are complete.
  std::atomic<size_t> done_items_{0};
  // The passes traced: the schedule's, or fewer once the time limit has cut it.
  std::atomic<size_t> passes_end_;
  std::atomic<bool> cancel_{false};
  mutable std::mutex mutex_;  // guards everything below
  // Notified when a pass completes, the job is cancelled or a worker stops.
  std::condition_variable changed_;
  int running_ = 0;
  std::vector<Tile> finished_;
  RenderStats stats_;
  std::exception_ptr error_;
  double start_time_ = 0.0;
};

}  // namespace whitted
