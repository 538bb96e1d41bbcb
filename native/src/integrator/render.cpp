#include "integrator/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace whitted {
namespace {

// Lower the calling thread's priority. On Linux each thread has its own nice value
// (setpriority on a thread id affects that thread alone). A failure only leaves the
// priority as it was, so it is not an error.
void lower_thread_priority(int nice) {
  if (nice <= 0) return;
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  setpriority(PRIO_PROCESS, tid, nice);
}

// The memory a worker's wave queues hold (their capacity, not their size).
size_t wave_bytes(const Wave& wave) {
  return (wave.rays.capacity() + wave.next.capacity()) * sizeof(WaveRay) +
         wave.feelers.capacity() * sizeof(WaveFeeler) +
         wave.feeler_passes.capacity() * sizeof(FeelerPasses) +
         wave.samples.capacity() * sizeof(WaveSample) +
         (wave.records.capacity() + wave.point_records.capacity()) * sizeof(SampleRecord) +
         (wave.order.capacity() + wave.groups.capacity()) * sizeof(uint32_t) +
         wave.blocked.capacity() + wave.points.capacity() * sizeof(SubdivisionPoint) +
         wave.squares.capacity() * sizeof(SubdivisionSquare);
}

double now_seconds() {
  using Clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

// Settings checked before anything is sized by them.
const Settings& validated(const Settings& settings) {
  settings.validate();
  return settings;
}

Tile border_area(const Settings& settings) {
  int xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  settings.border_rect(&xmin, &ymin, &xmax, &ymax);
  return {xmin, ymin, xmax - xmin, ymax - ymin};
}

// What an exception says, for the statistics.
std::string describe(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {  // not a std::exception: nothing to read, only to name
    return "an exception that is not a std::exception";
  }
}

}  // namespace

RenderJob::RenderJob(const Settings& settings, const Camera& camera, RayRecorder recorder)
    : settings_(validated(settings)),
      camera_(camera),
      passes_(make_schedule(settings_)),
      tiles_(make_tiles(settings_)),
      area_(border_area(settings_)),
      film_(settings_.width, settings_.height, settings_.progressive || settings_.adaptive_sampling,
            settings_.passes, settings_.contribution_depth, settings_.adaptive_sampling),
      cryptomatte_(settings_),
      recorder_(std::move(recorder)),
      passes_end_(passes_.size()) {}

RenderJob::RenderJob(const Scene& scene, const Settings& settings, const Camera& camera,
                     uint32_t record_stride, bool record_results)
    : RenderJob(settings, camera, RayRecorder(record_stride, record_results)) {
  const double t0 = now_seconds();
  scene_ = scene.compile(&stats_.top_level_built, &stats_.world_light_seconds);
  stats_.compile_seconds = now_seconds() - t0;
  describe_scene();
}

void RenderJob::describe_scene() {
  stats_.triangles = scene_->triangle_count();
  for (const CompiledScene::Instance& instance : scene_->instances) {
    stats_.curve_segments += instance.mesh->mesh.curves.segment_count();
    stats_.points += instance.mesh->mesh.points.count();
  }
  stats_.instances = scene_->instances.size();
  stats_.degenerate_instances = scene_->degenerate_instances;
  stats_.lights = scene_->lights.size();
  const WhittedIntegrator integrator(*scene_, settings_, camera_);
  camera_media_ = integrator.media_at(Vec3(camera_.to_world[3]));
  stats_.effects = integrator.effects().decisions;
  stats_.waves = integrator.waves();
  const PacketChoice packets = choose_packets(*scene_, camera_, settings_);
  camera_packets_ = packets.packets;
  stats_.camera_packets = packets.packets;
  stats_.visible_instances = packets.visible_instances;
  stats_.instances_per_pixel = packets.instances_per_pixel;
}

RenderJob::RenderJob(ReplayOf replay)
    : RenderJob(replay.recorded.settings_, replay.recorded.camera_,
                replay_recorder(replay.recorded)) {
  scene_ = replay.recorded.scene_;
  describe_scene();
}

RayRecorder RenderJob::replay_recorder(const RenderJob& recorded) {
  recorded.check_finished("a replay");
  return RayRecorder::replaying(recorded.recorder_);
}

RenderJob::~RenderJob() {
  cancel();
  for (std::thread& worker : workers_) worker.join();
}

void RenderJob::start() {
  if (!workers_.empty()) return;
  int threads = settings_.threads > 0 ? settings_.threads
                                      : static_cast<int>(std::thread::hardware_concurrency());
  threads = recorder_.workers(std::max(1, std::min<int>(threads, static_cast<int>(tiles_.size()))));
  std::lock_guard lock(mutex_);
  stats_.threads = threads;
  if (settings_.adaptive_sampling) {
    stats_.active_pixels = static_cast<size_t>(area_.width) * static_cast<size_t>(area_.height);
  }
  running_ = threads;
  start_time_ = now_seconds();
  recorder_.prepare(threads);
  for (int i = 0; i < threads; ++i) {
    try {
      workers_.emplace_back([this, i] { work(i); });
    } catch (...) {
      // No thread for the rest (std::system_error): the started ones stop, and wait()
      // does not wait for workers that never ran.
      running_ -= threads - i;
      cancel_ = true;
      changed_.notify_all();
      throw;
    }
  }
}

void RenderJob::work(int worker) {
  lower_thread_priority(settings_.worker_nice);
  RayLog* log = recorder_.log(worker);
  RayCounts counts;
  Wave wave;  // the worker's queues, reused tile after tile
  // The one catch-all of the engine: an exception must not leave a worker thread, where
  // it would call std::terminate and take Blender down. It is kept for wait() instead.
  try {
    const WhittedIntegrator integrator(*scene_, settings_, camera_, log);
    const CameraSampler sampler(integrator, camera_, camera_media_, camera_packets_);
    const size_t items = passes_.size() * tiles_.size();
    const auto take = [&] { return log != nullptr ? log->take_item(&next_item_) : next_item_++; };
    for (size_t item = take(); item < items; item = take()) {
      const size_t pass = item / tiles_.size();
      if (!wait_for_pass(pass)) break;
      const size_t tile = item % tiles_.size();
      if (static_cast<int64_t>(tile) == settings_.fault_tile) throw std::bad_alloc();
      trace(passes_[pass], tiles_[tile], sampler, log, &wave, &counts);
      if (cancel_) break;  // a tile cut short is not reported as finished
      finish_item(item, &counts);
    }
  } catch (...) {
    fail(std::current_exception());
  }
  std::lock_guard lock(mutex_);
  stats_.rays += counts;  // what a tile cut short traced
  stats_.wave_bytes = std::max(stats_.wave_bytes, wave_bytes(wave));
  if (--running_ == 0) {
    stats_.trace_seconds = now_seconds() - start_time_;
    if (settings_.adaptive_sampling) summarize_film();
    stats_.cancelled = cancel_;
  }
  changed_.notify_all();
}

bool RenderJob::wait_for_pass(size_t pass) {
  // A pixel's passes run in order: a tile of this pass waits until every tile of the
  // passes before it is done. No worker waits holding an item of those passes (items
  // are handed out in order), so this cannot deadlock; cancel() wakes it.
  const size_t needed = pass * tiles_.size();
  if (done_items_ < needed) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return cancel_ || done_items_ >= needed || pass >= passes_end_; });
  }
  return !cancel_ && pass < passes_end_;
}

