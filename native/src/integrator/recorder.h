// The benchmark's ray recorder: a render's queries kept so a bare Embree loop can trace
// the same rays again (the baseline scripts/perf_raw_embree.py compares against).
#pragma once

#include <cstdint>
#include <vector>

#include "accel/embree.h"

namespace whitted {

// The queries one worker made while `active` (the integrator appends to it).
struct RayLog {
  std::vector<RayQuery> queries;
  bool active = false;
};

// The recorded rays traced again with no shading.
struct BareTrace {
  uint64_t rays = 0;
  double seconds = 0.0;
  int threads = 0;
};

class RayRecorder {
 public:
  // Records the queries of every `stride`-th pixel (row by row); 0 records nothing.
  explicit RayRecorder(uint32_t stride) : stride_(stride) {}

  // One log per worker, made before the workers start; nullptr when not recording.
  void prepare(int workers);
  RayLog* log(int worker);
  // Switches `log` (if any) on for the queries of pixel (x, y) of an image `width` wide.
  void select(RayLog* log, int x, int y, int width) const;

  // Each worker's recording traced again on its own thread by a bare loop of
  // single-ray Embree queries, all threads timed from a common start to the last one's
  // end. Throws std::logic_error when nothing was recorded.
  BareTrace trace_bare(const SceneAccel& accel) const;

 private:
  uint32_t stride_;
  std::vector<RayLog> logs_;
};

}  // namespace whitted
