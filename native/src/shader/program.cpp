#include "shader/program.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "shader/procedural.h"

namespace whitted {
namespace {

using glm::vec4;

constexpr uint32_t kClampBit = 1u << 8;  // MATH, MIX, MAP_RANGE: clamp; CURVE: extrapolate
constexpr uint32_t kCurveTable = 256;    // entries per curve of a CURVE table
constexpr size_t kRampStop = 5;          // floats per colour ramp stop: pos, r, g, b, a

// ---------------------------------------------------------------------------------------
// Blender's scalar helpers (Cycles util/math.h): each defined where C's would be
// undefined or NaN, so a node graph never makes a NaN Blender would not.

float saturate(float x) {
  return std::fmin(std::fmax(x, 0.0f), 1.0f);  // NaN becomes 0, as in Cycles
}
// Cycles' clamp: the upper bound wins when the bounds cross.
float clamp_to(float x, float lo, float hi) {
  return std::fmin(std::fmax(x, lo), hi);
}
float safe_divide(float a, float b) {
  return b != 0.0f ? a / b : 0.0f;
}
float safe_pow(float a, float b) {
  if (a < 0.0f && std::trunc(b) != b) return 0.0f;  // a negative base needs an integer power
  return std::pow(a, b);
}
float safe_log(float a, float b) {
  if (a <= 0.0f || b <= 0.0f) return 0.0f;
  return safe_divide(std::log(a), std::log(b));
}
float safe_modulo(float a, float b) {
  return b != 0.0f ? std::fmod(a, b) : 0.0f;
}
float floored_modulo(float a, float b) {
  return b != 0.0f ? a - std::floor(a / b) * b : 0.0f;
}
float fract(float a) {
  return a - std::floor(a);
}
// Blender's wrap(value, max, min): value moved by whole ranges into [min, max).
float wrap(float value, float max, float min) {
  const float range = max - min;
  return range != 0.0f ? value - range * std::floor((value - min) / range) : min;
}
float pingpong(float a, float b) {
  return b != 0.0f ? std::fabs(fract((a - b) / (b * 2.0f)) * b * 2.0f - b) : 0.0f;
}
float smooth_min(float a, float b, float k) {
  if (k == 0.0f) return std::fmin(a, b);
  const float h = std::fmax(k - std::fabs(a - b), 0.0f) / k;
  return std::fmin(a, b) - h * h * h * k * (1.0f / 6.0f);
}
float sign(float a) {
  return a == 0.0f ? 0.0f : (a < 0.0f ? -1.0f : 1.0f);
}
float safe_asin(float a) {
  return std::asin(clamp_to(a, -1.0f, 1.0f));
}
float safe_acos(float a) {
  return std::acos(clamp_to(a, -1.0f, 1.0f));
}
float atan2_or_zero(float y, float x) {
  return x == 0.0f && y == 0.0f ? 0.0f : std::atan2(y, x);
}
float smoothstep(float edge0, float edge1, float x) {
  if (x < edge0) return 0.0f;
  if (x >= edge1) return 1.0f;
  const float t = (x - edge0) / (edge1 - edge0);
  return (3.0f - 2.0f * t) * (t * t);
}
float smootherstep(float edge0, float edge1, float x) {
  x = saturate(safe_divide(x - edge0, edge1 - edge0));
  return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}

Vec3 safe_normalize(const Vec3& v) {
  const float length = glm::length(v);
  return length != 0.0f ? v * (1.0f / length) : v;
}
Vec3 safe_divide(const Vec3& a, const Vec3& b) {
  return {safe_divide(a.x, b.x), safe_divide(a.y, b.y), safe_divide(a.z, b.z)};
}
Vec3 saturate(const Vec3& c) {
  return {saturate(c.x), saturate(c.y), saturate(c.z)};
}
// Cycles' interp: a + t (b - a).
Vec3 interp(const Vec3& a, const Vec3& b, float t) {
  return a + t * (b - a);
}
template <typename F>
Vec3 each(const Vec3& a, const Vec3& b, F f) {
  return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)};
}
template <typename F>
Vec3 each(const Vec3& a, F f) {
  return {f(a.x), f(a.y), f(a.z)};
}

vec4 scalar(float v) {
  return vec4(v);
}
vec4 vector(const Vec3& v) {
  return vec4(v, 0.0f);
}

// ---------------------------------------------------------------------------------------
// Colour spaces (Cycles util/color.h).

Vec3 rgb_to_hsv(const Vec3& rgb) {
  const float cmax = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
  const float cmin = std::fmin(rgb.x, std::fmin(rgb.y, rgb.z));
  const float delta = cmax - cmin;
  const float s = cmax != 0.0f ? delta / cmax : 0.0f;
  float h = 0.0f;
  if (s != 0.0f) {
    const Vec3 c = (Vec3(cmax) - rgb) / delta;
    if (rgb.x == cmax) {
      h = c.z - c.y;
    } else if (rgb.y == cmax) {
      h = 2.0f + c.x - c.z;
    } else {
      h = 4.0f + c.y - c.x;
    }
    h /= 6.0f;
    if (h < 0.0f) h += 1.0f;
  }
  return {h, s, cmax};
}