bool RenderJob::out_of_time(const Pass& next) const {
  // The first round always runs, so every pixel of the border has samples of its own.
  return settings_.adaptive_sampling && settings_.time_limit > 0.0 &&
         next.kind == Pass::Kind::kRound && next.sample > 0 &&
         now_seconds() - start_time_ >= settings_.time_limit;
}

void RenderJob::trace(const Pass& pass, const Tile& tile, const CameraSampler& sampler, RayLog* log,
                      Wave* wave, RayCounts* counts) {
  if (pass.kind != Pass::Kind::kPreview && sampler.waves()) {
    trace_rows(pass, tile, sampler, log, wave, counts);
    return;
  }
  const int width = settings_.width;
  // What each pixel (or sample) adds to the passes, when there are any.
  SampleRecord record;
  SampleRecord* const passes = (settings_.passes & kRecordedPasses) != 0 ? &record : nullptr;
  if (pass.kind == Pass::Kind::kPreview) {
    for_each_block(tile, pass.pixel_size, area_, [&](const Tile& block, const Tile& inside) {
      if (cancel_) return false;
      if (!recorder_.select(log, block.x, block.y, width)) return true;
      const uint64_t before = counts->total();
      if (passes != nullptr) record = SampleRecord{};
      const Sample s = sampler.point(
          static_cast<float>(block.x) + 0.5f * static_cast<float>(block.width),
          static_cast<float>(block.y) + 0.5f * static_cast<float>(block.height), counts, passes);
      const auto cost = static_cast<float>(counts->total() - before);
      for (int y = inside.y; y < inside.y + inside.height; ++y) {
        for (int x = inside.x; x < inside.x + inside.width; ++x) {
          film_.set(x, y, s, cost, 0, passes);  // no samples of the pixel's own
        }
      }
      return true;
    });
    return;
  }
  // Whole pixels: the camera rays of each block of pixels (fixed in the image, so it may
  // reach past the tile) go to Embree together when its first pixel in this tile comes up.
  const int block_width = pass.kind == Pass::Kind::kPixels ? sampler.block_width() : 0;
  FirstHits block;
  // A round's samples of one pixel: their rays, values, costs and records.
  RoundHits round;
  std::vector<Sample> values;
  std::vector<float> costs;
  std::vector<SampleRecord> records;
  for (int y = tile.y; y < tile.y + tile.height; ++y) {
    if (cancel_) return;  // checked per row so Esc is prompt even for slow tiles
    for (int x = tile.x; x < tile.x + tile.width; ++x) {
      if (block_width > 0 && !block.holds(x, y)) {
        const int end = std::min(x / block_width * block_width + block_width, tile.x + tile.width);
        if (recorder_.select_range(log, x, end, y, width)) sampler.first_hits(x, y, &block);
      }
      if (pass.kind == Pass::Kind::kRound && !film_.active(x, y)) continue;
      if (!recorder_.select(log, x, y, width)) continue;
      if (pass.kind == Pass::Kind::kRound) {
        const int count = pass.samples - pass.sample;
        sampler.round_hits(x, y, pass.sample, count, &round);
        values.resize(static_cast<size_t>(count));
        costs.resize(static_cast<size_t>(count));
        records.resize(passes != nullptr ? static_cast<size_t>(count) : 0);
        for (int i = 0; i < count; ++i) {
          const auto at = static_cast<size_t>(i);
          const uint64_t before = counts->total();
          SampleRecord* sample_record =
              passes != nullptr ? &(records[at] = SampleRecord{}) : nullptr;
          values[at] = sampler.round_sample(x, y, round, i, counts, sample_record);
          costs[at] = static_cast<float>(counts->total() - before);
        }
        film_.add(x, y, values.data(), costs.data(), count,
                  passes != nullptr ? records.data() : nullptr);
        if (pass.sample == 0 && cryptomatte_.enabled()) {
          cryptomatte_.trace_pixel(*scene_, camera_, x, y);
        }
        continue;
      }
      const uint64_t before = counts->total();
      if (passes != nullptr) record = SampleRecord{};
      if (pass.kind == Pass::Kind::kPixels) {
        const uint64_t camera_before = counts->camera;
        const Sample s = sampler.pixel(x, y, counts, nullptr, passes, &block);
        film_.set(x, y, s, static_cast<float>(counts->total() - before),
                  static_cast<uint32_t>(counts->camera - camera_before), passes);
        if (cryptomatte_.enabled()) cryptomatte_.trace_pixel(*scene_, camera_, x, y);
      } else {
        const Sample s = sampler.grid_sample(x, y, pass.sample, counts, passes);
        film_.add(x, y, s, static_cast<float>(counts->total() - before), passes);
      }
    }
  }
}

