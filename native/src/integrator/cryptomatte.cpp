#include "integrator/cryptomatte.h"

#include <algorithm>

#include "core/ray.h"
#include "integrator/sampler.h"

namespace whitted {
namespace {

// As the image's kernels (kernel.h): past this many cut-outs a surface covers all.
constexpr int kMaxLayers = 64;

int samples_per_axis(const Settings& s) {
  return s.aa_mode == AntiAliasing::kAdaptive ? 1 << s.aa_depth : s.aa_samples;
}

}  // namespace

CryptomatteFilm::CryptomatteFilm(const Settings& settings)
    : width_(settings.width),
      height_(settings.height),
      samples_per_axis_(samples_per_axis(settings)),
      seed_(settings.seed),
      filter_(settings),
      kinds_(settings.cryptomatte_kinds),
      depth_(settings.cryptomatte_depth) {
  if (!enabled()) return;
  for (int k = 0; k < kCryptomatteKinds; ++k) {
    if (has(static_cast<CryptomatteKind>(k))) {
      ranks_[static_cast<size_t>(k)].assign(
          static_cast<size_t>(width_) * height_ * static_cast<size_t>(channels()), 0.0f);
    }
  }
}

void CryptomatteFilm::trace_pixel(const CompiledScene& scene, const Camera& camera, int x, int y) {
  const int n = samples_per_axis_;
  std::array<std::vector<std::array<float, 2>>, kCryptomatteKinds> weights;
  const RayContext context{&camera, 0};
  const bool moves = scene.moves || camera.motion != nullptr;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Placed by the pixel filter as the image's grid samples are (its coverage is
      // the image's).
      const float px = static_cast<float>(x) +
                       filter_.position((static_cast<float>(i) + 0.5f) / static_cast<float>(n));
      const float py = static_cast<float>(y) +
                       filter_.position((static_cast<float>(j) + 0.5f) / static_cast<float>(n));
      // On the lens and in the shutter as the image's samples are (depth of field and
      // motion blur spread an object's coverage as they spread its colour).
      const LensTime at = lens_and_time(camera, moves, seed_, x, y, j * n + i, n, height_);
      Ray ray = camera.generate_ray(px / static_cast<float>(width_),
                                    py / static_cast<float>(height_), at.lens, at.time);
      float behind = 1.0f;  // the share of the sample not yet covered
      for (int layer = 0; behind > 0.0f; ++layer) {
        Hit hit;
        if (!scene.accel->intersect(ray, &hit)) break;
        const Interaction it = scene.interaction(ray, hit);
        if (it.holdout) break;
        float a = 1.0f;
        if (layer < kMaxLayers && it.material->translucent()) {
          a = scene.surface(it, ray, context).alpha;
        }
        if (a > 0.0f) {
          const CryptomatteIds& ids = scene.instances[it.instance].cryptomatte;
          const size_t slot = scene.instances[it.instance].mesh->mesh.slot(it.primitive);
          const float material = slot < ids.materials.size() ? ids.materials[slot] : 0.0f;
          const float share = behind * a;
          weights[0].push_back({ids.object, share});
          weights[1].push_back({material, share});
          weights[2].push_back({ids.asset, share});
        }
        behind *= 1.0f - a;
        if (behind <= 0.0f) break;
        const float left = ray.t_max - glm::length(it.position - ray.origin);
        if (!(left > 0.0f)) break;
        ray = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, ray.direction,
                        RayKind(ray.kind), left);
      }
    }
  }
  const float scale = 1.0f / static_cast<float>(n * n);
  const size_t at = (static_cast<size_t>(y) * width_ + x) * static_cast<size_t>(channels());
  for (int k = 0; k < kCryptomatteKinds; ++k) {
    std::vector<float>& out = ranks_[static_cast<size_t>(k)];
    if (!out.empty()) rank_ids(&weights[static_cast<size_t>(k)], depth_, scale, out.data() + at);
  }
}

void rank_ids(std::vector<std::array<float, 2>>* weights, int depth, float scale, float* out) {
  std::vector<std::array<float, 2>>& w = *weights;
  // Equal ids next to each other, then summed.
  std::sort(w.begin(), w.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  size_t unique = 0;
  for (size_t i = 0; i < w.size(); ++i) {
    if (w[i][0] == 0.0f) continue;
    if (unique > 0 && w[unique - 1][0] == w[i][0]) {
      w[unique - 1][1] += w[i][1];
    } else {
      w[unique++] = w[i];
    }
  }
  w.resize(unique);
  std::stable_sort(w.begin(), w.end(), [](const auto& a, const auto& b) { return a[1] > b[1]; });
  for (int r = 0; r < depth; ++r) {
    const bool found = static_cast<size_t>(r) < w.size();
    out[2 * r] = found ? w[static_cast<size_t>(r)][0] : 0.0f;
    out[2 * r + 1] = found ? w[static_cast<size_t>(r)][1] * scale : 0.0f;
  }
}

}  // namespace whitted