Vec3 hsv_to_rgb(const Vec3& hsv) {
  const float s = hsv.y;
  const float v = hsv.z;
  if (s == 0.0f) return Vec3(v);
  const float h = (hsv.x == 1.0f ? 0.0f : hsv.x) * 6.0f;
  const float i = std::floor(h);
  const float f = h - i;
  const float p = v * (1.0f - s);
  const float q = v * (1.0f - s * f);
  const float t = v * (1.0f - s * (1.0f - f));
  if (i == 0.0f) return {v, t, p};
  if (i == 1.0f) return {q, v, p};
  if (i == 2.0f) return {p, v, t};
  if (i == 3.0f) return {p, q, v};
  if (i == 4.0f) return {t, p, v};
  return {v, p, q};
}

Vec3 rgb_to_hsl(const Vec3& rgb) {
  const float cmax = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
  const float cmin = std::fmin(rgb.x, std::fmin(rgb.y, rgb.z));
  const float l = std::fmin(1.0f, (cmax + cmin) / 2.0f);
  if (cmax == cmin) return {0.0f, 0.0f, l};  // grey
  const float delta = cmax - cmin;
  const float s = l > 0.5f ? delta / (2.0f - cmax - cmin) : delta / (cmax + cmin);
  float h = 0.0f;
  if (cmax == rgb.x) {
    h = (rgb.y - rgb.z) / delta + (rgb.y < rgb.z ? 6.0f : 0.0f);
  } else if (cmax == rgb.y) {
    h = (rgb.z - rgb.x) / delta + 2.0f;
  } else {
    h = (rgb.x - rgb.y) / delta + 4.0f;
  }
  return {h / 6.0f, s, l};
}

Vec3 hsl_to_rgb(const Vec3& hsl) {
  const float h = hsl.x;
  const float nr = saturate(std::fabs(h * 6.0f - 3.0f) - 1.0f);
  const float ng = saturate(2.0f - std::fabs(h * 6.0f - 2.0f));
  const float nb = saturate(2.0f - std::fabs(h * 6.0f - 4.0f));
  const float chroma = (1.0f - std::fabs(2.0f * hsl.z - 1.0f)) * hsl.y;
  return Vec3(nr - 0.5f, ng - 0.5f, nb - 0.5f) * chroma + hsl.z;
}

// ---------------------------------------------------------------------------------------
// Nodes.

float math(MathOp op, float a, float b, float c) {
  switch (op) {
    case MathOp::kAdd:
      return a + b;
    case MathOp::kSubtract:
      return a - b;
    case MathOp::kMultiply:
      return a * b;
    case MathOp::kDivide:
      return safe_divide(a, b);
    case MathOp::kMultiplyAdd:
      return a * b + c;
    case MathOp::kPower:
      return safe_pow(a, b);
    case MathOp::kLogarithm:
      return safe_log(a, b);
    case MathOp::kSqrt:
      return std::sqrt(std::fmax(a, 0.0f));
    case MathOp::kInverseSqrt:
      return a > 0.0f ? 1.0f / std::sqrt(a) : 0.0f;
    case MathOp::kAbsolute:
      return std::fabs(a);
    case MathOp::kExponent:
      return std::exp(a);
    case MathOp::kMinimum:
      return std::fmin(a, b);
    case MathOp::kMaximum:
      return std::fmax(a, b);
    case MathOp::kLessThan:
      return a < b ? 1.0f : 0.0f;
    case MathOp::kGreaterThan:
      return a > b ? 1.0f : 0.0f;
    case MathOp::kSign:
      return sign(a);
    case MathOp::kCompare:
      return (a == b || std::fabs(a - b) <= std::fmax(c, FLT_EPSILON)) ? 1.0f : 0.0f;
    case MathOp::kSmoothMin:
      return smooth_min(a, b, c);
    case MathOp::kSmoothMax:
      return -smooth_min(-a, -b, c);
    case MathOp::kRound:
      return std::floor(a + 0.5f);
    case MathOp::kFloor:
      return std::floor(a);
    case MathOp::kCeil:
      return std::ceil(a);
    case MathOp::kTrunc:
      return a >= 0.0f ? std::floor(a) : std::ceil(a);
    case MathOp::kFract:
      return fract(a);
    case MathOp::kModulo:
      return safe_modulo(a, b);
    case MathOp::kFlooredModulo:
      return floored_modulo(a, b);
    case MathOp::kWrap:
      return wrap(a, b, c);
    case MathOp::kSnap:
      return std::floor(safe_divide(a, b)) * b;
    case MathOp::kPingpong:
      return pingpong(a, b);
    case MathOp::kSine:
      return std::sin(a);
    case MathOp::kCosine:
      return std::cos(a);
    case MathOp::kTangent:
      return std::tan(a);
    case MathOp::kArcsine:
      return safe_asin(a);
    case MathOp::kArccosine:
      return safe_acos(a);
    case MathOp::kArctangent:
      return std::atan(a);
    case MathOp::kArctan2:
      return atan2_or_zero(a, b);
    case MathOp::kSinh:
      return std::sinh(a);
    case MathOp::kCosh:
      return std::cosh(a);
    case MathOp::kTanh:
      return std::tanh(a);
    case MathOp::kRadians:
      return a * (kPi / 180.0f);
    case MathOp::kDegrees:
      return a * (180.0f / kPi);
  }
  return 0.0f;
}

