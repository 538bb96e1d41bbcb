#include "integrator/sampler.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>

#include "core/sobol.h"

namespace whitted {
namespace {

// What the render's Seed changes a key by: nothing for seed 0 (the images of before the
// setting), else a hash of the seed and the key's salt.
uint32_t seed_mix(uint32_t seed, uint32_t salt) {
  return seed == 0 ? 0u : hash3(seed, salt, 0x5eed5eedu);
}

// The seed of grid sample k of pixel (x, y) (NodeState::seed).
uint32_t grid_seed(uint32_t seed, int x, int y, int k) {
  return pixel_key(seed, x, y, 0x9e37u + static_cast<uint32_t>(k));
}

// The seed of a camera sample (NodeState::seed) at film position (px, py), in pixels:
// its bits, hashed.
uint32_t film_seed(uint32_t seed, float px, float py) {
  uint32_t a = 0;
  uint32_t b = 0;
  std::memcpy(&a, &px, sizeof a);
  std::memcpy(&b, &py, sizeof b);
  return hash3(a, b, 0x5eedu) ^ seed_mix(seed, 0x5eedu);
}

// Where packets stop paying: at about one instance in view per 500 pixels. Callgrind's
// instructions per camera ray in Embree, packet / single, on the sphere grids of
// scripts/perf_scenes.py (docs/notes/performance_reading.md), by instances in view per
// pixel: 0.85 at 0.0006, 0.84 at 0.0016, 0.99 at 0.0019, 1.29 at 0.0055, 1.52 at 0.016,
// 1.78 at 0.054. (The share of pixels on an instance's outline sorted them worse: 100
// large spheres on 42% of the pixels still gained, at 0.84.)
constexpr double kPacketInstancesPerPixel = 1.0 / 500.0;

}  // namespace

uint32_t pixel_key(uint32_t seed, int x, int y, uint32_t salt) {
  return hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), salt) ^ seed_mix(seed, salt);
}

PacketChoice choose_packets(const CompiledScene& scene, const Camera& camera,
                            const Settings& settings) {
  const CameraFrame frame(camera);
  const float* window = camera.window;
  const bool perspective = camera.projection == Projection::kPerspective;
  PacketChoice choice;
  for (const CompiledScene::Instance& instance : scene.instances) {
    if ((instance.visibility & kCameraRay) == 0) continue;
    if (camera.projection == Projection::kPanoramic) {  // all around: every one may be
      ++choice.visible_instances;
      continue;
    }
    const Sphere& sphere = instance.mesh->bounds;
    // The sphere through to_world: its centre moved, its radius times the longest axis.
    const glm::mat3 linear(instance.placement.to_world);
    const float stretch =
        std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
    const Vec3 to_centre =
        Vec3(instance.placement.to_world * glm::vec4(sphere.centre, 1.0f)) - frame.position;
    double x = glm::dot(to_centre, frame.right);
    double y = glm::dot(to_centre, frame.up);
    double r = sphere.radius * stretch;
    const double depth = -glm::dot(to_centre, frame.back);
    if (depth + r <= 0.0) continue;  // behind the camera
    if (perspective) {
      if (depth <= r) {  // around the camera: in view
        ++choice.visible_instances;
        continue;
      }
      // Onto the image plane at distance 1 (the window's).
      x /= depth;
      y /= depth;
      r /= depth;
    }
    if (x + r < window[0] || x - r > window[1] || y + r < window[2] || y - r > window[3]) {
      continue;  // outside the image
    }
    ++choice.visible_instances;
  }
  const double pixels = static_cast<double>(settings.width) * settings.height;
  choice.instances_per_pixel = static_cast<float>(choice.visible_instances / pixels);
  choice.packets =
      settings.packets && choice.visible_instances <= kPacketInstancesPerPixel * pixels;
  return choice;
}

CameraSampler::CameraSampler(const WhittedIntegrator& integrator, const Camera& camera,
                             const MediumStack& camera_media, bool packets)
    : integrator_(integrator),
      settings_(integrator.settings()),
      camera_(camera),
      frame_(camera),
      filter_(integrator.settings()),
      packets_(packets),
      moves_(camera.motion != nullptr || integrator.scene().moves),
      distributed_(moves_ || camera.lens.blurs()),
      root_{0, Color(1.0f), camera_media} {}

