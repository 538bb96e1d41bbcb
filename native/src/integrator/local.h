// The local model: one light sample's Phong terms at a shading point, per unit
// irradiance and unshadowed, with the lobes that extend it (the diffuse shapes and the
// coat of lobes.h, the GGX lobe of microfacet.h), and the share of the local term they
// make. The light samples themselves, and their feelers, are lights.h's.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "integrator/lobes.h"
#include "integrator/shading_point.h"
#include "scene/microfacet.h"
#include "scene/scene.h"

namespace whitted {

// (v.r)^f, without powf (about 61 instructions a call, callgrind) where its value is
// known or cannot show, to the bit: for f > 0 it is +0 at v.r = 0, and where ks is 0 the
// lobe is only ever multiplied by ks (then finite, as v.r <= 1), so 0 gives the same
// products.
inline float phong_lobe(const ShadingPoint& p, float v_dot_r) {
  const float f = p.surface.shininess;
  const bool known =
      f > 0.0f && (v_dot_r <= 0.0f || (v_dot_r <= 1.0f && p.surface.specular == Color(0.0f)));
  return known ? 0.0f : std::pow(v_dot_r, f);
}

// The diffuse lobe's factors for light from wi (fade, loss): Cycles' bump shadowing,
// times the lobe's shape where it is not Lambert's (material.h's DiffuseModel); and the
// sheen lobe's shape, under the same shadowing.
inline void diffuse_fade(const ShadingPoint& p, const Vec3& wi, float cos_l, LightTerms* t) {
  const Material& m = *p.it.material;
  t->fade = diffuse_shadowing(m.bump_shadowing, p.smooth, p.ns, wi);
  const bool sheen = !is_black(p.surface.sheen);
  if (m.diffuse_model == DiffuseModel::kLambert && !sheen) return;
  const float cos_v = glm::dot(p.ns, p.wo);
  const float l_dot_v = glm::dot(wi, p.wo);
  if (sheen) t->sheen = t->fade * velvet_sheen(cos_l, cos_v, l_dot_v, p.surface.sheen_roughness);
  if (m.diffuse_model == DiffuseModel::kLambert) return;
  const float r = p.surface.diffuse_roughness;
  if (m.diffuse_model == DiffuseModel::kBurley) {
    t->fade *= burley_diffuse(cos_l, cos_v, l_dot_v, r);
    return;
  }
  if (m.diffuse_model == DiffuseModel::kOrenNayarEnergy) {
    t->loss = t->fade * oren_nayar_loss(cos_l, r);
  }
  t->fade *= oren_nayar_diffuse(cos_l, cos_v, l_dot_v, r);
}

// The Phong terms of a light sample from wi, per unit irradiance, unshadowed.
inline LightTerms light_terms(const ShadingPoint& p, const Vec3& wi, float cos_l) {
  const float v_dot_r = std::max(0.0f, glm::dot(p.wo, reflect(-wi, p.ns)));
  LightTerms t{
      p.base * std::max(0.0f, cos_l),
      1.0f,
      0.0f,
      phong_lobe(p, v_dot_r),
      coat_highlight(p.coat, p.wo, wi, p.it.material->masking),
      p.alpha > 0.0f ? p.base * ggx_reflection(p.ggx, p.wo, wi, p.it.material->masking) : 0.0f,
      0.0f,
      coat_glossy(p.layer, p.wo, wi, p.it.material->masking)};
  diffuse_fade(p, wi, cos_l, &t);
  return t;
}

// A lamp's terms its ray visibility hides: the diffuse ones when it lights no diffuse
// surface (`diffuse` false), the specular ones (Phong, coat, glossy, and the sheen, a
// glossy closure in Cycles) when no glossy one shows it (`glossy` false).
inline void unseen(bool diffuse, bool glossy, LightTerms* t) {
  if (!diffuse) t->fade = t->loss = 0.0f;
  if (!glossy) t->lobe = t->coat = t->glossy = t->sheen = t->layer = 0.0f;
}

// An emitter feeler's MIS weights (mis.h, LobeWeights) on its glossy lobes' shares of t,
// each lobe's its own: the base's GGX lobe, the specular layer's and a rough coat's.
inline void weigh_glossy(const ShadingPoint& p, const Vec3& wi, const LobeWeights& mis,
                         LightTerms* t) {
  t->glossy *= mis.base;
  t->layer *= mis.layer;
  if (p.coat.alpha > 0.0f && t->coat > 0.0f) {
    const float glossy = coat_glossy(p.coat, p.wo, wi, p.it.material->masking);
    t->coat = std::max(0.0f, t->coat - (1.0f - mis.coat) * glossy);
  }
}

// A light sample's share of the local term if all of its `irradiance` arrives:
//   (1 - coat) * (kd/pi + ks*(f+2)/(2pi)*(v.r)^f) * E * (l.n) + coat_highlight * E,
// with the diffuse lobe's fade and loss and the GGX lobe's share.
inline Color unshadowed(const ShadingPoint& p, const LightTerms& t, const Color& irradiance) {
  const SurfaceParams& surface = p.surface;
  const Color brdf = surface.diffuse * (kInvPi * t.fade) + p.multiscatter * t.loss +
                     surface.specular * (p.phong_norm * t.lobe);
  Color share = (t.lit * brdf + Color(t.coat)) * irradiance;
  if (p.alpha > 0.0f) share += surface.reflectivity * p.energy * t.glossy * irradiance;
  if (t.sheen > 0.0f) share += sheen_share(p, t) * irradiance;
  if (t.layer > 0.0f) share += p.layer_tint * t.layer * irradiance;
  return share;
}

}  // namespace whitted
