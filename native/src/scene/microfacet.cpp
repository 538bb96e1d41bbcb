#include "scene/microfacet.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace whitted {

Frame::Frame(const Vec3& normal) : n(normal) {
  // Any vector not parallel to n makes the tangent; the frame is orthonormal either way.
  const Vec3 helper = std::fabs(n.x) > 0.9f ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(1.0f, 0.0f, 0.0f);
  t = glm::normalize(glm::cross(helper, n));
  b = glm::cross(n, t);
}

Frame::Frame(const Vec3& normal, const Vec3& tangent)
    : b(glm::normalize(glm::cross(normal, tangent))), n(normal) {
  t = glm::cross(b, n);
}

GgxLobe::GgxLobe(const Vec3& normal, const Vec3& tangent, float ax, float ay)
    : n(normal), alpha_x(ax), alpha_y(ay) {
  const Vec3 along = tangent - glm::dot(tangent, normal) * normal;
  const float length = glm::length(along);
  // Relative to the tangent's own length: a tangent along n leaves no direction.
  if (!(length > 1e-6f * glm::length(tangent)) || !std::isfinite(length)) {
    alpha_x = alpha_y = std::sqrt(ax * ay);
    return;
  }
  t = along / length;
}

Frame GgxLobe::frame() const {
  return isotropic() ? Frame(n) : Frame(n, t);
}

void ggx_anisotropic_alphas(float alpha, float anisotropy, float* ax, float* ay) {
  const float a = std::clamp(anisotropy, -0.99f, 0.99f);
  *ax = *ay = alpha;
  if (!(std::fabs(a) > 1e-4f)) return;  // NaN too
  if (a < 0.0f) {
    *ax = alpha / (1.0f + a);
    *ay = alpha * (1.0f + a);
  } else {
    *ax = alpha * (1.0f - a);
    *ay = alpha / (1.0f - a);
  }
}