Sample CameraSampler::pixel(int x, int y, RayCounts* counts, std::vector<float>* weights,
                            SampleRecord* record, const FirstHits* block) const {
  // Whitted's adaptive subdivision splits where a square's corners differ; when camera
  // samples spread over the lens or the shutter, corners differ by that spread's noise
  // as much as by edges, and a smooth blur gets its four corners alone. Such cameras
  // take the jittered grid instead, the lens and shutter stratified over it (against
  // Cycles, a motion-blurred cube at the Final preset: SSIM 0.976 adaptive, 0.988 on
  // the 3 x 3 grid; tests/blender/test_motion_blur.py).
  return adaptive() ? pixel_adaptive(x, y, counts, weights, record)
                    : pixel_grid(x, y, counts, weights, record, block);
}

Sample CameraSampler::grid_sample(int x, int y, int k, RayCounts* counts,
                                  SampleRecord* record) const {
  return shade(grid_ray(x, y, k), nullptr, counts, record, grid_root(x, y, k));
}

int CameraSampler::block_width() const {
  // One sample per pixel is left to single rays: a packet of neighbouring pixels' rays
  // picks another face than single rays where coplanar faces overlap, and where its
  // pixels meet the next block's the overlap shows both colours (the coplanar-quads hard
  // case, tests/blender/test_robustness.py: 48 to 404 of its pixels changed colour at
  // 64x48 to 200x150). With 2x2 samples or more, packets of whole pixels' samples changed
  // no more pixels there than the packets of one pixel's samples did before.
  const int samples = settings_.aa_samples * settings_.aa_samples;
  if (!packets_ || settings_.aa_mode == AntiAliasing::kAdaptive || samples == 1) return 0;
  // As many whole pixels as one packet holds (2x2 samples: 4 pixels), at least one.
  return std::max(1, SceneAccel::kIntersectPacketSize / samples);
}

void CameraSampler::first_hits(int x, int y, FirstHits* out) const {
  const int width = block_width();
  const int samples = settings_.aa_samples * settings_.aa_samples;
  out->x0 = x / width * width;
  out->y = y;
  out->width = std::min(width, settings_.width - out->x0);
  const int count = out->width * samples;
  out->rays.resize(static_cast<size_t>(count));
  out->hits.resize(static_cast<size_t>(count));
  out->found.assign(static_cast<size_t>(count), 0);
  for (int i = 0; i < count; ++i) {
    out->rays[static_cast<size_t>(i)] = grid_ray(out->x0 + i / samples, y, i % samples);
  }
  // The block's rays in order: the same packets whichever pixel of the block asks.
  packet_hits(out->rays.data(), count, out->hits.data(), out->found.data());
}

void CameraSampler::packet_hits(const Ray* rays, int count, Hit* hits, uint8_t* found) const {
  constexpr int kPacket = SceneAccel::kIntersectPacketSize;
  for (int first = 0; first < count; first += kPacket) {
    const int n = std::min(kPacket, count - first);
    if (n == 1) break;  // a lone ray is no packet: the integrator traces it
    integrator_.intersect_packet(rays + first, n, hits + first);
    std::fill_n(found + first, n, uint8_t{1});
  }
}

void CameraSampler::round_hits(int x, int y, int first, int count, RoundHits* out) const {
  const auto n = static_cast<size_t>(count);
  out->first = first;
  out->rays.resize(n);
  out->hits.resize(n);
  out->found.assign(n, 0);
  for (size_t i = 0; i < n; ++i) out->rays[i] = grid_ray(x, y, first + static_cast<int>(i));
  if (packets_) packet_hits(out->rays.data(), count, out->hits.data(), out->found.data());
}

Sample CameraSampler::round_sample(int x, int y, const RoundHits& round, int i, RayCounts* counts,
                                   SampleRecord* record) const {
  const auto at = static_cast<size_t>(i);
  return shade(round.rays[at], round.found[at] != 0 ? &round.hits[at] : nullptr, counts, record,
               grid_root(x, y, round.first + i));
}

