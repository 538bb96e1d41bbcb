// Which effects a scene calls for, decided once before tracing, so the integrator can
// run a variant with the others compiled out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "integrator/settings.h"
#include "scene/scene.h"

namespace whitted {

enum EffectBits : uint32_t {
  kShadowEffect = 1u << 0,        // shadow feelers: a light casts shadows and something can
                                  // block it
  kReflectionEffect = 1u << 1,    // a material reflects (or refracts, with Fresnel)
  kRefractionEffect = 1u << 2,    // a material transmits
  kTranslucencyEffect = 1u << 3,  // a material lets light through (alpha, transmission):
                                  // cut-out walks for camera rays and shadow feelers
  kPruningEffect = 1u << 4,       // skip rays that cannot show (backfacing lights, zero
                                  // irradiance, contribution below the cutoff)
  kAllEffects = (1u << 5) - 1,
};

struct Effects {
  uint32_t bits = kAllEffects;
  // One line per effect: "reflection: off, no reflective or transmissive material".
  std::vector<std::string> reasons;
  bool has(uint32_t bit) const { return (bits & bit) != 0; }
};

// With settings.analysis off, every effect is on and nothing is pruned (the baseline the
// benchmark compares against).
Effects analyse(const CompiledScene& scene, const Settings& settings);

}  // namespace whitted
