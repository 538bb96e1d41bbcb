#include "shader/program.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "shader/blackbody.h"
#include "shader/ies.h"
#include "shader/node_math.h"
#include "shader/procedural.h"
#include "shader/sky.h"
#include "shader/wavelength.h"

namespace whitted {
namespace {

using namespace node_math;

// ---------------------------------------------------------------------------------------
// Validation.

std::string_view op_name(uint32_t op) {
  return op < kOpTable.size() && op != 0 ? kOpTable[op].name : "?";
}

// Cycles' Ambient Occlusion node (svm_ao): the share of `samples` directions, drawn with
// density cos/pi about unit-made `n` (about -n: `inside`), along which nothing lies within
// `distance` of the hit (nothing of its own object: `local`). 1 where no ray is traced:
// no rays at the hit, no sample, or a distance that is not positive (NaN too).
float ambient_occlusion(const ProgramHit& hit, uint32_t mode, float distance, Vec3 n) {
  const auto samples = static_cast<int>(mode_field::kAoSamples.in(mode));
  if (hit.rays == nullptr || samples < 1 || !(distance > 0.0f)) return 1.0f;
  const float length = glm::length(n);
  n = length > 0.0f && std::isfinite(length) ? n / length : hit.normal;
  if (mode_field::kAoInside.on(mode)) n = -n;
  // A right-handed frame about n (Duff et al. 2017, "Building an Orthonormal Basis,
  // Revisited").
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  const Vec3 t(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const Vec3 bitangent(b, sign + n.y * n.y * a, -n.y);
  const bool local = mode_field::kAoOnlyLocal.on(mode);
  int open = 0;
  for (int k = 0; k < samples; ++k) {
    // Malley's method: a point of the unit disc (equal areas), lifted to the hemisphere.
    const glm::vec2 u = hit.rays->point(k, samples);
    float r = 0.0f, phi = 0.0f;
    concentric_disc(2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f, &r, &phi);
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    const float z = std::sqrt(std::fmax(1.0f - x * x - y * y, 0.0f));
    const Vec3 direction = glm::normalize(x * t + y * bitangent + z * n);
    if (!hit.rays->occluded(direction, distance, local)) ++open;
  }
  return static_cast<float>(open) / static_cast<float>(samples);
}

// The planar cubic falloff Cycles' Bevel node weighs nearby points by (svm_bevel): the
// density 10 (R - r)^3 / (pi R^5) of the distance r within radius R, 0 beyond.
float bevel_falloff(float radius, float r) {
  if (r >= radius) return 0.0f;
  const float f = radius - r;
  return 10.0f * f * f * f / ((radius * radius) * (radius * radius) * radius * kPi);
}

// The distance within `radius` of cumulative share `xi` under that falloff in the plane:
// the root of 10x^2 - 20x^3 + 15x^4 - 4x^5 = xi in [0, 1] (Newton's method from 0.25, as
// Cycles), times the radius.
float bevel_radius(float radius, float xi) {
  float x = 0.25f;
  for (int i = 0; i < 10; ++i) {
    const float x2 = x * x, x3 = x2 * x, nx = 1.0f - x;
    const float f = 10.0f * x2 - 20.0f * x3 + 15.0f * x2 * x2 - 4.0f * x2 * x3 - xi;
    const float slope = 20.0f * (x * nx) * (nx * nx);
    if (std::fabs(f) < 1e-6f || slope == 0.0f) break;
    x = std::clamp(x - f / slope, 0.0f, 1.0f);
  }
  return x * radius;
}

// Cycles' Bevel node (svm_bevel): the normals of the hit's own object near `p` averaged
// by the falloff of their distance within `radius`. Each of `samples` probes picks an
// axis of the frame about the true normal `ng` (itself with probability 1/2, each
// tangent 1/4), a point of the disc across it by the falloff, and a segment along the
// axis through that point; every point where the segment meets the object weighs its
// shading normal by the falloff at its real distance over the disc's density there,
// and by the power heuristic among the three axes. Cycles evaluates a random 4 of the
// points a segment meets (weighted by their count over 4): all of them here, the same
// mean. The shading normal where nothing was met, the radius is not positive and
// finite, or there are no samples or no rays.
Vec3 bevel(const ProgramHit& hit, uint32_t mode, float radius, const Vec3& p, const Vec3& ng) {
  const auto samples = static_cast<int>(mode_field::kBevelSamples.in(mode));
  if (hit.rays == nullptr || samples < 1 || !(radius > 0.0f) || !std::isfinite(radius)) {
    return hit.normal;
  }
  const float sign = std::copysign(1.0f, ng.z);
  const float a = -1.0f / (sign + ng.z);
  const float b = ng.x * ng.y * a;
  const Vec3 frame[3] = {ng, Vec3(1.0f + sign * ng.x * ng.x * a, sign * b, -sign * ng.x),
                         Vec3(b, sign + ng.y * ng.y * a, -ng.y)};
  // The chance of each axis: the normal's, and each tangent's.
  constexpr float kPick[3] = {0.5f, 0.25f, 0.25f};
  Vec3 sum(0.0f);
  HitRays::Surface found[HitRays::kMaxSurfaces];
  for (int k = 0; k < samples; ++k) {
    glm::vec2 u = hit.rays->point(k, samples);
    // The axis: the normal below 1/2, the first tangent below 3/4, else the second; the
    // choice's share of [0, 1) stretched back over it.
    const int axis = u.x < 0.5f ? 0 : u.x < 0.75f ? 1 : 2;
    u.x = axis == 0 ? 2.0f * u.x : 4.0f * (u.x - (axis == 1 ? 0.5f : 0.75f));
    const Vec3& n = frame[axis];
    const Vec3& t = frame[(axis + 1) % 3];
    const Vec3& s = frame[(axis + 2) % 3];
    const float disc_r = bevel_radius(radius, u.y);
    const float height = std::sqrt(std::fmax(radius * radius - disc_r * disc_r, 0.0f));
    const float disc_density = bevel_falloff(radius, disc_r);
    if (!(disc_density > 0.0f)) continue;
    const float phi = 2.0f * kPi * u.x;
    const Vec3 origin = p + height * n + disc_r * (std::cos(phi) * t + std::sin(phi) * s);
    const int count = hit.rays->surfaces(origin, -n, 2.0f * height, found);
    for (int i = 0; i < count; ++i) {
      // The axes' densities of this point (each axis's chance times the cosine of the
      // surface to it), the chosen one's in the numerator of the power heuristic (its
      // square over the sum of squares, over its own density).
      float densities[3];
      for (int j = 0; j < 3; ++j) {
        densities[j] = kPick[j] * std::fabs(glm::dot(frame[j], found[i].geometric_normal));
      }
      const float chosen = densities[axis];
      const float squares =
          densities[0] * densities[0] + densities[1] * densities[1] + densities[2] * densities[2];
      if (!(squares > 0.0f)) continue;
      const float falloff = bevel_falloff(radius, glm::length(found[i].position - p));
      sum += (chosen / squares) * (falloff / disc_density) * found[i].normal;
    }
  }
  const float length = glm::length(sum);
  if (!(length > 0.0f) || !std::isfinite(length)) return hit.normal;
  return hit.backfacing ? -sum / length : sum / length;
}

bool public_input(uint32_t mode) {
  if ((mode & kInputBumpX) != 0 && (mode & kInputBumpY) == 0) mode &= ~kInputBumpX;
  if ((mode & kInputBumpY) != 0 && (mode & kInputBumpX) == 0) mode &= ~kInputBumpY;
  return mode < kInputRadialTangent + 3 ||
         (mode >= kInputIsCameraRay && mode < kInputObjectAttribute + kObjectAttributes) ||
         (mode >= kInputObjectLocation && mode < kInputTriangleVertex + 3) ||
         (mode >= kInputUvSet && mode < kInputPublicEnd);
}

}  // namespace

Program::Program(const uint32_t* code, size_t rows, const float* registers, size_t register_count,
                 std::vector<float> constants, std::vector<std::string> textures)
    : constants_(std::move(constants)),
      textures_(std::move(textures)),
      image_slots_(textures_.size(), false) {
  if (register_count == 0 || register_count > kMaxRegisters) {
    throw std::invalid_argument("a program needs 1 to " + std::to_string(kMaxRegisters) +
                                " registers, not " + std::to_string(register_count));
  }
  for (size_t i = 0; i < 4 * register_count; ++i) {
    if (!std::isfinite(registers[i])) {
      throw std::invalid_argument("register " + std::to_string(i / 4) + " is NaN or infinite");
    }
  }
  for (size_t i = 0; i < constants_.size(); ++i) {
    if (!std::isfinite(constants_[i])) {
      throw std::invalid_argument("constant " + std::to_string(i) + " is NaN or infinite");
    }
  }
  initial_.reserve(register_count);
  for (size_t i = 0; i < register_count; ++i) {
    initial_.emplace_back(registers[4 * i], registers[4 * i + 1], registers[4 * i + 2],
                          registers[4 * i + 3]);
  }
  const auto zero = static_cast<uint32_t>(register_count);  // the register past the file
  steps_.reserve(rows);
  for (size_t row = 0; row < rows; ++row) {
    const uint32_t* c = &code[kColumns * row];
    const uint32_t op = c[0];
    const uint32_t mode = c[1];
    const auto fail = [&](const std::string& what) {
      throw std::invalid_argument("instruction " + std::to_string(row) + " (" +
                                  std::string(op_name(op)) + "): " + what);
    };
    if (op < static_cast<uint32_t>(Op::kInput) || op >= kOpTable.size()) {
      throw std::invalid_argument("instruction " + std::to_string(row) + ": unknown op " +
                                  std::to_string(op));
    }
    if (c[2] >= register_count) fail("out register " + std::to_string(c[2]) + " out of range");
    // Register operands: in range, or unused (then they read the zero register).
    const auto reg = [&](int column) {
      const uint32_t r = c[column];
      if (r == kUnused) return zero;
      if (r >= register_count) {
        fail(std::string("operand ") + "abcde"[column - 3] + " register " + std::to_string(r) +
             " out of range");
      }
      return r;
    };
    const auto texture_slot = [&]() {
      if (c[7] >= textures_.size()) {
        fail("texture slot " + std::to_string(c[7]) + " out of range (" +
             std::to_string(textures_.size()) + " textures)");
      }
      image_slots_[c[7]] = true;
      return c[7];
    };
    Step s{static_cast<Op>(op), mode, c[2], zero, zero, zero, zero, zero, false};
    // Every op's mode but INPUT's is fields (kOpModes), each holding one of its values,
    // or 0 for an op without a mode.
    if (s.op != Op::kInput && !valid_mode(mode_fields(s.op), mode))
      fail("mode " + std::to_string(mode) + " is not one of its modes");
    switch (s.op) {
      case Op::kInput:
        if (!public_input(mode)) fail("mode " + std::to_string(mode) + " is not an input");
        s.e = input_slot(mode);
        bumps_ |= (mode & (kInputBumpX | kInputBumpY)) != 0;
        break;
      case Op::kMath:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kVectorMath:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMix:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMixValue:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kCombine:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kSeparate:
        s.a = reg(3);
        break;
      case Op::kSwizzle:
        s.a = reg(3);
        break;
      case Op::kHueSat:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6), s.e = reg(7);
        break;
      case Op::kGamma:
      case Op::kInvert:
      case Op::kFresnel:
        s.a = reg(3), s.b = reg(4);
        s.b_given = c[4] != kUnused;
        break;
      case Op::kBrightContrast:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kClamp:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMapRange:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kColorRamp: {
        s.a = reg(3);
        const uint32_t e = c[7];
        if (e >= constants_.size()) fail("constants offset out of range");
        const float n = constants_[e];
        if (!(n >= 1.0f && n <= static_cast<float>(constants_.size())) || n != std::floor(n) ||
            e + 1 + kRampStop * static_cast<size_t>(n) > constants_.size()) {
          fail("constants at " + std::to_string(e) + " do not hold a ramp of n >= 1 stops");
        }
        for (size_t i = 1; i < static_cast<size_t>(n); ++i) {
          if (constants_[e + 1 + kRampStop * i] < constants_[e + 1 + kRampStop * (i - 1)]) {
            fail("ramp stops are not sorted by position");
          }
        }
        s.e = e;
        break;
      }
      case Op::kSky: {
        s.a = reg(3);
        const auto model = static_cast<sky::Model>(mode_field::kSkyModel.in(mode));
        if (c[7] >= constants_.size() ||
            sky::table_size(model, &constants_[c[7]], constants_.size() - c[7]) == 0) {
          fail("constants at " + std::to_string(c[7]) + " do not hold a sky table");
        }
        s.e = c[7];
        break;
      }
      case Op::kIes:
        s.a = reg(3), s.b = reg(4);
        if (c[7] >= constants_.size() ||
            ies::table_size(&constants_[c[7]], constants_.size() - c[7]) == 0) {
          fail("constants at " + std::to_string(c[7]) + " do not hold an IES profile");
        }
        s.e = c[7];
        break;
      case Op::kCurve:
        s.a = reg(3), s.b = reg(4);
        if (c[7] >= constants_.size() || c[7] + 4 * size_t{kCurveTable} > constants_.size()) {
          fail("constants at " + std::to_string(c[7]) + " do not hold a 4 x 256 curve table");
        }
        s.e = c[7];
        break;
      case Op::kMapping:
      case Op::kChecker:
      case Op::kPack:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6);
        break;
      case Op::kImage:
        s.a = reg(3), s.b = reg(4), s.e = texture_slot();
        break;
      case Op::kEnvironment:
        s.a = reg(3), s.e = texture_slot();
        break;
      case Op::kGradient:
        s.a = reg(3);
        break;
      case Op::kLayerWeight:
        s.a = reg(3), s.b = reg(4);
        s.b_given = c[4] != kUnused;
        break;
      case Op::kNormalMap:
        s.a = reg(3), s.b = reg(4);
        if (mode_field::kNormalMapSpace.in(mode) == 0) {
          if (c[7] >= kUvSets) fail("tangent set out of range");
          s.e = input_slot(kInputTangent + c[7]);
          s.d = input_slot(kInputObjectNormal);
        }
        break;
      case Op::kUvTangent:
        if (c[7] >= kUvSets) fail("tangent set out of range");
        s.e = input_slot(kInputTangent + c[7]);
        break;
      case Op::kRgbToBw:
      case Op::kBlackbody:
      case Op::kWavelength:
        s.a = reg(3);
        break;
      case Op::kWhiteNoise:
        s.a = reg(3), s.b = reg(4);
        break;
      case Op::kVectorRotate:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6);
        break;
      case Op::kLightFalloff:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kWireframe:
      case Op::kGabor:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6), s.e = reg(7);
        break;
      case Op::kNoise:
      case Op::kVoronoi:
      case Op::kWave:
      case Op::kMagic:
      case Op::kBrick:
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kBump:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6), s.e = reg(7);
        s.b_given = c[4] != kUnused;
        bumps_ = true;
        break;
      case Op::kAmbientOcclusion:
        s.a = reg(3), s.b = reg(4);
        s.b_given = c[4] != kUnused;
        traces_ = true;
        break;
      case Op::kBevel:
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6);
        s.b_given = c[6] != kUnused;  // the Normal input (d)
        traces_ = true;
        break;
    }
    steps_.push_back(s);
  }
}