void RenderJob::trace_rows(const Pass& pass, const Tile& tile, const CameraSampler& sampler,
                           RayLog* log, Wave* wave, RayCounts* counts) {
  const bool whole = pass.kind == Pass::Kind::kPixels;
  std::vector<Sample> values;
  std::vector<uint64_t> rays;
  std::vector<SampleRecord> records;  // where (data) passes are kept
  std::vector<uint32_t> samples;      // whole pixels: each one's camera samples
  std::vector<float> costs;           // rays, as the film takes them
  const int end = tile.x + tile.width;
  for (int y = tile.y; y < tile.y + tile.height; ++y) {
    if (cancel_) return;  // checked per row so Esc is prompt even for slow tiles
    // A wave's queries are interleaved, so a recording (or its replay) takes a row in runs
    // of pixels it records alike, a wave each; without one, the row is one wave.
    // A round skips the pixels that have stopped: its runs are also of active pixels.
    const bool round = pass.kind == Pass::Kind::kRound;
    const auto same_run = [&](int x, bool picked, bool active) {
      return recorder_.picked(log, x, y, settings_.width) == picked &&
             (!round || film_.active(x, y) == active);
    };
    for (int x0 = tile.x, x1 = x0; x0 < end; x0 = x1) {
      const bool picked = recorder_.picked(log, x0, y, settings_.width);
      const bool active = !round || film_.active(x0, y);
      for (x1 = x0 + 1; x1 < end && same_run(x1, picked, active);) ++x1;
      if (!active || !recorder_.select_range(log, x0, x1, y, settings_.width)) continue;
      // A round's samples as one wave, each pixel's added in its order.
      const int count = round ? pass.samples - pass.sample : 1;
      sampler.row(x0, x1, y, whole ? -1 : pass.sample, count, wave, counts, &values, &rays,
                  &records, &samples);
      costs.resize(rays.size());
      std::transform(rays.begin(), rays.end(), costs.begin(),
                     [](uint64_t n) { return static_cast<float>(n); });
      for (int x = x0; x < x1; ++x) {
        const auto i = static_cast<size_t>((x - x0) * (whole ? 1 : count));
        const SampleRecord* record = records.empty() ? nullptr : &records[i];
        if (whole) {
          film_.set(x, y, values[i], costs[i], samples[i], record);
        } else {
          film_.add(x, y, &values[i], &costs[i], count, record);
        }
      }
      if (cryptomatte_.enabled() && (whole || (round && pass.sample == 0))) {
        for (int x = x0; x < x1; ++x) cryptomatte_.trace_pixel(*scene_, camera_, x, y);
      }
    }
  }
}