vec4 vector_math(VectorMathOp op, const Vec3& a, const Vec3& b, const Vec3& c, float scale) {
  switch (op) {
    case VectorMathOp::kAdd:
      return vector(a + b);
    case VectorMathOp::kSubtract:
      return vector(a - b);
    case VectorMathOp::kMultiply:
      return vector(a * b);
    case VectorMathOp::kDivide:
      return vector(safe_divide(a, b));
    case VectorMathOp::kMultiplyAdd:
      return vector(a * b + c);
    case VectorMathOp::kCrossProduct:
      return vector(glm::cross(a, b));
    case VectorMathOp::kProject: {
      const float length2 = glm::dot(b, b);
      return vector(length2 != 0.0f ? (glm::dot(a, b) / length2) * b : Vec3(0.0f));
    }
    case VectorMathOp::kReflect: {
      const Vec3 n = safe_normalize(b);
      return vector(a - 2.0f * n * glm::dot(a, n));
    }
    case VectorMathOp::kRefract: {
      const Vec3 n = safe_normalize(b);
      const float eta = scale;
      const float cos_i = glm::dot(n, a);
      const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
      return vector(k < 0.0f ? Vec3(0.0f) : eta * a - (eta * cos_i + std::sqrt(k)) * n);
    }
    case VectorMathOp::kFaceforward:
      return vector(glm::dot(c, b) < 0.0f ? a : -a);
    case VectorMathOp::kDotProduct:
      return scalar(glm::dot(a, b));
    case VectorMathOp::kDistance:
      return scalar(glm::distance(a, b));
    case VectorMathOp::kLength:
      return scalar(glm::length(a));
    case VectorMathOp::kScale:
      return vector(a * scale);
    case VectorMathOp::kNormalize:
      return vector(safe_normalize(a));
    case VectorMathOp::kAbsolute:
      return vector(glm::abs(a));
    case VectorMathOp::kPower:
      return vector(each(a, b, safe_pow));
    case VectorMathOp::kSign:
      return vector(each(a, sign));
    case VectorMathOp::kMinimum:
      return vector(each(a, b, [](float x, float y) { return std::fmin(x, y); }));
    case VectorMathOp::kMaximum:
      return vector(each(a, b, [](float x, float y) { return std::fmax(x, y); }));
    case VectorMathOp::kFloor:
      return vector(glm::floor(a));
    case VectorMathOp::kCeil:
      return vector(glm::ceil(a));
    case VectorMathOp::kFraction:
      return vector(a - glm::floor(a));
    case VectorMathOp::kModulo:
      return vector(each(a, b, safe_modulo));
    case VectorMathOp::kWrap:
      return vector({wrap(a.x, b.x, c.x), wrap(a.y, b.y, c.y), wrap(a.z, b.z, c.z)});
    case VectorMathOp::kSnap:
      return vector(glm::floor(safe_divide(a, b)) * b);
    case VectorMathOp::kSine:
      return vector(each(a, [](float x) { return std::sin(x); }));
    case VectorMathOp::kCosine:
      return vector(each(a, [](float x) { return std::cos(x); }));
    case VectorMathOp::kTangent:
      return vector(each(a, [](float x) { return std::tan(x); }));
    case VectorMathOp::kRound:  // as the Math node's Round: halves away from -inf
      return vector(glm::floor(a + 0.5f));
  }
  return vec4(0.0f);
}

