// Lights, in the units Cycles uses, checked on construction, and the feelers a shading
// point sends to them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/ray.h"

namespace whitted {

class Program;  // shader/program.h

enum class LightType { kPoint, kSpot, kSun, kArea };

// Light linking (Blender 4.0+, Object > Light Linking): every object is a receiver in one
// light set and a blocker in one shadow set (0: named by no emitter's collection), and
// every emitter, lamp or emissive mesh, lights a mask of light sets and is shadowed by a
// mask of shadow sets. Blender's depsgraph rules, resolved by addon/export/light_linking.py.
inline constexpr uint64_t kAllLightSets = ~uint64_t{0};
inline constexpr int kMaxLightSets = 64;
inline bool in_sets(uint64_t sets, uint32_t set) {
  return ((sets >> set) & 1u) != 0;
}
enum class AreaShape { kRectangle, kEllipse };

// A light as the exporter describes it, in the units Cycles uses. Light's constructor
// checks and normalises it; these defaults are a valid 1 W/sr point light.
struct LightParams {
  LightType type = LightType::kPoint;
  // In the light's own unit, light colour included: radiant intensity (W/sr) for point and
  // spot, irradiance (W/m^2) for sun, radiance (W/(m^2 sr)) for area.
  Color color{1.0f};
  Vec3 position{0.0f};
  Vec3 direction{0.0f, 0.0f, -1.0f};  // the way light travels: spot axis, sun, area normal
  float spot_size = 0.785398f;        // full cone angle, radians
  float spot_blend = 0.15f;
  // Cycles before Blender 4.0 also multiplies the cone falloff by the cosine to the axis.
  bool spot_cosine_falloff = false;
  float size[2] = {0.0f, 0.0f};  // area extents along axis_u and axis_v, world units
  Vec3 axis_u{1.0f, 0.0f, 0.0f};
  Vec3 axis_v{0.0f, 1.0f, 0.0f};
  AreaShape shape = AreaShape::kRectangle;
  float radius = 0.0f;  // point and spot: a sphere of this radius (soft shadows)
  float angle = 0.0f;   // sun: full apex angle of the sun's disc, radians
  // Area: the full angle its light spreads over, radians (pi: all of its side; less:
  // a soft box's grid narrowing it, Cycles' Spread).
  float spread = kPi;
  int samples = 1;  // per axis for sized lights: samples x samples feelers
  bool cast_shadows = true;
  // Its ray visibility (Cycles' Diffuse and Glossy): whether it lights the diffuse terms,
  // and whether it shows in the specular ones (Phong highlight, coat, glossy lobes).
  bool diffuse = true;
  bool glossy = true;
  // The RayKind bits of the rays that see its shape (Cycles' Ray Visibility: Camera,
  // Glossy for reflected rays, Transmission for refracted ones), where it has one
  // (Light::has_shape). Blender makes lamps unseen by the camera.
  uint32_t visibility = kReflectionRay | kRefractionRay;
  // Cycles' Max Bounces: it lights only surfaces reached after at most this many
  // bounces (a camera ray's hit has had none; each reflection or refraction is one).
  int max_bounces = 1024;
  // Light linking: the receivers' light sets it lights, the blockers' shadow sets that
  // cast its shadows (all: no linking).
  uint64_t light_sets = kAllLightSets;
  uint64_t shadow_sets = kAllLightSets;
  // A node tree whose emission varies over the lamp (the add-on's export/light.py
  // light_shader; Light Falloff's ray length, say): the program whose register
  // `program_output` (xyz) multiplies `color` at each point a feeler samples on the lamp
  // and where a ray meets its shape (lamp_emission). Null: `color` alone, as for every
  // lamp whose tree folds to a constant.
  std::shared_ptr<const Program> program;
  uint32_t program_output = 0;
};

// The samples per axis a sized light may ask for (64 x 64 feelers per shading point).
inline constexpr int kMaxLightSamples = 64;

struct Light : LightParams {
  Light() = default;
  // Throws std::invalid_argument for what cannot be a light (a non-finite colour, point,
  // axis, radius or angle; a zero direction; samples outside 1..kMaxLightSamples) and
  // clamps what has an obvious nearest light: negative colour to 0 (it emits nothing),
  // spot size to [0, pi], blend to [0, 1], negative sizes and radius to 0, the sun's
  // angle and an area light's spread to [0, pi], negative max bounces to 0. The direction
  // is normalised. A program must be one a lamp can run (lamp_emission): not on a sun, its
  // output one of its registers, reading only the inputs a lamp gives and no image, and
  // tracing no ray.
  explicit Light(const LightParams& params);