uint32_t Program::input_slot(uint32_t mode) {
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (inputs_[i] == mode) return static_cast<uint32_t>(i);
  }
  if (inputs_.size() == kMaxInputs) {
    throw std::invalid_argument("a program reads at most " + std::to_string(kMaxInputs) +
                                " distinct inputs");
  }
  inputs_.push_back(mode);
  return static_cast<uint32_t>(inputs_.size() - 1);
}

void Program::run(const ProgramHit& hit, vec4* r) const {
  std::copy(initial_.begin(), initial_.end(), r);
  r[initial_.size()] = vec4(0.0f);
  for (const Step& s : steps_) {
    // Operands are read before `out` is written: an instruction may overwrite its input.
    const vec4 a = r[s.a];
    const vec4 b = r[s.b];
    const vec4 c = r[s.c];
    vec4 out(0.0f);
    switch (s.op) {
      case Op::kInput:
        out = hit.inputs[s.e];
        break;
      case Op::kMath: {
        const float v =
            math(static_cast<MathOp>(mode_field::kMathOperation.in(s.mode)), a.x, b.x, c.x);
        out = scalar(mode_field::kClamp.on(s.mode) ? saturate(v) : v);
        break;
      }
      case Op::kVectorMath: {
        // SCALE reads its factor from b, REFRACT its index from c.
        const auto operation =
            static_cast<VectorMathOp>(mode_field::kVectorMathOperation.in(s.mode));
        out = vector_math(operation, Vec3(a), Vec3(b), Vec3(c),
                          operation == VectorMathOp::kScale ? b.x : c.x);
        break;
      }
      case Op::kMix: {
        const Vec3 m =
            mix(static_cast<MixBlend>(mode_field::kMixBlend.in(s.mode)), a.x, Vec3(b), Vec3(c));
        out = vec4(mode_field::kClamp.on(s.mode) ? saturate(m) : m, b.w);
        break;
      }
      case Op::kMixValue: {
        const uint32_t factor_mode = mode_field::kMixValue.in(s.mode);  // kMixValueNames
        if (factor_mode == 0) {
          out = scalar(b.x * (1.0f - a.x) + c.x * a.x);
        } else {
          const Vec3 t = factor_mode == 1 ? Vec3(a.x) : Vec3(a);
          out = vector(Vec3(b) * (Vec3(1.0f) - t) + Vec3(c) * t);
        }
        break;
      }
      case Op::kSeparate: {
        const uint32_t color_mode = mode_field::kColorMode.in(s.mode);
        out = vec4(color_mode == 0   ? Vec3(a)
                   : color_mode == 1 ? rgb_to_hsv(Vec3(a))
                                     : rgb_to_hsl(Vec3(a)),
                   a.w);
        break;
      }
      case Op::kSwizzle:
        out = scalar(a[static_cast<int>(mode_field::kSwizzle.in(s.mode))]);
        break;
      case Op::kCombine: {
        const Vec3 v(a.x, b.x, c.x);
        const uint32_t color_mode = mode_field::kColorMode.in(s.mode);
        out = vec4(color_mode == 0 ? v : color_mode == 1 ? hsv_to_rgb(v) : hsl_to_rgb(v), 1.0f);
        break;
      }
      case Op::kHueSat: {
        // Hue shifted (0.5 is none), saturation and value scaled, then mixed by factor.
        const vec4 in = r[s.e];
        Vec3 hsv = rgb_to_hsv(Vec3(in));
        hsv.x = fract(hsv.x + a.x + 0.5f);
        hsv.y = saturate(hsv.y * b.x);
        hsv.z *= c.x;
        const float fac = r[s.d].x;
        const Vec3 mixed = fac * hsv_to_rgb(hsv) + (1.0f - fac) * Vec3(in);
        out = vec4(glm::max(mixed, Vec3(0.0f)), in.w);  // over-saturation can go negative
        break;
      }
      case Op::kGamma:
        if (b.x == 0.0f) {
          out = vec4(Vec3(1.0f), a.w);
        } else {
          out = vec4(each(Vec3(a), [&](float x) { return x > 0.0f ? std::pow(x, b.x) : x; }), a.w);
        }
        break;
      case Op::kBrightContrast: {
        const float mul = 1.0f + c.x;
        const float add = b.x - c.x * 0.5f;
        out = vec4(glm::max(mul * Vec3(a) + add, Vec3(0.0f)), a.w);
        break;
      }
      case Op::kInvert:
        out = vec4(a.x * (Vec3(1.0f) - Vec3(b)) + (1.0f - a.x) * Vec3(b), b.w);
        break;
      case Op::kClamp:
        out = scalar(mode_field::kClampType.in(s.mode) == 1 && b.x > c.x ? clamp_to(a.x, c.x, b.x)
                                                                         : clamp_to(a.x, b.x, c.x));
        break;
      case Op::kMapRange: {
        const uint32_t type = mode_field::kMapRange.in(s.mode);
        const float from_min = b.x, from_max = b.y, to_min = b.z, to_max = b.w;
        if (from_max == from_min) {
          out = scalar(0.0f);
          break;
        }
        float f = (a.x - from_min) / (from_max - from_min);
        if (type == 1) {
          f = c.x > 0.0f ? std::floor(f * (c.x + 1.0f)) / c.x : 0.0f;
        } else if (type == 2) {
          f = from_min > from_max ? 1.0f - smoothstep(from_max, from_min, a.x)
                                  : smoothstep(from_min, from_max, a.x);
        } else if (type == 3) {
          f = from_min > from_max ? 1.0f - smootherstep(from_max, from_min, a.x)
                                  : smootherstep(from_min, from_max, a.x);
        }
        float v = to_min + f * (to_max - to_min);
        // Blender clamps the linear and stepped results only; the smooth ones stay inside.
        if (mode_field::kClamp.on(s.mode) && type <= 1) {
          v = to_min > to_max ? clamp_to(v, to_max, to_min) : clamp_to(v, to_min, to_max);
        }
        out = scalar(v);
        break;
      }
      case Op::kColorRamp:
        // Cycles samples the ramp over [0, 1] only.
        out = color_ramp(mode_field::kRamp.in(s.mode), &constants_[s.e + 1],
                         static_cast<size_t>(constants_[s.e]), saturate(a.x));
        break;
      case Op::kCurve: {
        const float* table = &constants_[s.e];
        const bool extrapolate = mode_field::kCurveExtrapolate.on(s.mode);
        const auto row = [&](uint32_t i, float x) {
          return curve(table + i * kCurveTable, x, extrapolate);
        };
        const float fac = a.x;
        const uint32_t kind = mode_field::kCurveKind.in(s.mode);  // kCurveKindNames
        if (kind == 1) {
          out = scalar((1.0f - fac) * b.x + fac * row(0, b.x));
          break;
        }
        // RGB curves: the combined curve first, then each channel's; vector curves: one
        // curve per axis.
        const Vec3 mapped =
            kind == 0 ? Vec3(row(1, row(0, b.x)), row(2, row(0, b.y)), row(3, row(0, b.z)))
                      : Vec3(row(0, b.x), row(1, b.y), row(2, b.z));
        out = vec4((1.0f - fac) * Vec3(b) + fac * mapped, kind == 0 ? b.w : 0.0f);
        break;
      }
      case Op::kSky:
        out = vec4(sky::radiance(static_cast<sky::Model>(mode_field::kSkyModel.in(s.mode)),
                                 &constants_[s.e], Vec3(a)),
                   1.0f);
        break;
      case Op::kMapping:
        out = vector(
            mapping(mode_field::kMapping.in(s.mode), Vec3(a), Vec3(b), Vec3(c), Vec3(r[s.d])));
        break;
      case Op::kImage:
        out = image(mode_field::kImageProjection.in(s.mode), *hit.images[s.e], Vec3(a), b.x, hit);
        break;
      case Op::kEnvironment:  // a UDIM image's first tile, as Cycles
        out = sample_first_tile(
            *hit.images[s.e],
            environment_uv(mode_field::kEnvironmentProjection.in(s.mode), Vec3(a)));
        break;
      case Op::kChecker: {
        const bool first = checker_first(Vec3(a) * r[s.d].x);
        out = vec4(first ? Vec3(b) : Vec3(c), first ? 1.0f : 0.0f);
        break;
      }
      case Op::kGradient:
        out = scalar(saturate(gradient(mode_field::kGradient.in(s.mode), Vec3(a))));
        break;
      case Op::kNoise:
        out = procedural::noise_op(s.mode, a, b, c);
        break;
      case Op::kVoronoi:
        out = procedural::voronoi_op(s.mode, a, b, c);
        break;
      case Op::kWave:
        out = procedural::wave_op(s.mode, a, b, c);
        break;
      case Op::kMagic:
        out = procedural::magic_op(s.mode, a, b, c);
        break;
      case Op::kBrick:
        out = procedural::brick_op(s.mode, a, b, c);
        break;
      case Op::kFresnel: {
        const Vec3 n = s.b_given ? Vec3(b) : hit.normal;
        const float eta = std::fmax(a.x, 1e-5f);
        out = scalar(
            fresnel_dielectric(glm::dot(hit.incoming, n), hit.backfacing ? 1.0f / eta : eta));
        break;
      }
      case Op::kLayerWeight:
        out = scalar(layer_weight(mode_field::kLayerWeight.in(s.mode), a.x,
                                  s.b_given ? Vec3(b) : hit.normal, hit));
        break;
      case Op::kNormalMap: {
        const uint32_t space = mode_field::kNormalMapSpace.in(s.mode);
        const bool tangent = space == 0;
        out = vector(normal_map(space, a.x, Vec3(b), tangent ? hit.inputs[s.e] : vec4(0.0f),
                                tangent ? Vec3(hit.inputs[s.d]) : Vec3(0.0f), hit));
        break;
      }
      case Op::kUvTangent:
        out = vector(tangent_across(hit.normal_to_world * Vec3(hit.inputs[s.e]), hit.normal));
        break;
      case Op::kPack:
        out = vec4(a.x, b.x, c.x, r[s.d].x);
        break;
      case Op::kRgbToBw:
        out = scalar(0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z);
        break;
      case Op::kBlackbody:
        out = vec4(blackbody_rgb(a.x), 1.0f);
        break;
      case Op::kWhiteNoise:
        out = procedural::white_noise_op(s.mode, a, b);
        break;
      case Op::kWavelength:
        out = vec4(wavelength_rgb(a.x), 1.0f);
        break;
      case Op::kVectorRotate:
        out = vector(vector_rotate(s.mode, Vec3(a), Vec3(b), Vec3(c), r[s.d].x));
        break;
      case Op::kLightFalloff:
        out = scalar(light_falloff(s.mode, a.x, b.x, c.x));
        break;
      case Op::kWireframe:
        out = scalar(wireframe(a.x, Vec3(b), Vec3(c), Vec3(r[s.d]), Vec3(r[s.e])));
        break;
      case Op::kGabor:
        out = procedural::gabor_op(s.mode, a, b, c, r[s.d], r[s.e]);
        break;
      case Op::kIes:
        out = scalar(b.x *
                     ies::lookup(&constants_[s.e], Vec3(a), mode_field::kIesEdges.in(s.mode) == 0));
        break;
      case Op::kBump:
        out = vector(bump(hit, a.x, a.y, mode_field::kBumpInvert.on(s.mode),
                          s.b_given ? Vec3(b) : hit.normal, c.x, r[s.d].x, r[s.e].x));
        break;
      case Op::kAmbientOcclusion:
        out = scalar(ambient_occlusion(hit, s.mode, a.x, s.b_given ? Vec3(b) : hit.normal));
        break;
      case Op::kBevel: {
        const Vec3 bevelled = bevel(hit, s.mode, a.x, Vec3(b), Vec3(c));
        // A linked Normal keeps its own bend: the bevel's change of the shading normal
        // added to it (Cycles' svm_node_bevel).
        out = vector(s.b_given ? glm::normalize(Vec3(r[s.d]) + (bevelled - hit.normal)) : bevelled);
        break;
      }
      default:  // rejected at construction
        break;
    }
    r[s.out] = out;
  }
}