bool CameraSampler::waves() const {
  return integrator_.waves();
}

bool CameraSampler::adaptive() const {
  return settings_.aa_mode == AntiAliasing::kAdaptive && !distributed_;
}

void CameraSampler::start(Wave* wave, const Ray& ray, const NodeState& root, uint32_t index,
                          const Hit* first, RayCounts* counts, SampleRecord* record) const {
  counts->camera += 1;
  if (ray.kind == kNoRay) return;  // outside a fisheye's circle: opaque black (shade())
  integrator_.trace_camera(wave, ray, root, index, first, counts, record);
}

void CameraSampler::row(int x0, int x1, int y, int sample, int count, Wave* wave, RayCounts* counts,
                        std::vector<Sample>* values, std::vector<uint64_t>* rays,
                        std::vector<SampleRecord>* records, std::vector<uint32_t>* samples) const {
  if (sample < 0 && adaptive()) {
    row_adaptive(x0, x1, y, wave, counts, values, rays, records, samples);
    return;
  }
  const int grid = settings_.aa_samples * settings_.aa_samples;
  const int per_pixel = sample < 0 ? grid : count;
  const auto pixels = static_cast<size_t>(x1 - x0);
  const bool passes = (settings_.passes & kRecordedPasses) != 0;
  wave->reset(pixels * static_cast<size_t>(per_pixel), passes);
  // Whole pixels take their first hits from the blocks' packets, as pixel() does; a
  // round's samples from the pixel's own packets, as round_sample() does.
  const int width = sample < 0 ? block_width() : 0;
  FirstHits block;
  RoundHits round;
  for (int x = x0; x < x1; ++x) {
    if (width > 0 && !block.holds(x, y)) first_hits(x, y, &block);
    if (sample >= 0) round_hits(x, y, sample, count, &round);
    for (int j = 0; j < per_pixel; ++j) {
      const auto index = static_cast<uint32_t>((x - x0) * per_pixel + j);
      SampleRecord* record = passes ? &wave->records[index] : nullptr;
      if (sample >= 0) {
        const auto at = static_cast<size_t>(j);
        start(wave, round.rays[at], grid_root(x, y, sample + j), index,
              round.found[at] != 0 ? &round.hits[at] : nullptr, counts, record);
        continue;
      }
      const size_t b = width > 0 ? static_cast<size_t>((x - block.x0) * grid + j) : 0;
      const bool found = width > 0 && block.found[b] != 0;
      start(wave, width > 0 ? block.rays[b] : grid_ray(x, y, j), grid_root(x, y, j), index,
            found ? &block.hits[b] : nullptr, counts, record);
    }
  }
  integrator_.trace_wave(wave, counts);
  if (sample >= 0) {  // each sample apart, as grid_sample() gives it
    const size_t n = pixels * static_cast<size_t>(per_pixel);
    values->resize(n);
    rays->resize(n);
    records->resize(passes ? n : 0);
    for (size_t k = 0; k < n; ++k) {
      const WaveSample& s = wave->samples[k];
      SampleRecord* record = passes ? &wave->records[k] : nullptr;
      (*values)[k] = finished(s, counts, record);
      (*rays)[k] = s.rays + 1;  // and its camera ray
      if (record != nullptr) (*records)[k] = *record;
    }
    return;
  }
  values->resize(pixels);
  rays->resize(pixels);
  records->resize(passes ? pixels : 0);
  samples->assign(pixels, static_cast<uint32_t>(per_pixel));
  const float w = 1.0f / static_cast<float>(per_pixel);
  for (size_t i = 0; i < pixels; ++i) {
    // Summed in sample order and averaged, as pixel_grid() sums its samples.
    Sample sum{Color(0.0f), 0.0f};
    uint64_t cost = 0;
    SampleRecord* out = passes ? &(*records)[i] : nullptr;
    if (out != nullptr) *out = SampleRecord{};
    for (size_t j = 0; j < static_cast<size_t>(per_pixel); ++j) {
      const size_t k = i * static_cast<size_t>(per_pixel) + j;
      const WaveSample& s = wave->samples[k];
      cost += s.rays + 1;  // and its camera ray
      SampleRecord* record = passes ? &wave->records[k] : nullptr;
      const Sample value = finished(s, counts, record);
      sum.radiance += value.radiance;
      sum.alpha += value.alpha;
      if (out == nullptr) continue;
      out->add(*record, settings_.passes);
      if (j == 0) out->take_first(*record);
    }
    if (out != nullptr) out->scale(w, settings_.passes);
    (*values)[i] = per_pixel == 1 ? sum : Sample{sum.radiance * w, sum.alpha * w};
    (*rays)[i] = cost;
  }
}