// The Mix node's blend modes (Cycles svm/color_util.h): c1 the base, c2 the blend colour.
Vec3 mix(MixBlend blend, float t, const Vec3& c1, const Vec3& c2) {
  const float tm = 1.0f - t;
  switch (blend) {
    case MixBlend::kMix:
      return interp(c1, c2, t);
    case MixBlend::kDarken:
      return interp(c1, glm::min(c1, c2), t);
    case MixBlend::kMultiply:
      return interp(c1, c1 * c2, t);
    case MixBlend::kBurn:
      return each(c1, c2, [&](float a, float b) {
        const float d = tm + t * b;
        if (d <= 0.0f) return 0.0f;
        return saturate(1.0f - (1.0f - a) / d);
      });
    case MixBlend::kLighten:
      return interp(c1, glm::max(c1, c2), t);
    case MixBlend::kScreen:
      return Vec3(1.0f) - (Vec3(tm) + t * (Vec3(1.0f) - c2)) * (Vec3(1.0f) - c1);
    case MixBlend::kDodge:
      return each(c1, c2, [&](float a, float b) {
        if (a == 0.0f) return a;
        const float d = 1.0f - t * b;
        if (d <= 0.0f) return 1.0f;
        return std::fmin(a / d, 1.0f);
      });
    case MixBlend::kAdd:
      return interp(c1, c1 + c2, t);
    case MixBlend::kOverlay:
      return each(c1, c2, [&](float a, float b) {
        return a < 0.5f ? a * (tm + 2.0f * t * b)
                        : 1.0f - (tm + 2.0f * t * (1.0f - b)) * (1.0f - a);
      });
    case MixBlend::kSoftLight: {
      const Vec3 one(1.0f);
      const Vec3 screen = one - (one - c2) * (one - c1);
      return tm * c1 + t * ((one - c1) * c2 * c1 + c1 * screen);
    }
    case MixBlend::kLinearLight:
      return c1 + t * (2.0f * c2 - Vec3(1.0f));
    case MixBlend::kDifference:
      return interp(c1, glm::abs(c1 - c2), t);
    case MixBlend::kExclusion:
      return glm::max(interp(c1, c1 + c2 - 2.0f * c1 * c2, t), Vec3(0.0f));
    case MixBlend::kSubtract:
      return interp(c1, c1 - c2, t);
    case MixBlend::kDivide:
      return each(c1, c2, [&](float a, float b) { return b != 0.0f ? tm * a + t * a / b : a; });
    case MixBlend::kHue: {
      const Vec3 hsv2 = rgb_to_hsv(c2);
      if (hsv2.y == 0.0f) return c1;
      Vec3 hsv = rgb_to_hsv(c1);
      hsv.x = hsv2.x;
      return interp(c1, hsv_to_rgb(hsv), t);
    }
    case MixBlend::kSaturation: {
      Vec3 hsv = rgb_to_hsv(c1);
      if (hsv.y == 0.0f) return c1;
      hsv.y = tm * hsv.y + t * rgb_to_hsv(c2).y;
      return hsv_to_rgb(hsv);
    }
    case MixBlend::kColor: {
      const Vec3 hsv2 = rgb_to_hsv(c2);
      if (hsv2.y == 0.0f) return c1;
      Vec3 hsv = rgb_to_hsv(c1);
      hsv.x = hsv2.x;
      hsv.y = hsv2.y;
      return interp(c1, hsv_to_rgb(hsv), t);
    }
    case MixBlend::kValue: {
      Vec3 hsv = rgb_to_hsv(c1);
      hsv.z = tm * hsv.z + t * rgb_to_hsv(c2).z;
      return hsv_to_rgb(hsv);
    }
  }
  return c1;
}

// Blender's colour ramp (BKE_colorband_evaluate) over stops sorted by position, `stops`
// floats of (pos, r, g, b, a) each. Modes: 0 constant, 1 linear, 2 ease, 3 cardinal,
// 4 b-spline.
vec4 color_ramp(uint32_t mode, const float* stops, size_t n, float in) {
  const auto pos = [&](size_t i) { return stops[kRampStop * i]; };
  const auto color = [&](size_t i) {
    const float* s = &stops[kRampStop * i];
    return vec4(s[1], s[2], s[3], s[4]);
  };
  const bool spline = mode == 3 || mode == 4;
  if (n == 1 || (in <= pos(0) && !spline)) return color(0);
  // The stops either side: `right` the first one past `in`, `left` the one before it; off
  // either end, the end stop stands in at position 0 or 1.
  size_t a = 0;
  while (a < n && pos(a) <= in) ++a;
  if (a == n && !spline) return color(n - 1);
  const size_t right = a == n ? n - 1 : a;
  const size_t left = a == 0 ? 0 : a - 1;
  const float right_pos = a == n ? 1.0f : pos(right);
  const float left_pos = a == 0 ? 0.0f : pos(left);
  if (mode == 0) return color(left);
  float fac = left_pos != right_pos ? (in - right_pos) / (left_pos - right_pos)
                                    : (a != n ? 0.0f : 1.0f);  // weight of `left`
  if (spline) {
    const size_t after = a >= n - 1 ? right : a + 1;
    const size_t before = a < 2 ? left : a - 2;
    fac = saturate(fac);
    // Blender's key_curve_position_weights, from `after` (w0) to `before` (w3).
    const float t2 = fac * fac;
    const float t3 = t2 * fac;
    float w[4];
    if (mode == 3) {
      const float fc = 0.71f;
      w[0] = -fc * t3 + 2.0f * fc * t2 - fc * fac;
      w[1] = (2.0f - fc) * t3 + (fc - 3.0f) * t2 + 1.0f;
      w[2] = (fc - 2.0f) * t3 + (3.0f - 2.0f * fc) * t2 + fc * fac;
      w[3] = fc * t3 - fc * t2;
    } else {
      w[0] = -0.16666666f * t3 + 0.5f * t2 - 0.5f * fac + 0.16666666f;
      w[1] = 0.5f * t3 - t2 + 0.66666666f;
      w[2] = -0.5f * t3 + 0.5f * t2 + 0.5f * fac + 0.16666666f;
      w[3] = 0.16666666f * t3;
    }
    const vec4 out =
        w[3] * color(before) + w[2] * color(left) + w[1] * color(right) + w[0] * color(after);
    return glm::clamp(out, vec4(0.0f), vec4(1.0f));
  }
  if (mode == 2) fac = 3.0f * fac * fac - 2.0f * fac * fac * fac;
  return (1.0f - fac) * color(right) + fac * color(left);
}

