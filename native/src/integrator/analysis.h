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
  kPruningEffect = 1u << 4,       // skip shadow feelers that cannot show (the light
                                  // behind the surface, no irradiance, the light's
                                  // contribution below the cutoff)
  kAllEffects = (1u << 5) - 1,
  // Glossy rays from lobes rougher than a mirror (scene/microfacet.h). Read at run time
  // in every kernel: not one of the sets the kernels are compiled for (kAllEffects).
  kGlossyEffect = 1u << 5,
  // Feelers to emissive meshes (scene/mesh_light.h), read at run time likewise.
  kEmitterEffect = 1u << 6,
  // Feelers to the world as a light (scene/world_light.h), read at run time likewise.
  kWorldLightEffect = 1u << 7,
  // Homogeneous media (integrator/volume.h): segments inside them, their bounds, and
  // shadow feelers through them. Read at run time likewise; the step's queries meet
  // volume bounds only where it is on.
  kVolumeEffect = 1u << 8,
  // Shadow catchers (integrator/catcher.h): a camera ray's hit on one shows only the
  // shadows cast on it. Read at run time likewise.
  kCatcherEffect = 1u << 9,
};

// One decision of the analysis: an effect's name, whether it is simulated, and why
// ({"refraction", false, "no transmissive material"}).
struct EffectDecision {
  std::string name;
  bool on = true;
  std::string why;

  bool operator==(const EffectDecision&) const = default;
};

struct Effects {
  uint32_t bits = kAllEffects | kGlossyEffect | kEmitterEffect | kWorldLightEffect | kVolumeEffect |
                  kCatcherEffect;
  // One per effect, in EffectBits order (glossy after reflection, emitters after shadows),
  // then what is named without a bit: hair and points, light linking, the camera's.
  std::vector<EffectDecision> decisions;
  bool has(uint32_t bit) const { return (bits & bit) != 0; }
};

// With settings.analysis off, every effect is on; pruning follows settings.feeler_pruning
// (both off: the plain Whitted tracer the benchmark compares against).
// The camera's depth of field is named too (simulated wherever its lens has an aperture).
Effects analyse(const CompiledScene& scene, const Settings& settings,
                const Camera& camera = Camera{});

}  // namespace whitted