void CameraSampler::row_adaptive(int x0, int x1, int y, Wave* wave, RayCounts* counts,
                                 std::vector<Sample>* values, std::vector<uint64_t>* rays,
                                 std::vector<SampleRecord>* records,
                                 std::vector<uint32_t>* samples) const {
  // pixel_adaptive's squares, breadth first, in the wave's reused buffers.
  std::vector<SubdivisionPoint>& points = wave->points;
  std::vector<SubdivisionSquare>& squares = wave->squares;
  std::vector<SampleRecord>& point_records = wave->point_records;
  const bool passes = (settings_.passes & kRecordedPasses) != 0;
  points.clear();
  squares.clear();
  point_records.clear();
  const auto add_point = [&](float px, float py, uint32_t pixel) {
    points.push_back({px, py, pixel, {Color(0.0f), 0.0f}, 0});
    return static_cast<uint32_t>(points.size() - 1);
  };
  // Traces points[from..] as one wave, each as point() would, their records (where
  // passes are kept) straight into point_records.
  const auto trace = [&](size_t from) {
    wave->reset(points.size() - from, false);
    if (passes) point_records.resize(points.size());
    for (size_t i = from; i < points.size(); ++i) {
      const SubdivisionPoint& p = points[i];
      start(wave, camera_ray(p.x, p.y, film_lens(p.x, p.y), film_time(p.x, p.y)),
            film_root(p.x, p.y), static_cast<uint32_t>(i - from), nullptr, counts,
            passes ? &point_records[i] : nullptr);
    }
    integrator_.trace_wave(wave, counts);
    for (size_t i = from; i < points.size(); ++i) {
      const WaveSample& s = wave->samples[i - from];
      points[i].value = finished(s, counts, passes ? &point_records[i] : nullptr);
      points[i].rays = s.rays + 1;  // and its camera ray
    }
  };
  // Depth 0: each pixel's corners, in pixel_adaptive's order.
  for (int x = x0; x < x1; ++x) {
    const auto fx = static_cast<float>(x);
    const auto fy = static_cast<float>(y);
    const auto i = static_cast<uint32_t>(x - x0);
    squares.push_back({fx,
                       fy,
                       1.0f,
                       {add_point(fx, fy, i), add_point(fx + 1.0f, fy, i),
                        add_point(fx, fy + 1.0f, i), add_point(fx + 1.0f, fy + 1.0f, i)},
                       i});
  }
  size_t traced = 0;
  for (size_t level = 0, depth = 0; level < squares.size(); ++depth) {
    trace(traced);
    traced = points.size();
    // The squares of this depth that split get their five midpoints (subdivide's order:
    // bottom, left, centre, right, top) and quadrants, the next depth's squares.
    const size_t end = squares.size();
    for (size_t i = level; i < end; ++i) {
      const SubdivisionSquare sq = squares[i];
      const Sample corners[4] = {points[sq.corners[0]].value, points[sq.corners[1]].value,
                                 points[sq.corners[2]].value, points[sq.corners[3]].value};
      if (!splits(corners, static_cast<int>(depth))) continue;
      const float h = 0.5f * sq.size;
      const uint32_t px = sq.pixel;
      const uint32_t m[5] = {add_point(sq.x + h, sq.y, px), add_point(sq.x, sq.y + h, px),
                             add_point(sq.x + h, sq.y + h, px),
                             add_point(sq.x + sq.size, sq.y + h, px),
                             add_point(sq.x + h, sq.y + sq.size, px)};
      const auto& c = sq.corners;
      squares[i].child = static_cast<int32_t>(squares.size());
      squares.push_back({sq.x, sq.y, h, {c[0], m[0], m[1], m[2]}, px});
      squares.push_back({sq.x + h, sq.y, h, {m[0], c[1], m[2], m[3]}, px});
      squares.push_back({sq.x, sq.y + h, h, {m[1], m[2], c[2], m[4]}, px});
      squares.push_back({sq.x + h, sq.y + h, h, {m[2], m[3], m[4], c[3]}, px});
    }
    level = end;
  }
  // Each square's mean, bottom-up in subdivide's order of sums; and its record's, where
  // passes are kept (apart: a record is zeroed where it is declared, which cost the
  // renders without passes more than the rest of this function).
  const auto mean = [&](const auto& self, const SubdivisionSquare& sq) -> Sample {
    Sample sum{Color(0.0f), 0.0f};
    for (size_t q = 0; q < 4; ++q) {
      const Sample s = sq.child < 0 ? points[sq.corners[q]].value
                                    : self(self, squares[static_cast<size_t>(sq.child) + q]);
      sum.radiance += 0.25f * s.radiance;
      sum.alpha += 0.25f * s.alpha;
    }
    return sum;
  };
  const auto record_mean = [&](const auto& self, const SubdivisionSquare& sq,
                               SampleRecord* out) -> void {
    for (size_t q = 0; q < 4; ++q) {
      if (sq.child < 0) {
        out->add(point_records[sq.corners[q]], settings_.passes);
        continue;
      }
      SampleRecord quadrant;
      self(self, squares[static_cast<size_t>(sq.child) + q], &quadrant);
      out->add(quadrant, settings_.passes);
    }
    out->scale(0.25f, settings_.passes);
  };
  const auto pixels = static_cast<size_t>(x1 - x0);
  values->resize(pixels);
  rays->assign(pixels, 0);
  records->resize(passes ? pixels : 0);
  for (size_t i = 0; i < pixels; ++i) {
    (*values)[i] = mean(mean, squares[i]);
    if (!passes) continue;
    SampleRecord& out = (*records)[i];
    out = SampleRecord{};
    record_mean(record_mean, squares[i], &out);
    // The first-sample data (depth, position, indices) are the bottom-left corner's.
    out.take_first(point_records[squares[i].corners[0]]);
  }
  samples->assign(pixels, 0);
  for (const SubdivisionPoint& p : points) {
    (*rays)[p.pixel] += p.rays;
    (*samples)[p.pixel] += 1;
  }
}