// One curve of a CURVE table: kCurveTable samples over [0, 1], linearly interpolated
// (Cycles float_ramp_lookup); beyond the ends held, or extrapolated along the end slope.
float curve(const float* table, float f, bool extrapolate) {
  constexpr float kLast = static_cast<float>(kCurveTable - 1);
  if (extrapolate && (f < 0.0f || f > 1.0f)) {
    const float t0 = f < 0.0f ? table[0] : table[kCurveTable - 1];
    const float dy = f < 0.0f ? t0 - table[1] : t0 - table[kCurveTable - 2];
    return t0 + dy * (f < 0.0f ? -f : f - 1.0f) * kLast;
  }
  f = saturate(f) * kLast;
  const auto i = std::min(static_cast<uint32_t>(f), kCurveTable - 1);
  const float t = f - static_cast<float>(i);
  float a = table[i];
  if (t > 0.0f) a = (1.0f - t) * a + t * table[i + 1];
  return a;
}

// Blender's Euler XYZ rotation: X first, then Y, then Z.
glm::mat3 euler_rotation(const Vec3& e) {
  const float cx = std::cos(e.x), cy = std::cos(e.y), cz = std::cos(e.z);
  const float sx = std::sin(e.x), sy = std::sin(e.y), sz = std::sin(e.z);
  // Columns of Rz * Ry * Rx.
  return glm::mat3(Vec3(cy * cz, cy * sz, -sy),
                   Vec3(sy * sx * cz - cx * sz, sy * sx * sz + cx * cz, cy * sx),
                   Vec3(sy * cx * cz + sx * sz, sy * cx * sz - sx * cz, cy * cx));
}

Vec3 mapping(uint32_t mode, const Vec3& v, const Vec3& location, const Vec3& rotation,
             const Vec3& scale) {
  const glm::mat3 r = euler_rotation(rotation);
  switch (mode) {
    case 0:  // point
      return r * (v * scale) + location;
    case 1:  // texture: the inverse of point
      return safe_divide(glm::transpose(r) * (v - location), scale);
    case 2:  // vector
      return r * (v * scale);
    default:  // normal
      return safe_normalize(r * safe_divide(v, scale));
  }
}

glm::vec2 map_to_sphere(const Vec3& co) {
  const float l2 = glm::dot(co, co);
  if (!(l2 > 0.0f)) return glm::vec2(0.0f);
  const float u =
      co.x == 0.0f && co.y == 0.0f ? 0.0f : 0.5f - std::atan2(co.x, co.y) / (2.0f * kPi);
  return {u, 1.0f - safe_acos(co.z / std::sqrt(l2)) / kPi};
}

glm::vec2 map_to_tube(const Vec3& co) {
  const float len = std::sqrt(co.x * co.x + co.y * co.y);
  if (!(len > 0.0f)) return glm::vec2(0.0f);
  return {(1.0f - std::atan2(co.x / len, co.y / len) / kPi) * 0.5f, (co.z + 1.0f) * 0.5f};
}

// Blender's box projection (Cycles svm_node_tex_image_box): up to three planar lookups
// weighted by the object-space normal, blended over `blend`.
vec4 box_image(const ImageTexture& image, const Vec3& co, const Vec3& signed_n, float blend) {
  Vec3 n = glm::abs(signed_n);
  n /= n.x + n.y + n.z;
  Vec3 w(0.0f);
  const float limit = 0.5f * (1.0f + blend);
  if (n.x > limit * (n.x + n.y) && n.x > limit * (n.x + n.z)) {
    w.x = 1.0f;
  } else if (n.y > limit * (n.x + n.y) && n.y > limit * (n.y + n.z)) {
    w.y = 1.0f;
  } else if (n.z > limit * (n.x + n.z) && n.z > limit * (n.y + n.z)) {
    w.z = 1.0f;
  } else if (blend > 0.0f) {
    const float edge = 0.5f * (1.0f - blend);
    if (n.z < (1.0f - limit) * (n.y + n.x)) {
      w.x = saturate((n.x / (n.x + n.y) - edge) / blend);
      w.y = 1.0f - w.x;
    } else if (n.x < (1.0f - limit) * (n.y + n.z)) {
      w.y = saturate((n.y / (n.y + n.z) - edge) / blend);
      w.z = 1.0f - w.y;
    } else if (n.y < (1.0f - limit) * (n.x + n.z)) {
      w.x = saturate((n.x / (n.x + n.z) - edge) / blend);
      w.z = 1.0f - w.x;
    } else {
      w = ((2.0f - limit) * n + (limit - 1.0f)) / (2.0f * limit - 1.0f);
    }
  } else {
    w.x = 1.0f;  // no blend and no clear side (a zero normal): one side
  }
  vec4 out(0.0f);
  // Oriented so that no side shows its image mirrored.
  if (w.x > 0.0f) {
    out += w.x * sample_image(image, {signed_n.x < 0.0f ? 1.0f - co.y : co.y, co.z});
  }
  if (w.y > 0.0f) {
    out += w.y * sample_image(image, {signed_n.y > 0.0f ? 1.0f - co.x : co.x, co.z});
  }
  if (w.z > 0.0f) {
    out += w.z * sample_image(image, {signed_n.z > 0.0f ? 1.0f - co.y : co.y, co.x});
  }
  return out;
}

