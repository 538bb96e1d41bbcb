// How a kernel (kernel.h) asks Embree its queries, chosen at compile time: straight to
// Embree in a render (SceneQueries), or through the benchmark's log (LoggedQueries), so
// the product's kernels have no branch per query for it.
#pragma once

#include "accel/embree.h"
#include "core/ray.h"
#include "integrator/recorder.h"
#include "integrator/whitted.h"

namespace whitted {

// The kernel's queries in a render: straight to Embree.
class SceneQueries {
 public:
  explicit SceneQueries(const WhittedIntegrator& w) : accel_(*w.scene().accel) {}
  bool intersect(const Ray& ray, Hit* hit) const { return accel_.intersect(ray, hit); }
  bool occluded(const Ray& ray, const Blockers* blockers) const {
    return accel_.occluded(ray, blockers);
  }
  void intersect_packet(const Ray* rays, int count, Hit* hits) const {
    accel_.intersect_packet(rays, count, hits);
  }
  void occluded_packet(const Ray* rays, int count, bool* blocked, const Blockers* blockers) const {
    accel_.occluded_packet(rays, count, blocked, blockers);
  }

 private:
  const SceneAccel& accel_;
};

// The benchmark's, in a render given a RayLog (recorder.h): the queries made while the
// log is active go to it, which makes and notes them or answers them from a recording;
// the others straight to Embree.
class LoggedQueries {
 public:
  explicit LoggedQueries(const WhittedIntegrator& w) : accel_(*w.scene().accel), log_(*w.log()) {}
  bool intersect(const Ray& ray, Hit* hit) const {
    return log_.active ? log_.intersect(accel_, ray, hit) : accel_.intersect(ray, hit);
  }
  bool occluded(const Ray& ray, const Blockers* blockers) const {
    return log_.active ? log_.occluded(accel_, ray, blockers) : accel_.occluded(ray, blockers);
  }
  void intersect_packet(const Ray* rays, int count, Hit* hits) const {
    if (log_.active) {
      log_.intersect_packet(accel_, rays, count, hits);
    } else {
      accel_.intersect_packet(rays, count, hits);
    }
  }
  void occluded_packet(const Ray* rays, int count, bool* blocked, const Blockers* blockers) const {
    if (log_.active) {
      log_.occluded_packet(accel_, rays, count, blocked, blockers);
    } else {
      accel_.occluded_packet(rays, count, blocked, blockers);
    }
  }

 private:
  const SceneAccel& accel_;
  RayLog& log_;
};

}  // namespace whitted
