#include "integrator/render.h"

#include <chrono>

namespace whitted {
namespace {

double now_seconds() {
  using Clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

}  // namespace

RenderJob::RenderJob(const Scene& scene, const Settings& settings) : settings_(settings) {
  settings_.validate();
  const double t0 = now_seconds();
  scene_ = scene.compile();
  stats_.compile_seconds = now_seconds() - t0;
  stats_.triangles = scene_->triangle_count();
  stats_.instances = scene_->instances.size();
  stats_.degenerate_instances = scene_->degenerate_instances;
  stats_.lights = scene_->lights.size();
  pixels_.assign(size_t{4} * settings_.width * settings_.height, 0.0f);
  camera_media_ = WhittedIntegrator(*scene_, settings_).media_at(Vec3(scene_->camera.to_world[3]));
  const int ts = settings_.tile_size;
  int xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  settings_.border_rect(&xmin, &ymin, &xmax, &ymax);
  for (int y = ymin; y < ymax; y += ts) {
    for (int x = xmin; x < xmax; x += ts) {
      tiles_.push_back({x, y, std::min(ts, xmax - x), std::min(ts, ymax - y)});
    }
  }
}

RenderJob::~RenderJob() {
  cancel();
  for (std::thread& worker : workers_) worker.join();
}

void RenderJob::start() {
  if (!workers_.empty()) return;
  int threads = settings_.threads > 0 ? settings_.threads
                                      : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::max(1, std::min<int>(threads, static_cast<int>(tiles_.size())));
  std::lock_guard lock(mutex_);
  stats_.threads = threads;
  running_ = threads;
  start_time_ = now_seconds();
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

void RenderJob::work() {
  const WhittedIntegrator integrator(*scene_, settings_);
  RayCounts counts;
  for (size_t i = next_tile_++; i < tiles_.size() && !cancel_; i = next_tile_++) {
    render_tile(tiles_[i], integrator, &counts);
    if (cancel_) break;  // a tile cut short is not reported as finished
    done_tiles_ += 1;
    std::lock_guard lock(mutex_);
    finished_.push_back(tiles_[i]);
  }
  std::lock_guard lock(mutex_);
  stats_.rays += counts;
  if (--running_ == 0) {
    stats_.trace_seconds = now_seconds() - start_time_;
    stats_.cancelled = cancel_;
    finished_cv_.notify_all();
  }
}

void RenderJob::render_tile(const Tile& tile, const WhittedIntegrator& integrator,
                            RayCounts* counts) {
  const int n = settings_.aa_samples;
  const float inv_n = 1.0f / static_cast<float>(n);
  const float inv_w = 1.0f / static_cast<float>(settings_.width);
  const float inv_h = 1.0f / static_cast<float>(settings_.height);
  const PathState camera_path{0, Color(1.0f), camera_media_};
  for (int y = tile.y; y < tile.y + tile.height; ++y) {
    if (cancel_) return;  // checked per row so Esc is prompt even for slow tiles
    for (int x = tile.x; x < tile.x + tile.width; ++x) {
      Color sum(0.0f);
      float coverage = 0.0f;
      // Regular n x n grid of sample positions inside the pixel, averaged (box filter).
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const float sx = (static_cast<float>(x) + (static_cast<float>(i) + 0.5f) * inv_n) * inv_w;
          const float sy = (static_cast<float>(y) + (static_cast<float>(j) + 0.5f) * inv_n) * inv_h;
          counts->camera += 1;
          float alpha = 1.0f;
          const Color c =
              integrator.trace(scene_->camera.generate_ray(sx, sy), camera_path, counts, &alpha);
          if (is_finite(c)) {
            sum += c;
            coverage += alpha;
          } else {
            counts->nonfinite_samples += 1;  // never let one bad sample poison a pixel
          }
        }
      }
      float* out = &pixels_[4 * (static_cast<size_t>(y) * settings_.width + x)];
      const Color c = sum * (inv_n * inv_n);
      out[0] = c.x;
      out[1] = c.y;
      out[2] = c.z;
      out[3] = coverage * (inv_n * inv_n);
    }
  }
}

bool RenderJob::wait(double seconds) {
  std::unique_lock lock(mutex_);
  if (workers_.empty()) return false;
  return finished_cv_.wait_for(lock, std::chrono::duration<double>(seconds),
                               [this] { return running_ == 0; });
}

void RenderJob::cancel() {
  cancel_ = true;
}

float RenderJob::progress() const {
  return tiles_.empty()
             ? 1.0f
             : static_cast<float>(done_tiles_.load()) / static_cast<float>(tiles_.size());
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

}  // namespace whitted