const FirstHits* CameraSampler::block_for(int x, int y, const FirstHits* block,
                                          FirstHits* own) const {
  if (block != nullptr && block->holds(x, y)) return block;
  if (block_width() == 0) return nullptr;
  first_hits(x, y, own);
  return own;
}

Sample CameraSampler::point(float px, float py, RayCounts* counts, SampleRecord* record) const {
  return shade(camera_ray(px, py, film_lens(px, py), film_time(px, py)), nullptr, counts, record,
               film_root(px, py));
}

Sample CameraSampler::pixel_grid(int x, int y, RayCounts* counts, std::vector<float>* weights,
                                 SampleRecord* record, const FirstHits* block) const {
  // Neighbouring camera rays are coherent: Embree finds the first hits of a block of
  // pixels together (first_hits), then each sample is shaded on its own. The blocks are
  // fixed in the image, so a pixel's value depends on nothing but the pixel (not on tiles,
  // threads or the border): where two faces tie (coplanar, or meeting a ray at their
  // shared edge), the winner can depend on the packet.
  const int n = settings_.aa_samples;
  const int samples = n * n;
  FirstHits own;
  const FirstHits* hits = block_for(x, y, block, &own);
  const size_t offset = hits != nullptr ? static_cast<size_t>((x - hits->x0) * samples) : 0;
  // Summed in sample order, as Film::add sums a pixel built one sample at a time.
  Sample sum{Color(0.0f), 0.0f};
  // Each sample's record, emplaced afresh only when passes are recorded: zeroing every
  // pass cost a render without passes about 48 instructions per sample (callgrind,
  // session 6). Declared once per pixel, as GCC 12 zeroes an optional's storage where it
  // is declared (about 40 instructions per sample inside the loop, callgrind).
  std::optional<SampleRecord> sample_record;
  for (int k = 0; k < samples; ++k) {
    const size_t i = offset + static_cast<size_t>(k);
    const Hit* hit = hits != nullptr && hits->found[i] != 0 ? &hits->hits[i] : nullptr;
    const Sample s =
        shade(hits != nullptr ? hits->rays[i] : grid_ray(x, y, k), hit, counts,
              record != nullptr ? &sample_record.emplace() : nullptr, grid_root(x, y, k));
    sum.radiance += s.radiance;
    sum.alpha += s.alpha;
    if (record != nullptr) {
      record->add(*sample_record, settings_.passes);
      if (k == 0) record->take_first(*sample_record);
    }
  }
  // The average of the samples (box filter).
  const float w = 1.0f / static_cast<float>(samples);
  if (weights != nullptr) weights->assign(static_cast<size_t>(samples), w);
  if (record != nullptr) record->scale(w, settings_.passes);
  return {sum.radiance * w, sum.alpha * w};
}