vec4 image(uint32_t projection, const ImageTexture& texture, const Vec3& co, float blend,
           const ProgramHit& hit) {
  const Vec3 square = (co - 0.5f) * 2.0f;  // the [0,1] box onto [-1,1]
  switch (projection) {
    case 0:
      return sample_image(texture, glm::vec2(co));
    case 1:
      return box_image(texture, co, safe_normalize(glm::transpose(hit.to_world) * hit.normal),
                       blend);
    case 2:
      return sample_image(texture, map_to_sphere(square));
    default:
      return sample_image(texture, map_to_tube(square));
  }
}

// Blender's environment projections of a world direction (Cycles kernel/geom, the
// inverses of its panorama cameras): equirectangular with +X at the centre (u = 0.5), the
// seam at -X and +Z at the top (v = 1); a mirror ball seen from -Y.
glm::vec2 environment_uv(uint32_t mode, Vec3 dir) {
  dir = safe_normalize(dir);
  if (mode == 0) {
    if (dir == Vec3(0.0f)) return glm::vec2(0.0f);
    return {(std::atan2(dir.y, dir.x) - kPi) / (-2.0f * kPi), (safe_acos(dir.z) - kPi) / -kPi};
  }
  dir.y -= 1.0f;
  const float div = 2.0f * std::sqrt(std::fmax(-0.5f * dir.y, 0.0f));
  if (div > 0.0f) dir /= div;
  return {0.5f * (dir.x + 1.0f), 0.5f * (dir.z + 1.0f)};
}

float gradient(uint32_t mode, const Vec3& p) {
  switch (mode) {
    case 0:  // linear
      return p.x;
    case 1: {  // quadratic
      const float r = std::fmax(p.x, 0.0f);
      return r * r;
    }
    case 2: {  // easing
      const float r = saturate(p.x);
      return 3.0f * r * r - 2.0f * r * r * r;
    }
    case 3:  // diagonal
      return (p.x + p.y) * 0.5f;
    case 6:  // radial
      return std::atan2(p.y, p.x) / (2.0f * kPi) + 0.5f;
    default: {
      // Biased so that a unit vector gives exactly 0, not float noise.
      const float r = std::fmax(0.999999f - glm::length(p), 0.0f);
      return mode == 5 ? r * r : r;  // 5 quadratic sphere, 4 spherical
    }
  }
}

// Unpolarised dielectric reflectance for relative index eta (Cycles
// fresnel_dielectric_cos): 1 on total internal reflection.
float fresnel_dielectric(float cos_i, float eta) {
  const float c = std::fabs(cos_i);
  float g = eta * eta - 1.0f + c * c;
  if (!(g > 0.0f)) return 1.0f;
  g = std::sqrt(g);
  const float a = (g - c) / (g + c);
  const float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
  return 0.5f * a * a * (1.0f + b * b);
}

float layer_weight(uint32_t mode, float blend, const Vec3& n, const ProgramHit& hit) {
  const float cos_i = glm::dot(hit.incoming, n);
  if (mode == 0) {
    const float eta = std::fmax(1.0f - blend, 1e-5f);
    return fresnel_dielectric(cos_i, hit.backfacing ? eta : 1.0f / eta);
  }
  float f = std::fabs(cos_i);
  if (blend != 0.5f) {
    blend = clamp_to(blend, 0.0f, 1.0f - 1e-5f);
    f = std::pow(f, blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend));
  }
  return 1.0f - f;
}

// Blender's Normal Map node (Cycles svm_node_normal_map): the colour as a normal in
// tangent, object or world space, turned into a world normal on the incoming side.
Vec3 normal_map(uint32_t mode, float strength, Vec3 color, const glm::vec4& tangent,
                const Vec3& object_normal, const ProgramHit& hit) {
  color = 2.0f * (color - 0.5f);
  Vec3 n;
  if (mode == 0) {
    if (Vec3(tangent) == Vec3(0.0f)) return hit.normal;  // no tangents: unperturbed
    color.x *= strength;
    color.y *= strength;
    color.z = 1.0f + saturate(strength) * (color.z - 1.0f);
    const Vec3 t(tangent);
    const Vec3 b = tangent.w * glm::cross(object_normal, t);
    n = safe_normalize(hit.normal_to_world *
                       safe_normalize(color.x * t + color.y * b + color.z * object_normal));
  } else {
    n = mode == 1 ? safe_normalize(hit.normal_to_world * color) : safe_normalize(color);
    if (strength != 1.0f) {
      n = safe_normalize(hit.normal + (n - hit.normal) * std::fmax(strength, 0.0f));
    }
  }
  if (hit.backfacing) n = -n;
  return n == Vec3(0.0f) ? hit.normal : n;
}