void RenderJob::finish_item(size_t item, RayCounts* counts) {
  const Tile& tile = tiles_[item % tiles_.size()];
  std::lock_guard lock(mutex_);
  // Merged after every tile, so the statistics show the rays traced so far.
  stats_.rays += *counts;
  *counts = RayCounts{};
  if (item / tiles_.size() + 1 == passes_.size()) {
    finished_.push_back(tile);
    stats_.pixels += static_cast<uint64_t>(tile.width) * tile.height;
  }
  // Every item is counted here, under the lock, so the pass this item completes (if any)
  // is known before done_items_ lets the next pass start.
  const size_t done = done_items_ + 1;
  if (done % tiles_.size() == 0) {
    const size_t complete = done / tiles_.size();
    const Pass& pass = passes_[complete - 1];
    if (pass.kind == Pass::Kind::kRound) stats_.rounds += 1;
    if (pass.converge) {
      // No worker writes now: the next pass's items wait for done_items_.
      stats_.active_pixels =
          film_.converge(settings_.noise_threshold, area_.x, area_.y, area_.width, area_.height);
    }
    if (complete < passes_.size() && out_of_time(passes_[complete])) {
      // Decided once, between rounds, so every pixel of a round is traced or none is.
      // This pass is now the last: its tiles are finished.
      passes_end_ = complete;
      stats_.time_limited = true;
      for (const Tile& t : tiles_) {
        finished_.push_back(t);
        stats_.pixels += static_cast<uint64_t>(t.width) * t.height;
      }
    }
  }
  done_items_ = done;
  if (done % tiles_.size() == 0) changed_.notify_all();  // a pass is complete
}

