#include "scene/material.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace whitted {

Material::Material(const MaterialParams& params) : MaterialParams(params) {
  for (const Color* c : {&diffuse, &specular, &reflectivity, &transmissivity, &emission}) {
    if (!is_finite(*c)) throw std::invalid_argument("material colours must be finite");
  }
  if (!std::isfinite(shininess) || !std::isfinite(ambient) || !std::isfinite(ior) || ior <= 0.0f) {
    throw std::invalid_argument(
        "material shininess, ambient and ior must be finite and ior positive");
  }
  if (!std::isfinite(alpha)) throw std::invalid_argument("alpha must be finite");
  for (const float v : {coat_specular, coat_reflectivity, coat_shininess, coat_ior}) {
    if (!std::isfinite(v)) throw std::invalid_argument("coat values must be finite");
  }
  if (coat_ior <= 0.0f) throw std::invalid_argument("coat_ior must be positive");
  alpha = std::clamp(alpha, 0.0f, 1.0f);
  // Every output a register of the program that computes it.
  for (size_t f = 0; f < kFieldCount; ++f) {
    if (outputs[f] < 0) continue;
    if (!program) throw std::invalid_argument("material outputs need a program");
    if (static_cast<uint64_t>(outputs[f]) >= program->register_count()) {
      throw std::invalid_argument("output '" + std::string(kFieldNames[f]) + "' register " +
                                  std::to_string(outputs[f]) + " out of range (" +
                                  std::to_string(program->register_count()) + " registers)");
    }
  }
}

}  // namespace whitted
