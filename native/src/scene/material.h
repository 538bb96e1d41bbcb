// Whitted material parameters: Phong local term plus reflection and transmission weights.
#pragma once

#include <cstdint>
#include <string>

#include "core/math.h"

namespace whitted {

struct Material {
  Color diffuse{0.8f};          // albedo kd: the diffuse term is kd/pi * E
  Color specular{0.0f};         // ks of a normalised Phong lobe ks*(f+2)/(2pi)*(v.r)^f * E
  float shininess = 50.0f;      // Phong exponent f
  float ambient = 1.0f;         // ka: the ambient term is ka * Ia * kd
  Color reflectivity{0.0f};     // sigma_r: weight of the mirror-reflected ray
  Color transmissivity{0.0f};   // sigma_t: weight of the refracted ray
  float ior = 1.5f;             // index of refraction inside the surface (outside: 1)
  Color emission{0.0f};         // radiance added as is
  float alpha = 1.0f;           // coverage: 1 opaque, 0 invisible (cut-outs)
  int32_t priority = 0;         // nested dielectrics: the higher owns overlaps (medium.h)
  std::string diffuse_texture;  // multiplies `diffuse` by its RGB ("" for none)
  std::string alpha_texture;    // multiplies `alpha` by its A ("" for none)
  // Indices into CompiledScene::textures, resolved by Scene::compile (-1: none).
  int32_t diffuse_texture_index = -1;
  int32_t alpha_texture_index = -1;

  bool reflective() const { return !is_black(reflectivity); }
  bool transmissive() const { return !is_black(transmissivity); }
  // Lets some light through: transmission, or coverage below 1 (after compile, which
  // resolves the alpha texture).
  bool translucent() const { return transmissive() || alpha < 1.0f || alpha_texture_index >= 0; }
};

}  // namespace whitted