Ray CameraSampler::grid_ray(int x, int y, int k) const {
  // Placed about the pixel's centre by the pixel filter (the square itself for a Box of 1).
  const auto fx = static_cast<float>(x);
  const auto fy = static_cast<float>(y);
  if (settings_.aa_mode == AntiAliasing::kRegular) {
    // The centre of its cell c of an n x n grid over the unit square, row by row.
    const int n = settings_.aa_samples;
    const int c = regular_cell(settings_, x, y, k);
    const float cell = 1.0f / static_cast<float>(n);
    const float px = fx + filter_.position((static_cast<float>(c % n) + 0.5f) * cell);
    const float py = fy + filter_.position((static_cast<float>(c / n) + 0.5f) * cell);
    const LensTime at =
        lens_and_time(camera_, moves_, settings_.seed, x, y, c, n, settings_.height);
    return camera_ray(px, py, at.lens, at.time);
  }
  // Point k of the pixel's Owen-scrambled Sobol sequences (core/sobol.h), one for the film,
  // one for the lens and one for the time, each seeded by the pixel and its dimension: every
  // power-of-two prefix of the pixel's samples is stratified on the film, on the lens and in
  // the shutter, in every 2D projection, and the three are not paired alike.
  const uint32_t seed = settings_.seed;
  const auto index = static_cast<uint32_t>(k);
  const glm::vec2 film = sobol_point(index, pixel_key(seed, x, y, 0xf11du));
  const glm::vec2 lens =
      camera_.lens.blurs() ? sobol_point(index, pixel_key(seed, x, y, 0x1e45u)) : glm::vec2(0.5f);
  const float time = moves_
                         ? camera_.shutter.time(sobol_value(index, pixel_key(seed, x, y, 0x7a3du)),
                                                y, settings_.height)
                         : 0.0f;
  return camera_ray(fx + filter_.position(film.x), fy + filter_.position(film.y), lens, time);
}

NodeState CameraSampler::film_root(float px, float py) const {
  NodeState root = root_;
  root.seed = film_seed(settings_.seed, px, py);
  return root;
}

NodeState CameraSampler::grid_root(int x, int y, int k) const {
  NodeState root = root_;
  root.seed =
      grid_seed(settings_.seed, x, y,
                settings_.aa_mode == AntiAliasing::kRegular ? regular_cell(settings_, x, y, k) : k);
  root.pixel = pixel_key(settings_.seed, x, y, 0x70786cu);
  root.index = static_cast<uint32_t>(k);
  return root;
}

int regular_cell(const Settings& settings, int x, int y, int k) {
  if (!settings.adaptive_sampling) return k;
  const auto cells = static_cast<uint32_t>(settings.aa_samples * settings.aa_samples);
  return static_cast<int>(
      permuted(static_cast<uint32_t>(k), cells, pixel_key(settings.seed, x, y, 0xadau)));
}

