// A hit as the Whitted step shades it, and one light sample's terms there: what the
// kernel (kernel.h, local.h) computes, and what its recorders (kernel_recorder.h) read of it.
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "integrator/lobes.h"
#include "scene/microfacet.h"
#include "scene/scene.h"

namespace whitted {

// The surface, its normals turned to face the ray, the direction back along the ray,
// and what the local term reads of them.
struct ShadingPoint {
  const Interaction& it;
  const SurfaceParams& surface;
  Vec3 ng;      // geometric normal, facing the ray
  Vec3 ns;      // shading normal, facing the ray (never away from ng)
  Vec3 smooth;  // the interpolated normal on the ray's side (diffuse_shadowing)
  Vec3 wo;      // back along the ray
  Coat coat;
  float base;          // what reaches the base: (1 - coat.cover) (1 - layer.cover), or 1 if
                       // the layers are not layered (Material::coat_layered)
  float phong_norm;    // (f+2)/(2pi), the normalisation of the Phong lobe
  Color multiscatter;  // kOrenNayarEnergy: the diffuse lobe's multiple scattering, per
                       // unit LightTerms::loss (0 for the other diffuse models)
  float alpha;         // GGX alpha of the reflection lobe; 0: a mirror (microfacet.h)
  Color energy;        // the lobe's multiple-scattering scale (Material::multiscatter), or 1
  GgxLobe ggx;         // the reflection lobe about ns: alpha, or anisotropic along the tangent
  Coat layer;          // the base's specular layer beneath the coat (layer_of), its lobe ggx's
  Color layer_tint;    // its weight per unit layer.mirror, seen through the coat
};

// One light sample's Phong terms at a shading point, per unit irradiance and unshadowed:
// the pieces the sum, the passes and the inspector multiply out.
struct LightTerms {
  float lit;     // (1 - coat) * max(0, n.l): the light the base receives
  float fade;    // diffuse_fade: kd/pi * fade + multiscatter * loss is the diffuse lobe
  float loss;    // what a kOrenNayarEnergy lobe's single scattering loses of this light
  float lobe;    // (v.r)^f: ks * phong_norm * lobe is the Phong lobe
  float coat;    // the coat's highlight
  float glossy;  // (1 - coat) * the GGX lobe times (l.n): reflectivity * glossy is its share
  float sheen;   // the velvet lobe's shape: sheen_share
  float layer;   // the specular layer's lobe (coat_glossy of ShadingPoint::layer): layer_tint *
                 // layer is its share
};

// A light sample's MIS weights (mis.h) on the share of each glossy lobe the reflected
// term draws rays from (glossy.h): 1 where that lobe sends none.
struct LobeWeights {
  float coat = 1.0f;
  float layer = 1.0f;
  float base = 1.0f;
  bool weighs() const { return coat < 1.0f || layer < 1.0f || base < 1.0f; }
};

// The geometric and shading normals of a hit turned to face the ray; a shading normal
// cannot face away.
inline void facing_normals(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
                           Vec3* ng, Vec3* ns) {
  // Entering or leaving is decided by the geometric normal, never the shading normal.
  const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
  *ng = entering ? it.geometric_normal : -it.geometric_normal;
  *ns = entering ? surface.normal : -surface.normal;
  if (glm::dot(*ns, *ng) <= 0.0f) *ns = *ng;
}

// The hit as the local term and the split of weights read it: normals facing the ray,
// the coat over the base.
inline ShadingPoint shading_point(const Ray& ray, const Interaction& it,
                                  const SurfaceParams& surface, bool entering) {
  Vec3 ng;
  Vec3 ns;
  facing_normals(ray, it, surface, &ng, &ns);
  const Vec3 wo = -ray.direction;
  const Coat coat =
      coat_of(surface, wo, ng, entering, it.material->masking, it.material->coat_model);
  // A normal the material turned (a program's, or Cycles 3.x's lift) fades the diffuse
  // lobe towards the smooth surface's horizon, as Cycles does (diffuse_shadowing); one it
  // left as interpolated does not, even where facing_normals had to replace it.
  const Vec3 smooth = surface.normal == it.shading_normal        ? ns
                      : glm::dot(it.geometric_normal, ng) > 0.0f ? it.shading_normal
                                                                 : -it.shading_normal;
  const bool layered = it.material->coat_layered;
  const float phong_norm = (surface.shininess + 2.0f) * (0.5f * kInvPi);
  const Color multiscatter =
      it.material->diffuse_model == DiffuseModel::kOrenNayarEnergy
          ? surface.diffuse * oren_nayar_multiscatter(surface.diffuse, surface.diffuse_roughness,
                                                      glm::dot(ns, wo))
          : Color(0.0f);
  // A lobe rougher than a mirror is GGX's, for lights and rays (microfacet.h).
  const float alpha = surface.roughness * surface.roughness;
  const bool glossy = alpha >= kMirrorAlpha &&
                      (!is_black(surface.reflectivity) || !is_black(surface.transmissivity) ||
                       !is_black(surface.layer_reflectivity));
  // The multiple scattering of an anisotropic lobe is its round lobe's of the same mean
  // alpha, as Cycles takes it (alpha_x alpha_y = alpha^2).
  const Color energy =
      glossy && it.material->multiscatter
          ? ggx_multiscatter_scale(surface.reflectivity, glm::dot(ns, wo), surface.roughness)
          : Color(1.0f);
  float alpha_x = 0.0f;
  float alpha_y = 0.0f;
  if (glossy) ggx_anisotropic_alphas(alpha, surface.anisotropy, &alpha_x, &alpha_y);
  const GgxLobe ggx = alpha_x != alpha_y && surface.tangent != Vec3(0.0f)
                          ? GgxLobe(ns, surface.tangent, alpha_x, alpha_y)
                          : GgxLobe(ns, glossy ? alpha : 0.0f);
  // The specular layer beneath the coat: seen through what the coat lets pass, and the
  // base beneath both gets what each lets through.
  const Coat layer = layer_of(surface, wo, ns, glossy ? alpha : 0.0f, it.material->masking);
  float base = layered ? 1.0f - coat.cover : 1.0f;
  Color layer_tint(0.0f);
  if (layer.mirror > 0.0f) {
    layer_tint = (base / max_component(surface.layer_reflectivity)) * surface.layer_reflectivity;
    if (layered) base *= 1.0f - layer.cover;
  }
  return {it,
          surface,
          ng,
          ns,
          smooth,
          wo,
          coat,
          base,
          phong_norm,
          multiscatter,
          glossy ? alpha : 0.0f,
          energy,
          ggx,
          layer,
          layer_tint};
}

// A light sample's share through the sheen lobe, per unit of what arrives: the velvet
// lobe weighted by the sheen colour, kd/pi's place taken by sheen/pi.
inline Color sheen_share(const ShadingPoint& p, const LightTerms& t) {
  return p.surface.sheen * (t.lit * kInvPi * t.sheen);
}

}  // namespace whitted
