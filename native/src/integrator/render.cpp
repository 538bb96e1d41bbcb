#include "integrator/render.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <latch>
#include <stdexcept>

namespace whitted {
namespace {

// A hash of (x, y, i) to [0, 1) (a PCG-style integer mix): jitter that depends only on
// the pixel and the sample, so images do not depend on tiles or threads.
float hash01(uint32_t x, uint32_t y, uint32_t i) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ i * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

double now_seconds() {
  using Clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

}  // namespace

RenderJob::RenderJob(const Scene& scene, const Settings& settings, const Camera& camera,
                     uint32_t record_stride)
    : settings_(settings), camera_(camera), record_stride_(record_stride) {
  settings_.validate();
  const double t0 = now_seconds();
  scene_ = scene.compile(&stats_.top_level_built);
  stats_.compile_seconds = now_seconds() - t0;
  stats_.triangles = scene_->triangle_count();
  stats_.instances = scene_->instances.size();
  stats_.degenerate_instances = scene_->degenerate_instances;
  stats_.lights = scene_->lights.size();
  pixels_.assign(size_t{4} * settings_.width * settings_.height, 0.0f);
  cost_.assign(static_cast<size_t>(settings_.width) * settings_.height, 0.0f);
  const WhittedIntegrator integrator(*scene_, settings_);
  camera_media_ = integrator.media_at(Vec3(camera_.to_world[3]));
  stats_.effects = integrator.effects().reasons;
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
  if (record_stride_ > 0) logs_.resize(static_cast<size_t>(threads));
  for (int i = 0; i < threads; ++i) {
    RayLog* log = record_stride_ > 0 ? &logs_[static_cast<size_t>(i)] : nullptr;
    workers_.emplace_back([this, log] { work(log); });
  }
}

void RenderJob::work(RayLog* log) {
  const WhittedIntegrator integrator(*scene_, settings_, log);
  RayCounts counts;
  for (size_t i = next_tile_++; i < tiles_.size() && !cancel_; i = next_tile_++) {
    render_tile(tiles_[i], integrator, &counts);
    if (cancel_) break;  // a tile cut short is not reported as finished
    done_tiles_ += 1;
    std::lock_guard lock(mutex_);
    finished_.push_back(tiles_[i]);
    stats_.pixels += static_cast<uint64_t>(tiles_[i].width) * tiles_[i].height;
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
  const bool adaptive = settings_.aa_mode == AntiAliasing::kAdaptive;
  for (int y = tile.y; y < tile.y + tile.height; ++y) {
    if (cancel_) return;  // checked per row so Esc is prompt even for slow tiles
    for (int x = tile.x; x < tile.x + tile.width; ++x) {
      if (integrator.log() != nullptr) integrator.log()->active = recorded(x, y);
      const uint64_t rays_before = counts->total();
      const Sample pixel = adaptive ? render_pixel_adaptive(x, y, integrator, counts)
                                    : render_pixel_grid(x, y, integrator, counts);
      const size_t index = static_cast<size_t>(y) * settings_.width + x;
      float* out = &pixels_[4 * index];
      out[0] = pixel.radiance.x;
      out[1] = pixel.radiance.y;
      out[2] = pixel.radiance.z;
      out[3] = pixel.alpha;
      cost_[index] = static_cast<float>(counts->total() - rays_before);
    }
  }
}

RenderJob::Sample RenderJob::render_pixel_grid(int x, int y, const WhittedIntegrator& integrator,
                                               RayCounts* counts) const {
  // The camera rays of one pixel are coherent: Embree finds their first hits together,
  // up to a packet at a time, then each is shaded on its own. A packet never spans two
  // pixels, so a pixel's value depends on nothing but the pixel (not on tiles or
  // threads): where two coplanar faces tie, the winner can depend on the packet.
  constexpr int kPacket = SceneAccel::kPacketSize;
  const int n = settings_.aa_samples;
  const int samples = n * n;
  std::array<Ray, kPacket> rays;
  std::array<Hit, kPacket> hits;
  Sample sum{Color(0.0f), 0.0f};
  for (int first = 0; first < samples; first += kPacket) {
    const int count = std::min(kPacket, samples - first);
    for (int k = 0; k < count; ++k) {
      float px = 0.0f;
      float py = 0.0f;
      grid_sample(x, y, (first + k) % n, (first + k) / n, &px, &py);
      rays[static_cast<size_t>(k)] = camera_ray(px, py);
    }
    const bool packet = settings_.packets && count > 1;
    if (packet) integrator.intersect_packet(rays.data(), count, hits.data());
    for (int k = 0; k < count; ++k) {
      const Hit* hit = packet ? &hits[static_cast<size_t>(k)] : nullptr;
      const Sample s = shade_camera_ray(rays[static_cast<size_t>(k)], hit, integrator, counts);
      sum.radiance += s.radiance;
      sum.alpha += s.alpha;
    }
  }
  // The average of the samples (box filter).
  const float w = 1.0f / static_cast<float>(samples);
  return {sum.radiance * w, sum.alpha * w};
}

bool RenderJob::recorded(int x, int y) const {
  const uint64_t index =
      static_cast<uint64_t>(y) * static_cast<uint64_t>(settings_.width) + static_cast<uint64_t>(x);
  return index % record_stride_ == 0;
}

void RenderJob::grid_sample(int x, int y, int i, int j, float* px, float* py) const {
  // An n x n grid over the pixel; jittered inside each cell.
  const int n = settings_.aa_samples;
  const float cell = 1.0f / static_cast<float>(n);
  float du = 0.5f;
  float dv = 0.5f;
  if (settings_.aa_mode == AntiAliasing::kJittered) {
    const auto k = static_cast<uint32_t>(j * n + i);
    du = hash01(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 2 * k);
    dv = hash01(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 2 * k + 1);
  }
  *px = static_cast<float>(x) + (static_cast<float>(i) + du) * cell;
  *py = static_cast<float>(y) + (static_cast<float>(j) + dv) * cell;
}

Ray RenderJob::camera_ray(float px, float py) const {
  return camera_.generate_ray(px / static_cast<float>(settings_.width),
                              py / static_cast<float>(settings_.height));
}

RenderJob::Sample RenderJob::render_pixel_adaptive(int x, int y,
                                                   const WhittedIntegrator& integrator,
                                                   RayCounts* counts) const {
  const auto fx = static_cast<float>(x);
  const auto fy = static_cast<float>(y);
  const Sample corners[4] = {camera_sample(fx, fy, integrator, counts),
                             camera_sample(fx + 1.0f, fy, integrator, counts),
                             camera_sample(fx, fy + 1.0f, integrator, counts),
                             camera_sample(fx + 1.0f, fy + 1.0f, integrator, counts)};
  return subdivide(fx, fy, 1.0f, corners, 0, integrator, counts);
}

RenderJob::Sample RenderJob::camera_sample(float px, float py, const WhittedIntegrator& integrator,
                                           RayCounts* counts) const {
  return shade_camera_ray(camera_ray(px, py), nullptr, integrator, counts);
}

RenderJob::Sample RenderJob::shade_camera_ray(const Ray& ray, const Hit* first,
                                              const WhittedIntegrator& integrator,
                                              RayCounts* counts) const {
  counts->camera += 1;
  const PathState path{0, Color(1.0f), camera_media_};
  float alpha = 1.0f;
  const Color c = first != nullptr ? integrator.trace_from(ray, *first, path, counts, &alpha)
                                   : integrator.trace(ray, path, counts, &alpha);
  if (!is_finite(c)) {
    counts->nonfinite_samples += 1;  // never let one bad sample poison a pixel
    return {Color(0.0f), 0.0f};
  }
  return {c, alpha};
}

RenderJob::Sample RenderJob::subdivide(float x0, float y0, float size, const Sample corners[4],
                                       int depth, const WhittedIntegrator& integrator,
                                       RayCounts* counts) const {
  // How much the corners differ as shown: the spread of each channel clamped to [0, 1],
  // summed over RGB.
  Color lo(kInfinity);
  Color hi(-kInfinity);
  for (int i = 0; i < 4; ++i) {
    const Color c = glm::min(corners[i].radiance, Color(1.0f));
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  const Color spread = hi - lo;
  const bool split =
      depth < settings_.aa_depth && spread.x + spread.y + spread.z > settings_.aa_threshold;
  if (!split) {
    Sample mean{Color(0.0f), 0.0f};
    for (int i = 0; i < 4; ++i) {
      mean.radiance += 0.25f * corners[i].radiance;
      mean.alpha += 0.25f * corners[i].alpha;
    }
    return mean;
  }
  const float h = 0.5f * size;
  const Sample bottom = camera_sample(x0 + h, y0, integrator, counts);
  const Sample left = camera_sample(x0, y0 + h, integrator, counts);
  const Sample centre = camera_sample(x0 + h, y0 + h, integrator, counts);
  const Sample right = camera_sample(x0 + size, y0 + h, integrator, counts);
  const Sample top = camera_sample(x0 + h, y0 + size, integrator, counts);
  const Sample quadrants[4][4] = {{corners[0], bottom, left, centre},
                                  {bottom, corners[1], centre, right},
                                  {left, centre, corners[2], top},
                                  {centre, right, top, corners[3]}};
  const float offsets[4][2] = {{0.0f, 0.0f}, {h, 0.0f}, {0.0f, h}, {h, h}};
  Sample mean{Color(0.0f), 0.0f};
  for (int q = 0; q < 4; ++q) {
    const Sample s = subdivide(x0 + offsets[q][0], y0 + offsets[q][1], h, quadrants[q], depth + 1,
                               integrator, counts);
    mean.radiance += 0.25f * s.radiance;
    mean.alpha += 0.25f * s.alpha;
  }
  return mean;
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

BareTrace RenderJob::trace_bare() const {
  {
    std::lock_guard lock(mutex_);
    if (workers_.empty() || running_ > 0) {
      throw std::logic_error("trace_bare needs a finished render");
    }
  }
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
      traced[i] = scene_->accel->trace_bare(&batches[i]);
    });
  }
  ready.arrive_and_wait();
  const double t0 = now_seconds();
  for (std::thread& t : threads) t.join();
  out.seconds = now_seconds() - t0;
  for (uint64_t n : traced) out.rays += n;
  return out;
}

}  // namespace whitted
