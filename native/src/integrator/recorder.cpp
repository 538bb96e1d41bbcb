#include "integrator/recorder.h"

#include <algorithm>
#include <chrono>
#include <latch>
#include <limits>
#include <stdexcept>
#include <thread>

namespace whitted {
namespace {

// A replay runs the recorded render again: needing answers past the recorded ones (up to
// `end`) is a bug.
void check_answers(size_t end, size_t recorded) {
  if (end > recorded) throw std::logic_error("a replay made a query its recording did not");
}

}  // namespace

bool RayLog::intersect(const SceneAccel& accel, const Ray& ray, Hit* hit) {
  if (source != nullptr) {
    check_answers(next_hit + 1, source->hits.size());
    const Hit& recorded = source->hits[next_hit++];
    if (!(recorded.t < kInfinity)) return false;  // a miss leaves `hit` as it was
    *hit = recorded;
    return true;
  }
  queries.push_back({ray, false});
  const bool found = accel.intersect(ray, hit);
  if (results) hits.push_back(found ? *hit : Hit{});
  return found;
}

bool RayLog::occluded(const SceneAccel& accel, const Ray& ray, const Blockers* blockers) {
  if (source != nullptr) {
    check_answers(next_occlusion + 1, source->occlusion.size());
    return source->occlusion[next_occlusion++] != 0;
  }
  queries.push_back({ray, true});
  const bool blocked = accel.occluded(ray, blockers);
  if (results) occlusion.push_back(blocked ? 1 : 0);
  return blocked;
}

void RayLog::intersect_packet(const SceneAccel& accel, const Ray* rays, int count, Hit* out) {
  const auto n = static_cast<size_t>(count);
  if (source != nullptr) {
    check_answers(next_hit + n, source->hits.size());
    std::copy_n(source->hits.begin() + static_cast<std::ptrdiff_t>(next_hit), n, out);
    next_hit += n;
    return;
  }
  for (size_t i = 0; i < n; ++i) queries.push_back({rays[i], false});
  accel.intersect_packet(rays, count, out);
  if (results) hits.insert(hits.end(), out, out + n);
}

void RayLog::occluded_packet(const SceneAccel& accel, const Ray* rays, int count, bool* blocked,
                             const Blockers* blockers) {
  const auto n = static_cast<size_t>(count);
  if (source != nullptr) {
    check_answers(next_occlusion + n, source->occlusion.size());
    for (size_t i = 0; i < n; ++i) blocked[i] = source->occlusion[next_occlusion++] != 0;
    return;
  }
  for (size_t i = 0; i < n; ++i) queries.push_back({rays[i], true});
  accel.occluded_packet(rays, count, blocked, blockers);
  if (results) {
    for (size_t i = 0; i < n; ++i) occlusion.push_back(blocked[i] ? 1 : 0);
  }
}

size_t RayLog::take_item(std::atomic<size_t>* next) {
  if (source != nullptr) {
    return next_item < source->items.size() ? source->items[next_item++]
                                            : std::numeric_limits<size_t>::max();
  }
  const size_t item = (*next)++;
  items.push_back(item);
  return item;
}

RayRecorder RayRecorder::replaying(const RayRecorder& recorded) {
  if (recorded.logs_.empty() || !recorded.results_) {
    throw std::logic_error("a replay needs a finished render recorded with its results");
  }
  RayRecorder replay(recorded.stride_);
  replay.source_ = &recorded;
  return replay;
}

void RayRecorder::prepare(int workers) {
  if (stride_ == 0) return;
  logs_.resize(static_cast<size_t>(workers));
  for (size_t i = 0; i < logs_.size(); ++i) {
    logs_[i].results = results_;
    if (source_ != nullptr) logs_[i].source = &source_->logs_[i];
  }
}

RayLog* RayRecorder::log(int worker) {
  return stride_ > 0 ? &logs_[static_cast<size_t>(worker)] : nullptr;
}

int RayRecorder::workers(int wanted) const {
  return source_ != nullptr ? static_cast<int>(source_->logs_.size()) : wanted;
}

bool RayRecorder::select(RayLog* log, int x, int y, int width) const {
  return select_range(log, x, x + 1, y, width);
}

bool RayRecorder::select_range(RayLog* log, int x0, int x1, int y, int width) const {
  if (log == nullptr) return true;
  log->active = false;
  for (int x = x0; x < x1 && !log->active; ++x) log->active = picked(log, x, y, width);
  return log->active || source_ == nullptr;
}

bool RayRecorder::picked(const RayLog* log, int x, int y, int width) const {
  if (log == nullptr) return true;
  const uint64_t pixel =
      static_cast<uint64_t>(y) * static_cast<uint64_t>(width) + static_cast<uint64_t>(x);
  return pixel % stride_ == 0;
}

BareTrace RayRecorder::trace_bare(const SceneAccel& accel) const {
  if (logs_.empty()) throw std::logic_error("trace_bare needs a render made with recording");
  std::vector<BareRays> batches;
  batches.reserve(logs_.size());
  for (const RayLog& log : logs_) batches.push_back(SceneAccel::prepare_bare(log.queries));
  BareTrace out;
  out.threads = static_cast<int>(batches.size());
  std::vector<uint64_t> traced(batches.size(), 0);
  std::latch ready(static_cast<std::ptrdiff_t>(batches.size()) + 1);
  std::vector<std::thread> threads;
  for (size_t i = 0; i < batches.size(); ++i) {
    threads.emplace_back([&, i] {
      ready.arrive_and_wait();
      traced[i] = accel.trace_bare(&batches[i]);
    });
  }
  ready.arrive_and_wait();
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  for (std::thread& t : threads) t.join();
  out.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  for (uint64_t n : traced) out.rays += n;
  return out;
}

}  // namespace whitted
