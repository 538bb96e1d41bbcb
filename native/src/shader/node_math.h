// Blender's node maths, as Cycles' kernel defines each node (svm/*.h): the Math, Vector
// Math and Mix operations, colour conversions, ramps and curves, Mapping, the image and
// environment projections, Gradient, Fresnel, Layer Weight, Normal Map and Bump: what one
// op of a shader program computes (shader/program.cpp runs them; header-only so each op
// inlines into the interpreter's loop).
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "shader/ops.h"
#include "shader/procedural.h"
#include "shader/program.h"

namespace whitted::node_math {

using glm::vec4;

inline constexpr size_t kRampStop = 5;  // floats per colour ramp stop: pos, r, g, b, a

// ---------------------------------------------------------------------------------------
// Blender's scalar helpers (Cycles util/math.h): each defined where C's would be
// undefined or NaN, so a node graph never makes a NaN Blender would not.

inline float saturate(float x) {
  return std::fmin(std::fmax(x, 0.0f), 1.0f);  // NaN becomes 0, as in Cycles
}
// Cycles' clamp: the upper bound wins when the bounds cross.
inline float clamp_to(float x, float lo, float hi) {
  return std::fmin(std::fmax(x, lo), hi);
}
inline float safe_divide(float a, float b) {
  return b != 0.0f ? a / b : 0.0f;
}
inline float safe_pow(float a, float b) {
  if (a < 0.0f && std::trunc(b) != b) return 0.0f;  // a negative base needs an integer power
  return std::pow(a, b);
}
inline float safe_log(float a, float b) {
  if (a <= 0.0f || b <= 0.0f) return 0.0f;
  return safe_divide(std::log(a), std::log(b));
}
inline float safe_modulo(float a, float b) {
  return b != 0.0f ? std::fmod(a, b) : 0.0f;
}
inline float floored_modulo(float a, float b) {
  return b != 0.0f ? a - std::floor(a / b) * b : 0.0f;
}
inline float fract(float a) {
  return a - std::floor(a);
}
// Blender's wrap(value, max, min): value moved by whole ranges into [min, max).
inline float wrap(float value, float max, float min) {
  const float range = max - min;
  return range != 0.0f ? value - range * std::floor((value - min) / range) : min;
}
inline float pingpong(float a, float b) {
  return b != 0.0f ? std::fabs(fract((a - b) / (b * 2.0f)) * b * 2.0f - b) : 0.0f;
}
inline float smooth_min(float a, float b, float k) {
  if (k == 0.0f) return std::fmin(a, b);
  const float h = std::fmax(k - std::fabs(a - b), 0.0f) / k;
  return std::fmin(a, b) - h * h * h * k * (1.0f / 6.0f);
}
inline float sign(float a) {
  return a == 0.0f ? 0.0f : (a < 0.0f ? -1.0f : 1.0f);
}
inline float safe_asin(float a) {
  return std::asin(clamp_to(a, -1.0f, 1.0f));
}
inline float safe_acos(float a) {
  return std::acos(clamp_to(a, -1.0f, 1.0f));
}
inline float atan2_or_zero(float y, float x) {
  return x == 0.0f && y == 0.0f ? 0.0f : std::atan2(y, x);
}
inline float smoothstep(float edge0, float edge1, float x) {
  if (x < edge0) return 0.0f;
  if (x >= edge1) return 1.0f;
  const float t = (x - edge0) / (edge1 - edge0);
  return (3.0f - 2.0f * t) * (t * t);
}
inline float smootherstep(float edge0, float edge1, float x) {
  x = saturate(safe_divide(x - edge0, edge1 - edge0));
  return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}

inline Vec3 safe_normalize(const Vec3& v) {
  const float length = glm::length(v);
  return length != 0.0f ? v * (1.0f / length) : v;
}
inline Vec3 safe_divide(const Vec3& a, const Vec3& b) {
  return {safe_divide(a.x, b.x), safe_divide(a.y, b.y), safe_divide(a.z, b.z)};
}
inline Vec3 saturate(const Vec3& c) {
  return {saturate(c.x), saturate(c.y), saturate(c.z)};
}
// Cycles' interp: a + t (b - a).
inline Vec3 interp(const Vec3& a, const Vec3& b, float t) {
  return a + t * (b - a);
}
template <typename F>
inline Vec3 each(const Vec3& a, const Vec3& b, F f) {
  return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)};
}
template <typename F>
inline Vec3 each(const Vec3& a, F f) {
  return {f(a.x), f(a.y), f(a.z)};
}