float ggx_distribution(float cos_m, float alpha) {
  if (cos_m <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  const float c2 = cos_m * cos_m;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float ggx_lambda(float cos_theta, float alpha) {
  const float c2 = cos_theta * cos_theta;
  if (c2 <= 0.0f) return kInfinity;
  // alpha^2 tan^2(theta), with tan^2 = (1 - cos^2) / cos^2.
  const float a2t2 = alpha * alpha * std::max(0.0f, 1.0f - c2) / c2;
  return 0.5f * (std::sqrt(1.0f + a2t2) - 1.0f);
}

namespace {

// A unit world direction in a lobe's frame, its cosine to the normal given; an
// isotropic lobe needs only that cosine.
Vec3 in_frame(const GgxLobe& g, const Vec3& v, float cos_theta) {
  if (g.isotropic()) return {0.0f, 0.0f, cos_theta};
  return {glm::dot(g.t, v), glm::dot(glm::cross(g.n, g.t), v), cos_theta};
}

// D(m) for a microfacet normal m in the lobe's frame; an anisotropic lobe's
// 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2).
float distribution(const GgxLobe& g, const Vec3& m) {
  if (g.isotropic()) return ggx_distribution(m.z, g.alpha_x);
  if (m.z <= 0.0f) return 0.0f;
  const float x = m.x / g.alpha_x;
  const float y = m.y / g.alpha_y;
  const float d = x * x + y * y + m.z * m.z;
  return 1.0f / (kPi * g.alpha_x * g.alpha_y * d * d);
}

// Smith's Lambda for a direction w in the lobe's frame; an anisotropic lobe's alpha^2
// tan^2 is (ax^2 x^2 + ay^2 y^2) / z^2.
float lambda(const GgxLobe& g, const Vec3& w) {
  if (g.isotropic()) return ggx_lambda(w.z, g.alpha_x);
  const float c2 = w.z * w.z;
  if (c2 <= 0.0f) return kInfinity;
  const float x = g.alpha_x * w.x;
  const float y = g.alpha_y * w.y;
  return 0.5f * (std::sqrt(1.0f + (x * x + y * y) / c2) - 1.0f);
}

// G2 over G1(wo), from the two directions' Lambdas.
float masking_ratio(float lambda_o, float lambda_i, Masking masking) {
  if (masking == Masking::kSeparable) return 1.0f / (1.0f + lambda_i);  // G1_i
  return (1.0f + lambda_o) / (1.0f + lambda_o + lambda_i);
}

// Heitz (2018): a visible normal for the local view v (z up) of a lobe of these alphas
// (along x and y).
Vec3 visible_normal(const Vec3& v, float ax, float ay, float u1, float u2) {
  // The view stretched to the hemisphere configuration, ...
  const Vec3 vh = glm::normalize(Vec3(ax * v.x, ay * v.y, v.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = glm::cross(vh, t1);
  // ... a point on the disc of its visible projected area (the disc's lower half shrunk
  // by the view's tilt), ...
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  // ... lifted to the hemisphere, and unstretched: the microfacet normal.
  const Vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(Vec3(ax * nh.x, ay * nh.y, std::max(1e-7f, nh.z)));
}

// A reflection's cosines to n, of the view and the light, its unit half vector m and
// n.m; false below either horizon or for opposite directions (no half vector). GGX's
// and GTR1's lobes both start here.
bool half_vector(const Vec3& n, const Vec3& wo, const Vec3& wi, float* cos_o, float* cos_i, Vec3* m,
                 float* cos_m) {
  *cos_o = glm::dot(n, wo);
  *cos_i = glm::dot(n, wi);
  if (*cos_o <= 0.0f || *cos_i <= 0.0f) return false;
  const Vec3 half = wo + wi;
  const float length = glm::length(half);
  if (!(length > 0.0f)) return false;
  *m = half / length;
  *cos_m = glm::dot(n, half) / length;
  return true;
}

// A reflection's cosines to the normal, of the view and the light, and GGX's D of its
// half vector; false below either horizon or for opposite directions (no half vector).
bool reflection_geometry(const GgxLobe& g, const Vec3& wo, const Vec3& wi, float* cos_o,
                         float* cos_i, float* d) {
  Vec3 m;
  float cos_m = 0.0f;
  if (!half_vector(g.n, wo, wi, cos_o, cos_i, &m, &cos_m)) return false;
  *d = distribution(g, in_frame(g, m, cos_m));
  return true;
}

}  // namespace

float ggx_reflection(const GgxLobe& lobe, const Vec3& wo, const Vec3& wi, Masking masking) {
  float cos_o = 0.0f;
  float cos_i = 0.0f;
  float d = 0.0f;
  if (!reflection_geometry(lobe, wo, wi, &cos_o, &cos_i, &d)) return 0.0f;
  // Smith's masking-shadowing (Heitz 2014): height-correlated as Cycles 4.0 on has it,
  // or separable as Cycles 3.x.
  const float lambda_o = lambda(lobe, in_frame(lobe, wo, cos_o));
  const float lambda_i = lambda(lobe, in_frame(lobe, wi, cos_i));
  const float g2 = masking_ratio(lambda_o, lambda_i, masking) / (1.0f + lambda_o);
  return d * g2 / (4.0f * cos_o);
}

float ggx_reflection_pdf(const GgxLobe& lobe, const Vec3& wo, const Vec3& wi) {
  float cos_o = 0.0f;
  float cos_i = 0.0f;
  float d = 0.0f;
  if (!reflection_geometry(lobe, wo, wi, &cos_o, &cos_i, &d)) return 0.0f;
  return d / ((1.0f + lambda(lobe, in_frame(lobe, wo, cos_o))) * 4.0f * cos_o);
}

bool ggx_sample_normal(const Vec3& n, const Vec3& wo, float alpha, float u1, float u2, Vec3* m) {
  const Frame frame(n);
  const Vec3 v = frame.to_local(wo);
  if (v.z <= 0.0f) return false;
  *m = glm::normalize(frame.to_world(visible_normal(v, alpha, alpha, u1, u2)));
  return true;
}

float ggx_transmission_weight(float cos_o, float cos_t, float alpha, Masking masking) {
  return masking_ratio(ggx_lambda(cos_o, alpha), ggx_lambda(std::fabs(cos_t), alpha), masking);
}

bool ggx_sample_reflection(const GgxLobe& lobe, const Vec3& wo, float u1, float u2, Vec3* wi,
                           float* weight, Masking masking) {
  *weight = 0.0f;
  const Frame frame = lobe.frame();
  const Vec3 v = frame.to_local(wo);
  if (v.z <= 0.0f) return false;
  const Vec3 m = visible_normal(v, lobe.alpha_x, lobe.alpha_y, u1, u2);
  const Vec3 l = 2.0f * glm::dot(v, m) * m - v;  // the view mirrored about m
  if (l.z <= 0.0f) return false;
  *weight = masking_ratio(lambda(lobe, v), lambda(lobe, l), masking);
  *wi = glm::normalize(frame.to_world(l));
  return true;
}

namespace {

constexpr int kTableSize = 32;  // roughness and cos_o, each in [0, 1], ends included

// E(cos_o, roughness) on a grid, and E_avg(roughness): immutable once made.
struct AlbedoTables {
  std::array<float, kTableSize * kTableSize> albedo{};  // [roughness][cos_o]
  std::array<float, kTableSize> average{};

  AlbedoTables() {
    constexpr int kStrata = 24;  // 24 x 24 stratified lobe samples per entry
    for (int r = 0; r < kTableSize; ++r) {
      const float roughness = static_cast<float>(r) / (kTableSize - 1);
      const float alpha = std::max(roughness * roughness, 1e-4f);
      double mean = 0.0;
      for (int c = 0; c < kTableSize; ++c) {
        const float cos_o = std::max(static_cast<float>(c) / (kTableSize - 1), 1e-3f);
        const Vec3 wo(std::sqrt(1.0f - cos_o * cos_o), 0.0f, cos_o);
        double sum = 0.0;
        for (int i = 0; i < kStrata; ++i) {
          for (int j = 0; j < kStrata; ++j) {
            Vec3 wi;
            float weight = 0.0f;
            if (ggx_sample_reflection(GgxLobe(Vec3(0, 0, 1), alpha), wo, (i + 0.5f) / kStrata,
                                      (j + 0.5f) / kStrata, &wi, &weight)) {
              sum += weight;
            }
          }
        }
        const float e = static_cast<float>(sum / (kStrata * kStrata));
        albedo[static_cast<size_t>(r * kTableSize + c)] = e;
        // E_avg = 2 * integral of E(mu) mu dmu, by the trapezoid rule over the grid.
        const float weight = (c == 0 || c == kTableSize - 1) ? 0.5f : 1.0f;
        mean += weight * e * (static_cast<float>(c) / (kTableSize - 1));
      }
      average[static_cast<size_t>(r)] = static_cast<float>(2.0 * mean / (kTableSize - 1));
    }
  }
};

const AlbedoTables& tables() {
  static const AlbedoTables made;  // made once, by the first caller (thread-safe)
  return made;
}

// Position of x in [0, 1] on the grid: the cell and the weight of its upper end.
void cell(float x, int* index, float* t) {
  const float g = std::clamp(x, 0.0f, 1.0f) * (kTableSize - 1);
  *index = std::min(static_cast<int>(g), kTableSize - 2);
  *t = g - static_cast<float>(*index);
}

}  // namespace

float ggx_albedo(float cos_o, float roughness) {
  int r = 0;
  int c = 0;
  float tr = 0.0f;
  float tc = 0.0f;
  cell(roughness, &r, &tr);
  cell(cos_o, &c, &tc);
  const auto& e = tables().albedo;
  const auto at = [&](int i, int j) { return e[static_cast<size_t>(i * kTableSize + j)]; };
  const float low = at(r, c) + tc * (at(r, c + 1) - at(r, c));
  const float high = at(r + 1, c) + tc * (at(r + 1, c + 1) - at(r + 1, c));
  return low + tr * (high - low);
}

float ggx_average_albedo(float roughness) {
  int r = 0;
  float t = 0.0f;
  cell(roughness, &r, &t);
  const auto& a = tables().average;
  return a[static_cast<size_t>(r)] +
         t * (a[static_cast<size_t>(r + 1)] - a[static_cast<size_t>(r)]);
}

Color ggx_multiscatter_scale(const Color& f, float cos_o, float roughness) {
  const float e = std::max(ggx_albedo(cos_o, roughness), 1e-3f);
  const float e_avg = ggx_average_albedo(roughness);
  Color scale;
  for (int k = 0; k < 3; ++k) {
    const float fk = std::clamp(f[k], 0.0f, 1.0f);
    const float f_ms = fk * e_avg / std::max(1.0f - fk * (1.0f - e_avg), 1e-6f);
    scale[k] = 1.0f + f_ms * (1.0f - e) / e;
  }
  return scale;
}

namespace {

// Cycles 3.x's fixed alpha of the clearcoat's masking and shadowing.
constexpr float kGtr1MaskingAlpha = 0.25f;

float gtr1_masking(float cos_theta) {
  return 1.0f / (1.0f + ggx_lambda(cos_theta, kGtr1MaskingAlpha));
}

}  // namespace

float gtr1_distribution(float cos_m, float alpha) {
  if (cos_m <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  if (a2 >= 1.0f) return kInvPi;
  return (a2 - 1.0f) / (kPi * std::log(a2) * (1.0f + (a2 - 1.0f) * cos_m * cos_m));
}

float gtr1_reflection(const Vec3& n, float alpha, const Vec3& wo, const Vec3& wi) {
  float cos_o = 0.0f;
  float cos_i = 0.0f;
  Vec3 m;
  float cos_m = 0.0f;
  if (!half_vector(n, wo, wi, &cos_o, &cos_i, &m, &cos_m)) return 0.0f;
  return gtr1_distribution(cos_m, alpha) * gtr1_masking(cos_o) * gtr1_masking(cos_i) /
         (4.0f * cos_o);
}

float gtr1_reflection_pdf(const Vec3& n, float alpha, const Vec3& wo, const Vec3& wi) {
  float cos_o = 0.0f;
  float cos_i = 0.0f;
  Vec3 m;
  float cos_m = 0.0f;
  if (!half_vector(n, wo, wi, &cos_o, &cos_i, &m, &cos_m)) return 0.0f;
  // dwi = 4 (wo.m) dm: the reflection's Jacobian.
  return gtr1_distribution(cos_m, alpha) * cos_m / (4.0f * glm::dot(wo, m));
}

bool gtr1_sample_reflection(const Vec3& n, float alpha, const Vec3& wo, float u1, float u2,
                            Vec3* wi, float* weight) {
  *weight = 0.0f;
  const float cos_o = glm::dot(n, wo);
  if (cos_o <= 0.0f) return false;
  // sin^2 of the half vector's angle, from the inverted cumulative distribution (kept
  // as 1 - cos^2 computed directly: near the sharp core cos^2 rounds to 1).
  const float a2 = alpha * alpha;
  const float sin2 = a2 >= 1.0f ? u1 : (std::pow(a2, 1.0f - u1) - a2) / (1.0f - a2);
  const float sin_m = std::sqrt(std::clamp(sin2, 0.0f, 1.0f));
  const float cos_m = std::sqrt(std::clamp(1.0f - sin2, 0.0f, 1.0f));
  const float phi = 2.0f * kPi * u2;
  const Frame frame(n);
  const Vec3 m = frame.to_world({sin_m * std::cos(phi), sin_m * std::sin(phi), cos_m});
  const float o_dot_m = glm::dot(wo, m);
  if (o_dot_m <= 0.0f) return false;
  const Vec3 l = 2.0f * o_dot_m * m - wo;  // the view mirrored about m
  const float cos_i = glm::dot(n, l);
  if (cos_i <= 0.0f || !(cos_m > 0.0f)) return false;
  *weight = gtr1_masking(cos_o) * gtr1_masking(cos_i) * o_dot_m / (cos_o * cos_m);
  *wi = glm::normalize(l);
  return true;
}

float lobe_reflection(CoatModel model, const GgxLobe& lobe, const Vec3& wo, const Vec3& wi,
                      Masking masking) {
  return model == CoatModel::kGtr1 ? gtr1_reflection(lobe.n, lobe.alpha(), wo, wi)
                                   : ggx_reflection(lobe, wo, wi, masking);
}

bool lobe_sample_reflection(CoatModel model, const GgxLobe& lobe, const Vec3& wo, float u1,
                            float u2, Vec3* wi, float* weight, Masking masking) {
  return model == CoatModel::kGtr1
             ? gtr1_sample_reflection(lobe.n, lobe.alpha(), wo, u1, u2, wi, weight)
             : ggx_sample_reflection(lobe, wo, u1, u2, wi, weight, masking);
}

float lobe_reflection_pdf(CoatModel model, const GgxLobe& lobe, const Vec3& wo, const Vec3& wi) {
  return model == CoatModel::kGtr1 ? gtr1_reflection_pdf(lobe.n, lobe.alpha(), wo, wi)
                                   : ggx_reflection_pdf(lobe, wo, wi);
}

}  // namespace whitted