  bool sized() const {
    return type == LightType::kArea || (type == LightType::kSun ? angle > 0.0f : radius > 0.0f);
  }
  int sample_count() const { return sized() ? samples * samples : 1; }
  // Whether a ray can meet it (intersect_light): an area light's rectangle or ellipse, a
  // point or spot light's sphere; a sun, or a point without a radius, has no shape.
  bool has_shape() const { return sized() && type != LightType::kSun; }

  // A sized light's samples as far as they do not depend on the shading point, made once
  // by the constructor: each stratum's offset on the light's shape ([-0.5, 0.5]^2; a disc
  // for a sun or a sphere light), and a sun's direction towards each. Drawing them per
  // feeler (a concentric map, a sine and cosine, a basis) was a quarter of the demo
  // scene's instructions (docs/notes/waves.md). Empty for a Light built field by field
  // without the constructor (tests), whose samples sample_light draws one by one; a
  // light whose parameters change must be constructed again.
  std::vector<glm::vec2> offsets;
  std::vector<Vec3> sun_directions;
};

// One feeler's worth of light arriving at a point.
struct LightSample {
  Vec3 wi;           // unit direction from the point towards the light
  float distance;    // to the light sample; infinity for the sun
  Color irradiance;  // on a surface facing wi, before the surface's cosine and visibility
  // The density with which one of the light's feelers draws wi, per unit solid angle
  // (the MIS weight against the rays that meet its shape); 0 for a light without one.
  float density = 0.0f;
};

// Sample `index` of light.sample_count() arriving at point p. Irradiance is zero where
// the light cannot reach (outside a spot cone, behind an area light). A sized light's
// samples are the centres of its n x n strata (a fixed lattice), or, given `at`, the point
// *at of [0, 1)^2 placed on its shape (a Monte Carlo camera sample's draw: lights.h).
LightSample sample_light(const Light& light, const Vec3& p, int index,
                         const glm::vec2* at = nullptr);

// Why `program`, its output in register `output`, cannot be the program of a lamp of
// `type` (lamp_emission's: it reads only the lamp's point, normal, incoming direction and
// ray length, samples no image, traces no ray, bumps nothing, and no sun runs one); empty
// where it can. The one statement of the rule: Light's constructor refuses what it names,
// and the add-on asks it before handing a lamp a program (export/light.py).
std::string lamp_program_refusal(const Program& program, LightType type, uint32_t output);

// What light.program gives (xyz; a negative channel emits nothing) at `point` on the lamp,
// whose normal there is `normal`, for a point `length` away along unit `towards` from it:
// the inputs Cycles gives a lamp's shader (shader_setup_from_sample: P; N and Ng, facing the
// lit point on a point or spot lamp, the area's own; I; the ray length Light Falloff
// reads). The lamp's other inputs (coordinates, Light Path) are not given: the
// constructor refuses a program that reads them.
Color lamp_emission(const Light& light, const Vec3& point, const Vec3& normal, const Vec3& towards,
                    float length);

// Where a ray meets a light's shape, as Cycles' lamps are met: an area light's rectangle
// or ellipse from its lit side, a point or spot light's sphere as the disc of its radius
// facing the ray's origin (what its feelers sample, and Cycles 3.x's sphere light).
struct LightHit {
  float t;         // along the ray
  Color radiance;  // what the ray sees there, W/(m^2 sr): the feelers' irradiance integrates it
  float density;   // LightSample::density of a feeler from the ray's origin towards the hit
};

// Whether `ray` meets the shape of `light` within (ray.t_min, t_max), and where (*hit). A
// light without a shape (has_shape) is met by none.
bool intersect_light(const Light& light, const Ray& ray, float t_max, LightHit* hit);

}  // namespace whitted