LensTime lens_and_time(const Camera& camera, bool moves, uint32_t seed, int x, int y, int k, int n,
                       int height) {
  LensTime out;
  const auto samples = static_cast<uint32_t>(n * n);
  const auto pixel = pixel_key(seed, x, y, 0x1e45u);
  const auto sample = static_cast<uint32_t>(k);
  if (moves) {
    const uint32_t order = hash3(pixel, 0x7a3du, 0x51edu);
    const float u = (static_cast<float>(permuted(sample, samples, order)) +
                     unit_float(hash3(order, sample, 0x3c6fu))) /
                    static_cast<float>(samples);
    out.time = camera.shutter.time(u, y, height);
  }
  if (!camera.lens.blurs()) return out;
  const float cell = 1.0f / static_cast<float>(n);
  const uint32_t stratum = permuted(sample, samples, pixel);
  const auto h = hash3(pixel, sample, 0x2f1du);
  out.lens =
      glm::vec2((static_cast<float>(stratum % n) + unit_float(h)) * cell,
                (static_cast<float>(stratum / n) + unit_float(hash3(h, 0x6b43u, 0x2f1du))) * cell);
  return out;
}

Ray CameraSampler::camera_ray(float px, float py, glm::vec2 lens, float time) const {
  return frame_.generate_ray(px / static_cast<float>(settings_.width),
                             py / static_cast<float>(settings_.height), lens, time);
}

float CameraSampler::film_time(float px, float py) const {
  if (!moves_) return 0.0f;
  const float u = unit_float(hash3(film_seed(settings_.seed, px, py), 0x7a3du, 0x51edu));
  return camera_.shutter.time(u, static_cast<int>(std::floor(py)), settings_.height);
}

glm::vec2 CameraSampler::film_lens(float px, float py) const {
  if (!frame_.camera.lens.blurs()) return glm::vec2(0.5f);
  const uint32_t h = hash3(film_seed(settings_.seed, px, py), 0x1e45u, 0x2f1du);
  return {unit_float(h), unit_float(hash3(h, 0x6b43u, 0x2f1du))};
}

Sample CameraSampler::pixel_adaptive(int x, int y, RayCounts* counts, std::vector<float>* weights,
                                     SampleRecord* record) const {
  const auto fx = static_cast<float>(x);
  const auto fy = static_cast<float>(y);
  const bool recording = record != nullptr;
  size_t ids[4];
  Sample corners[4];
  std::optional<std::array<SampleRecord, 4>> records;  // only when passes are recorded
  if (recording) records.emplace();
  const SampleRecord* corner_records[4] = {nullptr, nullptr, nullptr, nullptr};
  const float at[4][2] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, {1.0f, 1.0f}};
  for (int i = 0; i < 4; ++i) {
    ids[i] = new_weight(weights);
    SampleRecord* r = recording ? &(*records)[static_cast<size_t>(i)] : nullptr;
    corners[i] = point(fx + at[i][0], fy + at[i][1], counts, r);
    corner_records[i] = r;
  }
  const Sample s =
      subdivide(fx, fy, 1.0f, corners, ids, corner_records, 0, counts, weights, record);
  // The first-sample data (depth, position, indices) are the bottom-left corner's.
  if (recording) record->take_first((*records)[0]);
  return s;
}

size_t CameraSampler::new_weight(std::vector<float>* weights) {
  if (weights == nullptr) return 0;
  weights->push_back(0.0f);
  return weights->size() - 1;
}

Sample CameraSampler::shade(const Ray& ray, const Hit* first, RayCounts* counts,
                            SampleRecord* record, const NodeState& root) const {
  counts->camera += 1;
  if (ray.kind == kNoRay) {  // outside a fisheye's circle: opaque black, as Cycles
    if (record != nullptr) *record = SampleRecord{};
    return {Color(0.0f), 1.0f};
  }
  float alpha = 1.0f;
  const Color c = first != nullptr
                      ? integrator_.trace_from(ray, *first, root, counts, &alpha, record)
                      : integrator_.trace(ray, root, counts, &alpha, record);
  if (!is_finite(c)) {
    counts->nonfinite_samples += 1;  // never let one bad sample poison a pixel
    if (record != nullptr) *record = SampleRecord{};
    return {Color(0.0f), 0.0f};
  }
  return {c, alpha};
}