// Blender's Bump node (Cycles svm_node_set_bump): the normal of the surface displaced by
// `distance` x height, from the height at the hit and at the two offsets dx, dy along it;
// on the incoming side, as `n` is. The offsets' length cancels out to first order.
Vec3 bump(const ProgramHit& hit, float strength, float distance, bool invert, const Vec3& n,
          float h, float h_x, float h_y) {
  const Vec3 r_x = glm::cross(hit.bump_dy, n);
  const Vec3 r_y = glm::cross(n, hit.bump_dx);
  const float det = glm::dot(hit.bump_dx, r_x);
  const Vec3 gradient = (h_x - h) * r_x + (h_y - h) * r_y;
  if (invert) distance = -distance;
  const float sign = det < 0.0f ? -1.0f : 1.0f;
  const Vec3 bumped = safe_normalize(std::fabs(det) * n - distance * sign * gradient);
  if (bumped == Vec3(0.0f)) return n;
  strength = std::fmax(strength, 0.0f);
  return safe_normalize(strength * bumped + (1.0f - strength) * n);
}

// ---------------------------------------------------------------------------------------
// Validation.

const char* op_name(uint32_t op) {
  static constexpr const char* kNames[] = {
      "?",        "INPUT",       "MATH",      "VECTOR_MATH", "MIX",          "MIX_VALUE",
      "SEPARATE", "SWIZZLE",     "COMBINE",   "HUE_SAT",     "GAMMA",        "BRIGHT_CONTRAST",
      "INVERT",   "CLAMP",       "MAP_RANGE", "COLOR_RAMP",  "CURVE",        "MAPPING",
      "IMAGE",    "ENVIRONMENT", "CHECKER",   "GRADIENT",    "NOISE",        "VORONOI",
      "WAVE",     "MAGIC",       "BRICK",     "FRESNEL",     "LAYER_WEIGHT", "NORMAL_MAP",
      "PACK",     "RGB_TO_BW",   "BUMP"};
  return op < std::size(kNames) ? kNames[op] : "?";
}

