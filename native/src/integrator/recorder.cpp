#include "integrator/recorder.h"

#include <chrono>
#include <latch>
#include <stdexcept>
#include <thread>

namespace whitted {

void RayRecorder::prepare(int workers) {
  if (stride_ > 0) logs_.resize(static_cast<size_t>(workers));
}

RayLog* RayRecorder::log(int worker) {
  return stride_ > 0 ? &logs_[static_cast<size_t>(worker)] : nullptr;
}

void RayRecorder::select(RayLog* log, int x, int y, int width) const {
  if (log == nullptr) return;
  const uint64_t index =
      static_cast<uint64_t>(y) * static_cast<uint64_t>(width) + static_cast<uint64_t>(x);
  log->active = index % stride_ == 0;
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