bool CameraSampler::splits(const Sample corners[4], int depth) const {
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
  return depth < settings_.aa_depth && spread.x + spread.y + spread.z > settings_.aa_threshold;
}

Sample CameraSampler::subdivide(float x0, float y0, float size, const Sample corners[4],
                                const size_t ids[4], const SampleRecord* const records[4],
                                int depth, RayCounts* counts, std::vector<float>* weights,
                                SampleRecord* out) const {
  const bool recording = out != nullptr;
  if (!splits(corners, depth)) {
    Sample mean{Color(0.0f), 0.0f};
    for (int i = 0; i < 4; ++i) {
      mean.radiance += 0.25f * corners[i].radiance;
      mean.alpha += 0.25f * corners[i].alpha;
      // A corner's share of the pixel: a quarter of this square's area.
      if (weights != nullptr) (*weights)[ids[i]] += 0.25f * size * size;
      if (recording) out->add(*records[i], settings_.passes);
    }
    if (recording) out->scale(0.25f, settings_.passes);
    return mean;
  }
  const float h = 0.5f * size;
  // Bottom, left, centre, right and top midpoints, in this order.
  const float at[5][2] = {{h, 0.0f}, {0.0f, h}, {h, h}, {size, h}, {h, size}};
  Sample mid[5];
  size_t mid_ids[5];
  std::optional<std::array<SampleRecord, 5>> mid_records;  // only when passes are recorded
  if (recording) mid_records.emplace();
  const SampleRecord* m[5] = {nullptr, nullptr, nullptr, nullptr, nullptr};
  for (int i = 0; i < 5; ++i) {
    mid_ids[i] = new_weight(weights);
    SampleRecord* r = recording ? &(*mid_records)[static_cast<size_t>(i)] : nullptr;
    mid[i] = point(x0 + at[i][0], y0 + at[i][1], counts, r);
    m[i] = r;
  }
  const Sample quadrants[4][4] = {{corners[0], mid[0], mid[1], mid[2]},
                                  {mid[0], corners[1], mid[2], mid[3]},
                                  {mid[1], mid[2], corners[2], mid[4]},
                                  {mid[2], mid[3], mid[4], corners[3]}};
  const size_t quadrant_ids[4][4] = {{ids[0], mid_ids[0], mid_ids[1], mid_ids[2]},
                                     {mid_ids[0], ids[1], mid_ids[2], mid_ids[3]},
                                     {mid_ids[1], mid_ids[2], ids[2], mid_ids[4]},
                                     {mid_ids[2], mid_ids[3], mid_ids[4], ids[3]}};
  const SampleRecord* const quadrant_records[4][4] = {{records[0], m[0], m[1], m[2]},
                                                      {m[0], records[1], m[2], m[3]},
                                                      {m[1], m[2], records[2], m[4]},
                                                      {m[2], m[3], m[4], records[3]}};
  const float offsets[4][2] = {{0.0f, 0.0f}, {h, 0.0f}, {0.0f, h}, {h, h}};
  Sample mean{Color(0.0f), 0.0f};
  for (int q = 0; q < 4; ++q) {
    std::optional<SampleRecord> quadrant;
    if (recording) quadrant.emplace();
    const Sample s = subdivide(x0 + offsets[q][0], y0 + offsets[q][1], h, quadrants[q],
                               quadrant_ids[q], quadrant_records[q], depth + 1, counts, weights,
                               recording ? &*quadrant : nullptr);
    mean.radiance += 0.25f * s.radiance;
    mean.alpha += 0.25f * s.alpha;
    if (recording) out->add(*quadrant, settings_.passes);
  }
  if (recording) out->scale(0.25f, settings_.passes);
  return mean;
}

}  // namespace whitted
