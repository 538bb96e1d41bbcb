// The benchmark's ray recorder: a render's queries kept so a bare Embree loop can trace
// the same rays again (the baseline scripts/perf_raw_embree.py compares against), and
// with them their results, so the same render can be made again with every query
// answered from the recording instead of Embree (a replay: the shading alone).
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "accel/embree.h"

namespace whitted {

// One worker's recording, or its replay of one. The kernels of a render given a log
// (whitted.cpp's LoggedQueries) hand it the queries made while `active`; recording, it
// makes them and notes them (and, with `results`, what they found); replaying, it
// answers them from `source` in the same order, with no Embree call.
struct RayLog {
  std::vector<RayQuery> queries;
  std::vector<Hit> hits;           // with `results`: each closest hit (packet lanes in order)
  std::vector<uint8_t> occlusion;  // with `results`: each any-hit query's answer
  std::vector<size_t> items;       // the render's work items this worker took, in order
  const RayLog* source = nullptr;  // replaying: the recording whose answers are given
  size_t next_hit = 0;             // replaying: where the answers given so far end
  size_t next_occlusion = 0;
  size_t next_item = 0;
  bool results = false;
  bool active = false;

  bool intersect(const SceneAccel& accel, const Ray& ray, Hit* hit);
  bool occluded(const SceneAccel& accel, const Ray& ray, const Blockers* blockers);
  void intersect_packet(const SceneAccel& accel, const Ray* rays, int count, Hit* hits);
  void occluded_packet(const SceneAccel& accel, const Ray* rays, int count, bool* blocked,
                       const Blockers* blockers);
  // The worker's next work item: recording, the next of the render's sequence (noted);
  // replaying, the next this worker took in the recording (SIZE_MAX after the last).
  size_t take_item(std::atomic<size_t>* next);
};

// The recorded rays traced again with no shading.
struct BareTrace {
  uint64_t rays = 0;
  double seconds = 0.0;
  int threads = 0;
};

class RayRecorder {
 public:
  // Records the queries of every `stride`-th pixel (row by row), with their results when
  // `results`; a stride of 0 records nothing.
  explicit RayRecorder(uint32_t stride, bool results = false)
      : stride_(stride), results_(results) {}
  // A replay of `recorded` (recorded with results; it must outlive the replay): its
  // pixels, each worker answered from the log of the worker that made it.
  static RayRecorder replaying(const RayRecorder& recorded);

  // One log per worker, made before the workers start; nullptr when not recording.
  void prepare(int workers);
  RayLog* log(int worker);
  // How many workers to start for `wanted`: a replay, as many as the recording had.
  int workers(int wanted) const;
  // Switches `log` (if any) on for the queries of pixel (x, y) of an image `width` wide.
  // False for a pixel a replay skips: one the recording did not record.
  bool select(RayLog* log, int x, int y, int width) const;
  // The same for queries shared by pixels x0 to x1 - 1 of row y (a block's camera packets):
  // on when any of them is recorded; false when a replay skips them all.
  bool select_range(RayLog* log, int x0, int x1, int y, int width) const;
  // Whether the recording takes pixel (x, y)'s queries (with `log`; every pixel without).
  bool picked(const RayLog* log, int x, int y, int width) const;

  // Each worker's recording traced again on its own thread by a bare loop of
  // single-ray Embree queries, all threads timed from a common start to the last one's
  // end. Throws std::logic_error when nothing was recorded.
  BareTrace trace_bare(const SceneAccel& accel) const;

 private:
  uint32_t stride_;
  bool results_;
  const RayRecorder* source_ = nullptr;  // a replay's recording
  std::vector<RayLog> logs_;
};

}  // namespace whitted