void RenderJob::summarize_film() {
  uint64_t total = 0;
  stats_.samples_min = UINT32_MAX;
  stats_.samples_max = 0;
  RenderStats::Noise noise;
  uint64_t measured = 0;
  for (int y = area_.y; y < area_.y + area_.height; ++y) {
    for (int x = area_.x; x < area_.x + area_.width; ++x) {
      const uint32_t n = film_.samples(x, y);
      total += n;
      stats_.samples_min = std::min(stats_.samples_min, n);
      stats_.samples_max = std::max(stats_.samples_max, n);
      const float error = film_.noise(x, y);
      if (std::isnan(error)) continue;
      noise.mean += error;
      noise.max = std::max(noise.max, error);
      ++measured;
    }
  }
  stats_.samples_mean = static_cast<double>(total) /
                        (static_cast<double>(area_.width) * static_cast<double>(area_.height));
  if (measured > 0) {
    noise.mean /= static_cast<double>(measured);
    stats_.noise = noise;
  }
}

void RenderJob::fail(std::exception_ptr error) {
  std::lock_guard lock(mutex_);
  if (!error_) {
    error_ = error;
    stats_.error = describe(error);
  }
  cancel_ = true;
  changed_.notify_all();
}

bool RenderJob::wait(double seconds) {
  std::unique_lock lock(mutex_);
  if (workers_.empty()) return false;
  if (!changed_.wait_for(lock, std::chrono::duration<double>(seconds),
                         [this] { return running_ == 0; })) {
    return false;
  }
  if (error_) std::rethrow_exception(error_);
  return true;
}

void RenderJob::cancel() {
  cancel_ = true;
  // Notified under the lock, so a worker between its wait's test and its sleep cannot
  // miss it.
  std::lock_guard lock(mutex_);
  changed_.notify_all();
}

float RenderJob::progress() const {
  return static_cast<float>(done_items_.load()) /
         static_cast<float>(passes_end_.load() * tiles_.size());
}

int RenderJob::frame() const {
  return static_cast<int>(done_items_.load() / tiles_.size());
}

PassInfo RenderJob::pass_info() const {
  PassInfo info;
  info.pass = frame();
  info.passes = static_cast<int>(passes_end_.load());
  if (info.pass > 0) {
    const Pass& last = passes_[static_cast<size_t>(info.pass) - 1];
    info.pixel_size = last.pixel_size;
    info.samples = last.samples;
  }
  return info;
}

std::vector<Tile> RenderJob::take_finished_tiles() {
  std::lock_guard lock(mutex_);
  std::vector<Tile> out;
  out.swap(finished_);
  return out;
}

RenderStats RenderJob::stats() const {
  std::lock_guard lock(mutex_);
  RenderStats out = stats_;
  out.samples = out.rays.camera;
  return out;
}

RayTree RenderJob::inspect(int x, int y, int sample) const {
  return inspect_pixel(*scene_, settings_, camera_, camera_media_, camera_packets_, x, y, sample);
}

void RenderJob::check_finished(const char* what) const {
  std::lock_guard lock(mutex_);
  if (workers_.empty() || running_ > 0) {
    throw std::logic_error(std::string(what) + " needs a finished render");
  }
}

BareTrace RenderJob::trace_bare() const {
  check_finished("trace_bare");
  return recorder_.trace_bare(*scene_->accel);
}

}  // namespace whitted