bool public_input(uint32_t mode) {
  if ((mode & kInputBumpX) != 0 && (mode & kInputBumpY) == 0) mode &= ~kInputBumpX;
  if ((mode & kInputBumpY) != 0 && (mode & kInputBumpX) == 0) mode &= ~kInputBumpY;
  return mode <= kInputObjectSpaceNormal ||
         (mode >= kInputIsCameraRay && mode <= kInputIsSingularRay) ||
         (mode >= kInputObjectLocation && mode <= kInputObjectColor) ||
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
      throw std::invalid_argument("instruction " + std::to_string(row) + " (" + op_name(op) +
                                  "): " + what);
    };
    if (op < static_cast<uint32_t>(Op::kInput) || op > static_cast<uint32_t>(Op::kBump)) {
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
    const auto modes = [&](uint32_t count, uint32_t flags = 0) {
      if ((mode & ~flags) >= count)
        fail("mode " + std::to_string(mode) + " is not one of its modes");
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
    switch (s.op) {
      case Op::kInput:
        if (!public_input(mode)) fail("mode " + std::to_string(mode) + " is not an input");
        s.e = input_slot(mode);
        bumps_ |= (mode & (kInputBumpX | kInputBumpY)) != 0;
        break;
      case Op::kMath:
        modes(static_cast<uint32_t>(kMathOpNames.size()), kClampBit);
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kVectorMath:
        modes(static_cast<uint32_t>(kVectorMathOpNames.size()));
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMix:
        modes(static_cast<uint32_t>(kMixBlendNames.size()), kClampBit);
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMixValue:
      case Op::kCombine:
        modes(3);
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kSeparate:
        modes(3);
        s.a = reg(3);
        break;
      case Op::kSwizzle:
        modes(4);
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
        modes(2);
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kMapRange:
        modes(4, kClampBit);
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kColorRamp: {
        modes(5);
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
      case Op::kCurve:
        modes(3, kClampBit);
        s.a = reg(3), s.b = reg(4);
        if (c[7] >= constants_.size() || c[7] + 4 * size_t{kCurveTable} > constants_.size()) {
          fail("constants at " + std::to_string(c[7]) + " do not hold a 4 x 256 curve table");
        }
        s.e = c[7];
        break;
      case Op::kMapping:
      case Op::kChecker:
      case Op::kPack:
        if (s.op == Op::kMapping) modes(4);
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6);
        break;
      case Op::kImage:
        modes(4);
        s.a = reg(3), s.b = reg(4), s.e = texture_slot();
        break;
      case Op::kEnvironment:
        modes(2);
        s.a = reg(3), s.e = texture_slot();
        break;
      case Op::kGradient:
        modes(7);
        s.a = reg(3);
        break;
      case Op::kLayerWeight:
        modes(2);
        s.a = reg(3), s.b = reg(4);
        s.b_given = c[4] != kUnused;
        break;
      case Op::kNormalMap:
        modes(3);
        s.a = reg(3), s.b = reg(4);
        if (mode == 0) {
          if (c[7] >= kInputAttribute - kInputUvSet) fail("tangent set out of range");
          s.e = input_slot(kInputTangent + c[7]);
          s.d = input_slot(kInputObjectNormal);
        }
        break;
      case Op::kRgbToBw:
        s.a = reg(3);
        break;
      case Op::kNoise:
      case Op::kVoronoi:
      case Op::kWave:
      case Op::kMagic:
      case Op::kBrick:
        if (!procedural::valid_mode(op, mode))
          fail("mode " + std::to_string(mode) + " is not one of its modes");
        s.a = reg(3), s.b = reg(4), s.c = reg(5);
        break;
      case Op::kBump:
        modes(2);
        s.a = reg(3), s.b = reg(4), s.c = reg(5), s.d = reg(6), s.e = reg(7);
        s.b_given = c[4] != kUnused;
        bumps_ = true;
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
        const float v = math(static_cast<MathOp>(s.mode & 0xFF), a.x, b.x, c.x);
        out = scalar((s.mode & kClampBit) != 0 ? saturate(v) : v);
        break;
      }
      case Op::kVectorMath:
        // SCALE reads its factor from b, REFRACT its index from c.
        out = vector_math(static_cast<VectorMathOp>(s.mode), Vec3(a), Vec3(b), Vec3(c),
                          static_cast<VectorMathOp>(s.mode) == VectorMathOp::kScale ? b.x : c.x);
        break;
      case Op::kMix: {
        const Vec3 m = mix(static_cast<MixBlend>(s.mode & 0xFF), a.x, Vec3(b), Vec3(c));
        out = vec4((s.mode & kClampBit) != 0 ? saturate(m) : m, b.w);
        break;
      }
      case Op::kMixValue:
        if (s.mode == 0) {
          out = scalar(b.x * (1.0f - a.x) + c.x * a.x);
        } else {
          const Vec3 t = s.mode == 1 ? Vec3(a.x) : Vec3(a);
          out = vector(Vec3(b) * (Vec3(1.0f) - t) + Vec3(c) * t);
        }
        break;
      case Op::kSeparate:
        out = vec4(s.mode == 0   ? Vec3(a)
                   : s.mode == 1 ? rgb_to_hsv(Vec3(a))
                                 : rgb_to_hsl(Vec3(a)),
                   a.w);
        break;
      case Op::kSwizzle:
        out = scalar(a[static_cast<int>(s.mode)]);
        break;
      case Op::kCombine: {
        const Vec3 v(a.x, b.x, c.x);
        out = vec4(s.mode == 0 ? v : s.mode == 1 ? hsv_to_rgb(v) : hsl_to_rgb(v), 1.0f);
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
        out = scalar(s.mode == 1 && b.x > c.x ? clamp_to(a.x, c.x, b.x) : clamp_to(a.x, b.x, c.x));
        break;
      case Op::kMapRange: {
        const uint32_t type = s.mode & 0xFF;
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
        if ((s.mode & kClampBit) != 0 && type <= 1) {
          v = to_min > to_max ? clamp_to(v, to_max, to_min) : clamp_to(v, to_min, to_max);
        }
        out = scalar(v);
        break;
      }
      case Op::kColorRamp:
        // Cycles samples the ramp over [0, 1] only.
        out = color_ramp(s.mode, &constants_[s.e + 1], static_cast<size_t>(constants_[s.e]),
                         saturate(a.x));
        break;
      case Op::kCurve: {
        const float* table = &constants_[s.e];
        const bool extrapolate = (s.mode & kClampBit) != 0;
        const auto row = [&](uint32_t i, float x) {
          return curve(table + i * kCurveTable, x, extrapolate);
        };
        const float fac = a.x;
        const uint32_t kind = s.mode & 0xFF;
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
      case Op::kMapping:
        out = vector(mapping(s.mode, Vec3(a), Vec3(b), Vec3(c), Vec3(r[s.d])));
        break;
      case Op::kImage:
        out = image(s.mode, *hit.images[s.e], Vec3(a), b.x, hit);
        break;
      case Op::kEnvironment:
        out = sample_image(*hit.images[s.e], environment_uv(s.mode, Vec3(a)));
        break;
      case Op::kChecker: {
        const bool first = checker_first(Vec3(a) * r[s.d].x);
        out = vec4(first ? Vec3(b) : Vec3(c), first ? 1.0f : 0.0f);
        break;
      }
      case Op::kGradient:
        out = scalar(saturate(gradient(s.mode, Vec3(a))));
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
        out = scalar(layer_weight(s.mode, a.x, s.b_given ? Vec3(b) : hit.normal, hit));
        break;
      case Op::kNormalMap: {
        const bool tangent = s.mode == 0;
        out = vector(normal_map(s.mode, a.x, Vec3(b), tangent ? hit.inputs[s.e] : vec4(0.0f),
                                tangent ? Vec3(hit.inputs[s.d]) : Vec3(0.0f), hit));
        break;
      }
      case Op::kPack:
        out = vec4(a.x, b.x, c.x, r[s.d].x);
        break;
      case Op::kRgbToBw:
        out = scalar(0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z);
        break;
      case Op::kBump:
        out = vector(bump(hit, a.x, a.y, s.mode == 1, s.b_given ? Vec3(b) : hit.normal, c.x,
                          r[s.d].x, r[s.e].x));
        break;
      default:  // rejected at construction
        break;
    }
    r[s.out] = out;
  }
}

}  // namespace whitted
