#include "integrator/ray_tree.h"

#include <stdexcept>
#include <string>

#include "integrator/sampler.h"
#include "integrator/whitted.h"

namespace whitted {

RayTree inspect_pixel(const CompiledScene& scene, const Settings& settings, const Camera& camera,
                      const MediumStack& camera_media, bool packets, int x, int y, int sample) {
  if (x < 0 || y < 0 || x >= settings.width || y >= settings.height) {
    throw std::out_of_range("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") is outside the " + std::to_string(settings.width) + " x " +
                            std::to_string(settings.height) + " image");
  }
  const int grid = settings.aa_samples * settings.aa_samples;
  if (sample >= 0 && settings.aa_mode == AntiAliasing::kAdaptive) {
    throw std::invalid_argument("adaptive anti-aliasing has no grid sample to inspect alone");
  }
  if (sample >= grid) {
    throw std::out_of_range("sample " + std::to_string(sample) + " of a pixel with " +
                            std::to_string(grid) + " samples");
  }
  RayTree tree;
  const WhittedIntegrator integrator(scene, settings, camera, nullptr, &tree);
  const CameraSampler sampler(integrator, camera, camera_media, packets);
  RayCounts counts;
  std::vector<float> weights;  // of each camera sample, in the order traced
  Sample s;
  if (sample < 0) {
    s = sampler.pixel(x, y, &counts, &weights);
  } else {
    s = sampler.grid_sample(x, y, sample, &counts);
    weights.assign(1, 1.0f);
  }
  // Each camera sample was recorded at weight 1; its share of the pixel is known only now
  // (adaptive subdivision decides it from the samples).
  for (RayTreeNode& node : tree.nodes) {
    const float w = weights[static_cast<size_t>(node.sample)];
    node.weight *= w;
    node.emission *= w;
    node.ambient *= w;
    node.background *= w;
    node.diffuse *= w;
    node.specular *= w;
    node.scattered *= w;
    if (sample >= 0) node.sample = sample;
  }
  tree.pixel = s.radiance;
  tree.alpha = s.alpha;
  return tree;
}

}  // namespace whitted
