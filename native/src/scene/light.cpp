#include "scene/light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "shader/program.h"

namespace whitted {
namespace {

// The narrowest spread an area light takes (Cycles 4.x's; 3.x's is 1 degree): below it
// the normalisation's float loses the light.
constexpr float kMinSpread = 0.1f * kPi / 180.0f;

// The inputs lamp_emission gives a lamp's program.
bool lamp_input(uint32_t mode) {
  return mode == kInputPosition || mode == kInputNormal || mode == kInputTrueNormal ||
         mode == kInputIncoming || mode == kInputRayLength;
}

void require_finite(bool finite, const char* what) {
  if (!finite) throw std::invalid_argument(std::string("light ") + what + " must be finite");
}

// Cone falloff as Cycles defines it: zero outside the half angle, a smoothstep over the
// blend band inside it.
float spot_falloff(const Light& light, const Vec3& to_point) {
  const float c = glm::dot(glm::normalize(light.direction), to_point);
  const float c0 = std::cos(0.5f * light.spot_size);
  if (c <= c0) return 0.0f;
  const float band = (1.0f - c0) * light.spot_blend;
  const float falloff = band > 0.0f ? smoothstep01((c - c0) / band) : 1.0f;
  return light.spot_cosine_falloff ? c * falloff : falloff;
}

// What an area light of Spread `spread` sends towards a direction `cos_l` off its normal,
// relative to a plain (Lambertian) one, as Cycles models a soft box's grid: the share of
// the light its slats let through, (tan h - tan a) / (tan h - h) with h the half spread,
// normalised so that the light's power stays the same (at small h, 3 / h^3 is the limit
// of that normalisation, kept where float's tan h - h loses its digits).
float spread_attenuation(float spread, float cos_l) {
  if (spread >= kPi) return 1.0f;
  const float h = 0.5f * std::max(spread, kMinSpread);
  const float tan_a = std::sqrt(std::max(0.0f, 1.0f - cos_l * cos_l)) / cos_l;
  const float normalise = h > 0.05f ? 1.0f / (std::tan(h) - h) : 3.0f / (h * h * h);
  return std::max(0.0f, (std::tan(h) - tan_a) * normalise);
}

// An area light's area, world units squared.
float area_of(const Light& light) {
  return light.size[0] * light.size[1] * (light.shape == AreaShape::kEllipse ? 0.25f * kPi : 1.0f);
}

// The point of sample `index` of an n x n grid, in [0, 1]^2: its stratum's centre (the
// lattice of the seed's soft shadows), or *at where given (a Monte Carlo draw).
void stratum(const Light& light, int index, const glm::vec2* at, float* u, float* v) {
  if (at != nullptr) {
    *u = at->x;
    *v = at->y;
    return;
  }
  const int n = light.samples;
  *u = (static_cast<float>(index % n) + 0.5f) / static_cast<float>(n);
  *v = (static_cast<float>(index / n) + 0.5f) / static_cast<float>(n);
}

// Sample `index` (stratum) on the unit-diameter disc, in [-0.5, 0.5]^2.
void disc_offset(const Light& light, int index, const glm::vec2* at, float* a, float* b) {
  float u = 0.0f;
  float v = 0.0f;
  stratum(light, index, at, &u, &v);
  // The concentric map keeps the strata equal in area on the disk.
  float r = 0.0f;
  float phi = 0.0f;
  concentric_disc(2.0f * u - 1.0f, 2.0f * v - 1.0f, &r, &phi);
  *a = 0.5f * r * std::cos(phi);
  *b = 0.5f * r * std::sin(phi);
}

// Sample `index` (stratum) on an area light's shape, in [-0.5, 0.5]^2.
void area_offset(const Light& light, int index, const glm::vec2* at, float* a, float* b) {
  if (light.shape == AreaShape::kEllipse) {
    disc_offset(light, index, at, a, b);
    return;
  }
  stratum(light, index, at, a, b);
  *a -= 0.5f;
  *b -= 0.5f;
}

// Two unit vectors perpendicular to unit vector w and to each other.
void basis(const Vec3& w, Vec3* u, Vec3* v) {
  const Vec3 helper = std::fabs(w.x) > 0.9f ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(1.0f, 0.0f, 0.0f);
  *u = glm::normalize(glm::cross(helper, w));
  *v = glm::cross(w, *u);
}

// Sample `index` (stratum) of a sized light, on its shape: the disc of a sun or a sphere light, an
// area light's rectangle or ellipse. From the constructor's table where it has one.
glm::vec2 strata_offset(const Light& light, int index, const glm::vec2* at) {
  if (at == nullptr && static_cast<size_t>(index) < light.offsets.size()) {
    return light.offsets[static_cast<size_t>(index)];
  }
  glm::vec2 out(0.0f);
  if (light.type == LightType::kArea) {
    area_offset(light, index, at, &out.x, &out.y);
  } else {
    disc_offset(light, index, at, &out.x, &out.y);
  }
  return out;
}

// The direction towards sample `index` of a sun with a disc.
Vec3 sun_direction(const Light& light, int index, const glm::vec2* at) {
  const Vec3 towards = -glm::normalize(light.direction);
  // Directions spread over the sun's disc, of angular radius angle/2.
  Vec3 u;
  Vec3 v;
  basis(towards, &u, &v);
  const glm::vec2 o = strata_offset(light, index, at);
  const float spread = 2.0f * std::tan(0.5f * std::min(light.angle, 3.0f));
  return glm::normalize(towards + spread * (o.x * u + o.y * v));
}

}  // namespace

Light::Light(const LightParams& params) : LightParams(params) {
  for (const Vec3* v : {&color, &position, &direction, &axis_u, &axis_v}) {
    require_finite(is_finite(*v), "colour, position and axes");
  }
  require_finite(std::isfinite(spot_size) && std::isfinite(spot_blend) && std::isfinite(size[0]) &&
                     std::isfinite(size[1]),
                 "spot size, blend and area size");
  require_finite(std::isfinite(radius) && std::isfinite(angle) && std::isfinite(spread),
                 "radius, angle and spread");
  if (glm::length(direction) == 0.0f) {
    throw std::invalid_argument("light direction must not be zero");
  }
  if (samples < 1 || samples > kMaxLightSamples) {
    throw std::invalid_argument("light samples must be between 1 and " +
                                std::to_string(kMaxLightSamples));
  }
  if (program) {
    if (std::string why = lamp_program_refusal(*program, type, program_output); !why.empty()) {
      throw std::invalid_argument("a lamp's program cannot run: " + why);
    }
  }
  color = glm::max(color, Vec3(0.0f));  // negative power emits nothing
  direction = glm::normalize(direction);
  spot_size = std::clamp(spot_size, 0.0f, kPi);
  spot_blend = std::clamp(spot_blend, 0.0f, 1.0f);
  size[0] = std::max(0.0f, size[0]);
  size[1] = std::max(0.0f, size[1]);
  radius = std::max(0.0f, radius);
  angle = std::clamp(angle, 0.0f, kPi);
  spread = std::clamp(spread, 0.0f, kPi);
  max_bounces = std::max(max_bounces, 0);
  if (sized()) {
    const int count = sample_count();
    for (int i = 0; i < count; ++i) offsets.push_back(strata_offset(*this, i, nullptr));
    if (type == LightType::kSun) {
      for (int i = 0; i < count; ++i) sun_directions.push_back(sun_direction(*this, i, nullptr));
    }
  }
}

LightSample sample_light(const Light& light, const Vec3& p, int index, const glm::vec2* at) {
  // What each of a sized light's feelers carries of it; asked only there (not per feeler
  // of a sun without a disc, the common case).
  const auto share = [&] { return 1.0f / static_cast<float>(light.sample_count()); };
  if (light.type == LightType::kSun) {
    if (light.angle <= 0.0f) return {-glm::normalize(light.direction), kInfinity, light.color};
    const auto i = static_cast<size_t>(index);
    const Vec3 wi = at == nullptr && i < light.sun_directions.size()
                        ? light.sun_directions[i]
                        : sun_direction(light, index, at);
    return {wi, kInfinity, light.color * share()};
  }
  Vec3 target = light.position;
  float weight = 1.0f;
  Vec3 disc_normal(0.0f);  // a sphere light's disc, facing p
  if (light.type != LightType::kArea && light.radius > 0.0f) {
    // A sphere light seen from p: a disc of its radius facing p, as Cycles 3.x does.
    const Vec3 axis = p - light.position;
    const float length = glm::length(axis);
    if (length > light.radius) {
      Vec3 u;
      Vec3 v;
      disc_normal = axis / length;
      basis(disc_normal, &u, &v);
      const glm::vec2 o = strata_offset(light, index, at);
      target += 2.0f * light.radius * (o.x * u + o.y * v);
    }
    weight = share();  // each feeler carries its share of the intensity
  } else if (light.type == LightType::kArea) {
    const glm::vec2 o = strata_offset(light, index, at);
    target += o.x * light.size[0] * light.axis_u + o.y * light.size[1] * light.axis_v;
    weight = area_of(light) * share();
  }
  const Vec3 d = target - p;
  const float dist2 = glm::dot(d, d);
  const float dist = std::sqrt(dist2);
  if (!(dist > 0.0f)) return {Vec3(0.0f, 0.0f, 1.0f), 0.0f, Color(0.0f)};
  const Vec3 wi = d / dist;
  Color irradiance(0.0f);
  // The density of wi: a sphere light's feelers draw its disc uniformly by area (an area
  // light's its shape, below); 0 where the light has no disc.
  const float disc_cos = -glm::dot(wi, disc_normal);
  float density = disc_cos > 0.0f ? dist2 / (kPi * light.radius * light.radius * disc_cos) : 0.0f;
  switch (light.type) {
    case LightType::kPoint:
      irradiance = light.color * (weight / dist2);  // E = I / r^2
      break;
    case LightType::kSpot:
      // The cone is measured from the light's centre, as Cycles does.
      {
        const Vec3 from_centre = p - light.position;
        const float length = glm::length(from_centre);
        if (length > 0.0f) {
          irradiance = light.color * (weight * spot_falloff(light, from_centre / length) / dist2);
        }
      }
      break;
    case LightType::kArea: {
      // A patch of area dA and radiance L gives E = L cos(theta_l) dA / r^2, one-sided.
      const float cos_l = glm::dot(glm::normalize(light.direction), -wi);
      if (cos_l > 0.0f) {
        irradiance =
            light.color * (cos_l * weight * spread_attenuation(light.spread, cos_l) / dist2);
        density = dist2 / (area_of(light) * cos_l);
      }
      break;
    }
    case LightType::kSun:
      break;
  }
  if (light.program && !is_black(irradiance)) {
    // A point or spot lamp faces the lit point (Cycles' Ng = -D); an area lamp's normal is
    // the way its light travels.
    const Vec3 normal = light.type == LightType::kArea ? light.direction : -wi;
    irradiance *= lamp_emission(light, target, normal, -wi, dist);
  }
  return {wi, dist, irradiance, density};
}

std::string lamp_program_refusal(const Program& program, LightType type, uint32_t output) {
  if (type == LightType::kSun) return "a sun's program is not evaluated";
  if (output >= program.register_count()) return "its output is not one of its registers";
  if (!program.textures().empty()) return "it samples an image, which no lamp gives";
  if (program.traces()) return "it traces rays from a hit (Ambient Occlusion, Bevel)";
  if (program.bumps()) return "it bumps a normal, which no lamp has";
  for (uint32_t mode : program.inputs()) {
    if (!lamp_input(mode)) return "it reads a coordinate or a path input Whitted gives no lamp";
  }
  return {};
}

Color lamp_emission(const Light& light, const Vec3& point, const Vec3& normal, const Vec3& towards,
                    float length) {
  const Program& program = *light.program;
  std::array<glm::vec4, Program::kMaxInputs> inputs;
  for (size_t i = 0; i < program.inputs().size(); ++i) {
    switch (program.inputs()[i]) {
      case kInputPosition:
        inputs[i] = glm::vec4(point, 0.0f);
        break;
      case kInputNormal:
      case kInputTrueNormal:
        inputs[i] = glm::vec4(normal, 0.0f);
        break;
      case kInputIncoming:
        inputs[i] = glm::vec4(towards, 0.0f);
        break;
      default:  // kInputRayLength, the last the constructor lets through (lamp_input)
        inputs[i] = glm::vec4(length);
        break;
    }
  }
  ProgramHit hit;
  hit.inputs = inputs.data();
  hit.incoming = towards;
  hit.normal = normal;
  // The register file of one evaluation, on the stack.
  std::array<glm::vec4, Program::kMaxRegisters + 1> registers;
  program.run(hit, registers.data());
  return glm::max(Color(registers[light.program_output]), Color(0.0f));
}

bool intersect_light(const Light& light, const Ray& ray, float t_max, LightHit* hit) {
  if (!light.has_shape()) return false;
  const Vec3& d = ray.direction;
  if (light.type == LightType::kArea) {
    // Seen from its lit side only: the ray goes against the way the light travels.
    const float cos_l = -glm::dot(d, light.direction);
    if (!(cos_l > 0.0f)) return false;
    const float t = glm::dot(ray.origin - light.position, light.direction) / cos_l;
    if (!(t > ray.t_min && t < t_max)) return false;
    // Where in the shape, in [-0.5, 0.5]^2 of its extents (the axes are unit vectors).
    const Vec3 q = ray.origin + t * d - light.position;
    const float a = glm::dot(q, light.axis_u) / light.size[0];
    const float b = glm::dot(q, light.axis_v) / light.size[1];
    const bool inside = light.shape == AreaShape::kEllipse
                            ? a * a + b * b <= 0.25f
                            : std::fabs(a) <= 0.5f && std::fabs(b) <= 0.5f;
    if (!inside) return false;
    Color radiance = light.color * spread_attenuation(light.spread, cos_l);
    // Its program at the point met, for the ray's length from where it starts (a camera
    // ray at its near clip distance, as a surface's Ray Length).
    if (light.program) {
      radiance *= lamp_emission(light, ray.origin + t * d, light.direction, -d, t - ray.t_min);
    }
    *hit = {t, radiance, t * t / (area_of(light) * cos_l)};
    return true;
  }
  // A sphere light: the disc of its radius through its centre, facing the ray's origin.
  const Vec3 to_origin = ray.origin - light.position;
  const float length = glm::length(to_origin);
  if (!(length > light.radius)) return false;  // from inside, no disc faces the origin
  const Vec3 normal = to_origin / length;
  const float cos_n = -glm::dot(d, normal);
  if (!(cos_n > 0.0f)) return false;
  const float t = length / cos_n;
  if (!(t > ray.t_min && t < t_max)) return false;
  const Vec3 q = ray.origin + t * d - light.position;
  const float r2 = light.radius * light.radius;
  if (glm::dot(q, q) > r2) return false;
  // A sphere of intensity I (W/sr) seen as a disc of area pi r^2: radiance I / (pi r^2);
  // a spot's cone at the direction the ray came from, as Cycles weighs it.
  Color radiance = light.color * (1.0f / (kPi * r2));
  if (light.type == LightType::kSpot) radiance *= spot_falloff(light, -d);
  if (light.program)
    radiance *= lamp_emission(light, ray.origin + t * d, normal, -d, t - ray.t_min);
  if (is_black(radiance)) return false;
  *hit = {t, radiance, t * t / (kPi * r2 * cos_n)};
  return true;
}

}  // namespace whitted