inline vec4 scalar(float v) {
  return vec4(v);
}
inline vec4 vector(const Vec3& v) {
  return vec4(v, 0.0f);
}

// ---------------------------------------------------------------------------------------
// Colour spaces (Cycles util/color.h).

inline Vec3 rgb_to_hsv(const Vec3& rgb) {
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

inline Vec3 hsv_to_rgb(const Vec3& hsv) {
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

inline Vec3 rgb_to_hsl(const Vec3& rgb) {
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

inline Vec3 hsl_to_rgb(const Vec3& hsl) {
  const float h = hsl.x;
  const float nr = saturate(std::fabs(h * 6.0f - 3.0f) - 1.0f);
  const float ng = saturate(2.0f - std::fabs(h * 6.0f - 2.0f));
  const float nb = saturate(2.0f - std::fabs(h * 6.0f - 4.0f));
  const float chroma = (1.0f - std::fabs(2.0f * hsl.z - 1.0f)) * hsl.y;
  return Vec3(nr - 0.5f, ng - 0.5f, nb - 0.5f) * chroma + hsl.z;
}

// ---------------------------------------------------------------------------------------
// Nodes.

inline float math(MathOp op, float a, float b, float c) {
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

inline vec4 vector_math(VectorMathOp op, const Vec3& a, const Vec3& b, const Vec3& c, float scale) {
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
inline Vec3 mix(MixBlend blend, float t, const Vec3& c1, const Vec3& c2) {
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
inline vec4 color_ramp(uint32_t mode, const float* stops, size_t n, float in) {
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
inline float curve(const float* table, float f, bool extrapolate) {
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
inline glm::mat3 euler_rotation(const Vec3& e) {
  const float cx = std::cos(e.x), cy = std::cos(e.y), cz = std::cos(e.z);
  const float sx = std::sin(e.x), sy = std::sin(e.y), sz = std::sin(e.z);
  // Columns of Rz * Ry * Rx.
  return glm::mat3(Vec3(cy * cz, cy * sz, -sy),
                   Vec3(sy * sx * cz - cx * sz, sy * sx * sz + cx * cz, cy * sx),
                   Vec3(sy * cx * cz + sx * sz, sy * cx * sz - sx * cz, cy * cx));
}

inline Vec3 mapping(uint32_t mode, const Vec3& v, const Vec3& location, const Vec3& rotation,
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

// The Vector Rotate node: `v` turned about `center` by `mode`'s rotation_type (Euler XYZ
// `rotation`; else `angle` radians about X, Y, Z or `axis`, right-handed), the inverse
// rotation with the invert flag; about a zero axis `v` is unchanged.
inline Vec3 vector_rotate(uint32_t mode, const Vec3& v, const Vec3& center, const Vec3& rotation,
                          float angle) {
  const uint32_t type = mode_field::kVectorRotateType.in(mode);  // kVectorRotateNames
  const bool invert = mode_field::kVectorRotateInvert.on(mode);
  if (type == 4) {
    const glm::mat3 r = euler_rotation(rotation);
    return (invert ? glm::transpose(r) : r) * (v - center) + center;
  }
  Vec3 axis = type == 1   ? Vec3(1.0f, 0.0f, 0.0f)
              : type == 2 ? Vec3(0.0f, 1.0f, 0.0f)
              : type == 3 ? Vec3(0.0f, 0.0f, 1.0f)
                          : rotation;
  const float length = type == 0 ? glm::length(axis) : 1.0f;
  if (length == 0.0f) return v;
  axis /= length;
  if (invert) angle = -angle;
  // Rodrigues' rotation of the offset from the centre, written out as Cycles' matrix.
  const Vec3 p = v - center;
  const float c = std::cos(angle), s = std::sin(angle), k = 1.0f - c;
  const Vec3 r((c + k * axis.x * axis.x) * p.x + (k * axis.x * axis.y - axis.z * s) * p.y +
                   (k * axis.x * axis.z + axis.y * s) * p.z,
               (k * axis.x * axis.y + axis.z * s) * p.x + (c + k * axis.y * axis.y) * p.y +
                   (k * axis.y * axis.z - axis.x * s) * p.z,
               (k * axis.x * axis.z - axis.y * s) * p.x + (k * axis.y * axis.z + axis.x * s) * p.y +
                   (c + k * axis.z * axis.z) * p.z);
  return r + center;
}

// The Light Falloff node at a hit `length` from where its ray started: `strength` as is
// (Quadratic), times the length (Linear) or its square (Constant), so that a light's own
// inverse-square falloff leaves that; a positive `smooth` scales it by
// length^2 / (smooth + length^2), except where the square overflows.
inline float light_falloff(uint32_t mode, float strength, float smooth, float length) {
  const uint32_t falloff = mode_field::kLightFalloff.in(mode);  // kLightFalloffNames
  if (falloff == 1) strength *= length;
  if (falloff == 2) strength *= length * length;
  if (smooth > 0.0f) {
    const float squared = length * length;
    if (std::isfinite(squared)) strength *= squared / (smooth + squared);
  }
  return strength;
}

// The Wireframe node (Pixel Size off): 1 where point `p` lies within `size` / 2 (world
// units) of an edge line of the triangle with corners `c0`, `c1`, `c2`, else 0: the
// squared distance to each edge's line, |edge x (p - corner)|^2 / |edge|^2, against
// (size / 2)^2, as Cycles compares them (a zero edge never counts).
inline float wireframe(float size, const Vec3& p, const Vec3& c0, const Vec3& c1, const Vec3& c2) {
  const Vec3 corners[3] = {c0, c1, c2};
  float width = 0.5f * size;
  width *= width;
  for (int i = 0; i < 3; ++i) {
    const Vec3 edge = corners[i] - corners[i == 0 ? 2 : i - 1];
    const Vec3 crs = glm::cross(edge, p - corners[i]);
    if (glm::dot(crs, crs) < glm::dot(edge, edge) * width) return 1.0f;
  }
  return 0.0f;
}

inline glm::vec2 map_to_sphere(const Vec3& co) {
  const float l2 = glm::dot(co, co);
  if (!(l2 > 0.0f)) return glm::vec2(0.0f);
  const float u =
      co.x == 0.0f && co.y == 0.0f ? 0.0f : 0.5f - std::atan2(co.x, co.y) / (2.0f * kPi);
  return {u, 1.0f - safe_acos(co.z / std::sqrt(l2)) / kPi};
}

inline glm::vec2 map_to_tube(const Vec3& co) {
  const float len = std::sqrt(co.x * co.x + co.y * co.y);
  if (!(len > 0.0f)) return glm::vec2(0.0f);
  return {(1.0f - std::atan2(co.x / len, co.y / len) / kPi) * 0.5f, (co.z + 1.0f) * 0.5f};
}

// Blender's box projection (Cycles svm_node_tex_image_box): up to three planar lookups
// weighted by the object-space normal, blended over `blend`.
inline vec4 box_image(const ImageTexture& image, const Vec3& co, const Vec3& signed_n,
                      float blend) {
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
  // Oriented so that no side shows its image mirrored; a UDIM image's first tile, as
  // Cycles projects it.
  if (w.x > 0.0f) {
    out += w.x * sample_first_tile(image, {signed_n.x < 0.0f ? 1.0f - co.y : co.y, co.z});
  }
  if (w.y > 0.0f) {
    out += w.y * sample_first_tile(image, {signed_n.y > 0.0f ? 1.0f - co.x : co.x, co.z});
  }
  if (w.z > 0.0f) {
    out += w.z * sample_first_tile(image, {signed_n.z > 0.0f ? 1.0f - co.y : co.y, co.x});
  }
  return out;
}

inline vec4 image(uint32_t projection, const ImageTexture& texture, const Vec3& co, float blend,
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
inline glm::vec2 environment_uv(uint32_t mode, Vec3 dir) {
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

inline float gradient(uint32_t mode, const Vec3& p) {
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
inline float fresnel_dielectric(float cos_i, float eta) {
  const float c = std::fabs(cos_i);
  float g = eta * eta - 1.0f + c * c;
  if (!(g > 0.0f)) return 1.0f;
  g = std::sqrt(g);
  const float a = (g - c) / (g + c);
  const float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
  return 0.5f * a * a * (1.0f + b * b);
}

// Blender's Layer Weight node: `output` 0 its Fresnel, 1 its Facing (kLayerWeightNames).
inline float layer_weight(uint32_t output, float blend, const Vec3& n, const ProgramHit& hit) {
  const float cos_i = glm::dot(hit.incoming, n);
  if (output == 0) {
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
inline Vec3 normal_map(uint32_t mode, float strength, Vec3 color, const glm::vec4& tangent,
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
inline Vec3 bump(const ProgramHit& hit, float strength, float distance, bool invert, const Vec3& n,
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

}  // namespace whitted::node_math
