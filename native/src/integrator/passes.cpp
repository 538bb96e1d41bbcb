#include "integrator/passes.h"

#include <algorithm>
#include <cmath>

#include "integrator/glossy.h"
#include "integrator/split.h"
#include "integrator/whitted.h"

namespace whitted {
void SampleRecord::add(const SampleRecord& s, uint32_t passes) {
  if ((passes & kLightPasses) != 0) {
    emission += s.emission;
    environment += s.environment;
    diffuse_direct += s.diffuse_direct;
    diffuse_indirect += s.diffuse_indirect;
    diffuse_color += s.diffuse_color;
    glossy_direct += s.glossy_direct;
    glossy_indirect += s.glossy_indirect;
    glossy_color += s.glossy_color;
    transmission_indirect += s.transmission_indirect;
    transmission_color += s.transmission_color;
    volume_direct += s.volume_direct;
  }
  if ((passes & pass_bit(FilmPass::kContributions)) != 0) {
    for (size_t d = 0; d < contributions.size(); ++d) contributions[d] += s.contributions[d];
  }
  cut_weight += s.cut_weight;
  mist += s.mist;
  normal += s.normal;
  uv += s.uv;
  denoising_albedo += s.denoising_albedo;
  denoising_normal += s.denoising_normal;
  caught.with += s.caught.with;
  caught.without += s.caught.without;
  caught_coverage += s.caught_coverage;
}

void SampleRecord::take_first(const SampleRecord& s) {
  depth = s.depth;
  position = s.position;
  object_index = s.object_index;
  material_index = s.material_index;
  data_found = s.data_found;
}

void SampleRecord::scale(float w, uint32_t passes) {
  if ((passes & kLightPasses) != 0) {
    emission *= w;
    environment *= w;
    diffuse_direct *= w;
    diffuse_indirect *= w;
    diffuse_color *= w;
    glossy_direct *= w;
    glossy_indirect *= w;
    glossy_color *= w;
    transmission_indirect *= w;
    transmission_color *= w;
    volume_direct *= w;
  }
  if ((passes & pass_bit(FilmPass::kContributions)) != 0) {
    for (Color& c : contributions) c *= w;
  }
  cut_weight *= w;
  mist *= w;
  normal *= w;
  uv *= w;
  denoising_albedo *= w;
  denoising_normal *= w;
  caught.with *= w;
  caught.without *= w;
  caught_coverage *= w;
}

PassRecorder::PassRecorder(const WhittedIntegrator& integrator, SampleRecord* record)
    : scene_(integrator.scene()),
      settings_(integrator.settings()),
      camera_(integrator.camera()),
      record_(record),
      light_((settings_.passes & kLightPasses) != 0),
      data_((settings_.passes & kDataPasses) != 0),
      contributions_((settings_.passes & pass_bit(FilmPass::kContributions)) != 0),
      cut_weight_((settings_.passes & pass_bit(FilmPass::kCutWeight)) != 0),
      guides_((settings_.passes & kGuidePasses) != 0),
      caught_((settings_.passes & pass_bit(FilmPass::kShadowCatcher)) != 0) {
  // A camera ray seeks its guides, with all of the sample's tint and share.
  if (guides_) path_ = {IndirectPass::kNone, Color(1.0f), 1.0f};
}

void PassRecorder::camera_surface(const Interaction& it, const SurfaceParams& surface,
                                  const Vec3& normal, float share) const {
  // Distances from the camera: along its view axis (Depth; a panorama has none, so from
  // its position, as Cycles), and from its position (Mist, as Cycles; an orthographic
  // camera has no position, so the view axis).
  const Vec3 eye(camera_.to_world[3]);
  const Vec3 forward = -glm::normalize(Vec3(camera_.to_world[2]));
  const float z = camera_.projection == Projection::kPanoramic
                      ? glm::length(it.position - eye)
                      : glm::dot(it.position - eye, forward);
  if ((settings_.passes & pass_bit(FilmPass::kMist)) != 0) {
    const float distance =
        camera_.projection != Projection::kOrthographic ? glm::length(it.position - eye) : z;
    // Mist: 0 at the start distance, 1 at start + depth, shaped by the falloff exponent;
    // what the film shows is 1 - the sum of (1 - mist) * coverage.
    const float reach =
        settings_.mist_depth > 0.0f
            ? std::clamp((distance - settings_.mist_start) / settings_.mist_depth, 0.0f, 1.0f)
            : (distance >= settings_.mist_start ? 1.0f : 0.0f);
    const float mist = std::pow(reach, settings_.mist_falloff);
    record_->mist += (1.0f - mist) * share;
  }
  if (record_->data_found || surface.alpha < settings_.pass_alpha_threshold) return;
  record_->data_found = true;
  record_->depth = z;
  record_->position = it.position;
  record_->normal = normal;
  if ((settings_.passes & pass_bit(FilmPass::kUV)) != 0) {
    record_->uv = Vec3(scene_.texture_point(it).uv, 0.0f);
  }
  record_->object_index = scene_.instances[it.instance].info.pass_index;
  record_->material_index = static_cast<float>(it.material->pass_index);
}

void PassRecorder::local(const ShadingPoint& p, int depth, const Color& emission,
                         const Color& ambient, const Color& total) {
  if (contributions_) {
    record_->contributions[static_cast<size_t>(std::min(depth, settings_.contribution_depth))] +=
        throughput_ * total;
  }
  if (depth == 0 && light_) {
    // kd and ks, under a coat times what it lets through; the coat's highlight is specular.
    const Color diffuse_color = p.base * p.surface.diffuse;
    const Color specular_color =
        p.base * (p.surface.specular + p.surface.sheen) + Color(p.coat.highlight);
    record_->emission += throughput_ * emission;
    record_->diffuse_direct += throughput_ * diffuse_;
    record_->diffuse_indirect += throughput_ * ambient;
    record_->diffuse_color += throughput_ * diffuse_color;
    record_->glossy_direct += throughput_ * specular_;
    record_->glossy_color += throughput_ * specular_color;
  } else if (Color* indirect = indirect_field(); indirect != nullptr) {
    *indirect += throughput_ * total;  // deeper nodes: the camera hit's indirect light
  }
  diffuse_ = Color(0.0f);
  specular_ = Color(0.0f);
}

void PassRecorder::split(const ShadingPoint& p, const Split& split, bool glossy) {
  if (!(path_.guide_share > 0.0f)) return;  // written, or not kept
  // The surface's lobes as Cycles' closures: rough (the diffuse, the Phong and coat
  // highlights, the reflection and the refraction where drawn from a lobe rougher than
  // kSharpGuideAlpha) or near-specular (the others), each weighing its colour.
  Color rough_reflection(0.0f);
  Color sharp_reflection(0.0f);
  for (const Lobe& lobe : reflection_lobes(p, split, glossy)) {
    (lobe.ggx.alpha() > kSharpGuideAlpha ? rough_reflection : sharp_reflection) += lobe.sigma;
  }
  const bool rough_refraction = glossy && p.alpha > kSharpGuideAlpha;
  const Color rough = p.base * (p.surface.diffuse + p.surface.specular + p.surface.sheen) +
                      Color(p.coat.highlight) + rough_reflection +
                      (rough_refraction ? split.sigma_t : Color(0.0f));
  const Color sharp = sharp_reflection + (rough_refraction ? Color(0.0f) : split.sigma_t);
  const Color emission = glm::clamp(p.surface.emission, 0.0f, 1.0f);
  const float rough_weight = mean_component(rough);
  const float sharp_weight = mean_component(sharp);
  // Cycles waits for the next bounce where three quarters or more of the weight is
  // near-specular.
  if (!(sharp_weight > 0.0f) || 4.0f * rough_weight > rough_weight + sharp_weight) {
    record_->denoising_albedo += path_.guide_tint * glm::min(rough + emission, Color(1.0f));
    record_->denoising_normal += path_.guide_share * p.ns;
    path_.guide_tint = Color(0.0f);
    path_.guide_share = 0.0f;
    return;
  }
  // Followed: each branch traced takes the tint of its weight (PassRecorder::path) and
  // its share of the normal as a fraction of the branches' sum (the rays drawn from a
  // lobe sum to about their sigma; a rough lobe, under a quarter of the weight, is
  // followed too, as Cycles' path may sample it).
  record_->denoising_albedo += path_.guide_tint * emission;
  path_.guide_share /= mean_component(split.sigma_r + split.sigma_t);
}

FeelerPasses PassRecorder::queued(const ShadingPoint& p, const LightTerms& t,
                                  const Color& irradiance, int depth) const {
  FeelerPasses out;
  if (depth == 0 && light_) {
    shares(p, t, irradiance, &out.diffuse, &out.specular);
    out.diffuse *= throughput_;
    out.specular *= throughput_;
  }
  if (contributions_) out.bin = std::min(depth, settings_.contribution_depth);
  if (depth > 0 && light_) out.indirect = path_.indirect;
  return out;
}

void FeelerPasses::arrived(const Color& transmittance, const Color& light,
                           SampleRecord* record) const {
  record->diffuse_direct += diffuse * transmittance;
  record->glossy_direct += specular * transmittance;
  if (bin >= 0) record->contributions[static_cast<size_t>(bin)] += light;
  if (indirect == IndirectPass::kGlossy) record->glossy_indirect += light;
  if (indirect == IndirectPass::kTransmission) record->transmission_indirect += light;
}

Color* PassRecorder::indirect_field() const {
  if (!light_) return nullptr;
  switch (path_.indirect) {
    case IndirectPass::kGlossy:
      return &record_->glossy_indirect;
    case IndirectPass::kTransmission:
      return &record_->transmission_indirect;
    case IndirectPass::kNone:
      break;
  }
  return nullptr;
}

PassRecorder::Scope PassRecorder::reflected(int depth, const Color& sigma_r) {
  if (depth > 0) return {this, throughput_, path_};
  if (light_) record_->glossy_color += throughput_ * sigma_r;
  return {this, throughput_, {IndirectPass::kGlossy, path_.guide_tint, path_.guide_share}};
}

PassRecorder::Scope PassRecorder::refracted(int depth, const Color& sigma_t) {
  if (depth > 0) return {this, throughput_, path_};
  if (light_) record_->transmission_color += throughput_ * sigma_t;
  return {this, throughput_, {IndirectPass::kTransmission, path_.guide_tint, path_.guide_share}};
}

void PassRecorder::segment_light(int depth, const SegmentLight& light) const {
  if (contributions_) {
    record_->contributions[static_cast<size_t>(std::min(depth, settings_.contribution_depth))] +=
        throughput_ * light.radiance();
  }
  if (depth == 0 && light_) {
    record_->emission += throughput_ * light.emitted;
    record_->volume_direct += throughput_ * light.scattered;
  } else if (Color* indirect = indirect_field(); indirect != nullptr) {
    *indirect += throughput_ * light.radiance();
  }
}

void PassRecorder::escaped(Node /*node*/, int depth, float behind, const Color& through,
                           const Color& world, bool shown) const {
  // A transparent film leaves the world out of Combined but, as in Cycles, not out of
  // the Environment pass, so it can be put back in the compositor.
  const Color throughput = throughput_ * behind * through;
  if (shown && contributions_) {
    record_->contributions[static_cast<size_t>(std::min(depth, settings_.contribution_depth))] +=
        throughput * world;
  }
  if (depth == 0 && light_) {
    record_->environment += throughput * world;
  } else if (Color* indirect = indirect_field(); indirect != nullptr && shown) {
    *indirect += throughput * world;
  }
  // The world where it shows, as Cycles writes the background into its albedo.
  if (shown) {
    record_->denoising_albedo += path_.guide_tint * behind * glm::clamp(world, 0.0f, 1.0f);
  }
}

void PassRecorder::lamps(int depth, float behind, const Color& through,
                         const Color& radiance) const {
  const Color seen = throughput_ * behind * through * radiance;
  if (contributions_) {
    record_->contributions[static_cast<size_t>(std::min(depth, settings_.contribution_depth))] +=
        seen;
  }
  if (depth == 0 && light_) {
    record_->emission += seen;
  } else if (Color* indirect = indirect_field(); indirect != nullptr) {
    *indirect += seen;
  }
}

void PassRecorder::cut(const Ray& /*ray*/, int /*depth*/, TreeRayKind /*kind*/, const Color& weight,
                       float share, TreeCut /*why*/) const {
  if (cut_weight_) record_->cut_weight += mean_component(throughput_ * weight * share);
}

}  // namespace whitted