std::optional<vec4> Program::fold(uint32_t op, uint32_t mode,
                                  std::span<const std::optional<vec4>> operands,
                                  std::vector<float> constants) {
  if (op == 0 || op >= kOpTable.size()) {
    throw std::invalid_argument("unknown op " + std::to_string(op));
  }
  const OpInfo& info = kOpTable[op];
  if (info.reads_hit) return std::nullopt;
  if (operands.size() > info.operands) {
    throw std::invalid_argument(std::string(info.name) + " takes " + std::to_string(info.operands) +
                                " operands, not " + std::to_string(operands.size()));
  }
  // One instruction: the operands in registers 0.., the result in the register after.
  std::vector<float> registers;
  uint32_t row[kColumns] = {op, mode, 0, kUnused, kUnused, kUnused, kUnused, kUnused};
  for (size_t i = 0; i < operands.size(); ++i) {
    if (!operands[i]) continue;
    row[3 + i] = static_cast<uint32_t>(registers.size() / 4);
    registers.insert(registers.end(),
                     {operands[i]->x, operands[i]->y, operands[i]->z, operands[i]->w});
  }
  const auto out = static_cast<uint32_t>(registers.size() / 4);
  registers.insert(registers.end(), 4, 0.0f);
  row[2] = out;
  if (reads_table(static_cast<Op>(op))) {
    row[7] = 0;  // the table is the whole of `constants`
  }
  const Program program(row, 1, registers.data(), out + 1, std::move(constants), {});
  std::vector<vec4> file(out + 2);  // and the zero register run() puts past the file
  program.run(ProgramHit{}, file.data());
  return file[out];
}

}  // namespace whitted
