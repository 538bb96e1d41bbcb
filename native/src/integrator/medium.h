// The media a ray is inside, for nested dielectrics (water in a glass, overlapping
// glass, the camera inside glass).
//
// The rule (Schmidt & Budge 2002, "Simple Nested Dielectrics in Ray Traced Images"):
// where objects overlap, the medium of higher priority owns the overlap; among equal
// priorities the one entered last does. A ray is in its current medium: the one that
// owns the point. Crossing a surface whose medium does not become or stop being the
// current one is a false interface: the ray goes on straight and unshaded. Priorities
// default to 0, so by default the medium entered last is the current one.
//
// The stack also holds the bounds of media without a surface (a fog box, entered and left
// by kernel.h's trace()): they own no point and bend no ray, so the rule above passes them
// by; the media a point is inside are summed (transmittance.h's medium_at).
#pragma once

#include <array>
#include <cstdint>

#include "scene/scene.h"

namespace whitted {

class MediumStack {
 public:
  static constexpr int kCapacity = 8;  // deeper nesting keeps the 8 entered last

  // Material index of the current medium, or -1 for the surrounding air (IOR 1).
  int32_t current() const {
    int best = -1;
    for (int i = 0; i < size_; ++i) {
      if (entries_[i].bound) continue;
      if (best < 0 || entries_[i].priority >= entries_[best].priority) best = i;
    }
    return best < 0 ? -1 : static_cast<int32_t>(entries_[best].material);
  }
  bool empty() const { return size_ == 0; }

  // Into a dielectric (glass, water) of `priority`, through the mesh of `instance`.
  void enter(uint32_t material, uint32_t instance, int32_t priority) {
    push({material, instance, priority, false});
  }
  // Into the bounds of a medium without a surface: the mesh of `instance` (what a
  // heterogeneous medium's program reads its object coordinates of).
  void enter_bound(uint32_t material, uint32_t instance) { push({material, instance, 0, true}); }

  // The entries, oldest first: material(i) entered through instance(i) for i < size(), a
  // bound where is_bound(i).
  int size() const { return size_; }
  uint32_t material(int i) const { return entries_[static_cast<size_t>(i)].material; }
  uint32_t instance(int i) const { return entries_[static_cast<size_t>(i)].instance; }
  bool is_bound(int i) const { return entries_[static_cast<size_t>(i)].bound; }

  // Removes the most recent entry of `material`; false if the ray was not inside it.
  bool leave(uint32_t material) {
    for (int i = size_ - 1; i >= 0; --i) {
      if (entries_[i].material != material) continue;
      for (int j = i + 1; j < size_; ++j) entries_[j - 1] = entries_[j];
      --size_;
      return true;
    }
    return false;
  }

 private:
  struct Entry {
    uint32_t material;
    uint32_t instance;
    int32_t priority;
    bool bound;  // a medium's bound (enter_bound), not a dielectric
  };
  void push(const Entry& entry) {
    if (size_ == kCapacity) {
      for (int i = 1; i < kCapacity; ++i) entries_[i - 1] = entries_[i];
      --size_;
    }
    entries_[size_++] = entry;
  }
  std::array<Entry, kCapacity> entries_{};
  int size_ = 0;
};

// IOR of a medium (-1 is the surrounding air): its material's constant ior, since a
// program's ior belongs to a hit, not to the volume behind it.
inline float ior_of(const CompiledScene& scene, int32_t medium) {
  return medium < 0 ? 1.0f : scene.materials[static_cast<size_t>(medium)].ior;
}

// The interface step's answer: what lies beyond a transmissive surface for the refracted
// ray (the rule above).
struct Crossing {
  MediumStack media;             // the media the refracted ray is inside
  float eta = 1.0f;              // eta_incident / eta_transmitted
  bool false_interface = false;  // the current medium stays what it was: go on straight
};

// The interface step: which media lie beyond a transmissive surface (the ray enters
// its medium or leaves it), the ratio of indices across it, and whether it is a false
// interface, inside a medium of higher priority. Elsewhere (and where the kernel traces
// no refraction) the media stay as they are. Always inlined into the step, as
// split_weights (split.h says why).
[[gnu::always_inline]] inline Crossing crossing(const CompiledScene& scene, bool refraction,
                                                const Interaction& it, const SurfaceParams& surface,
                                                bool entering, const MediumStack& media) {
  Crossing beyond{media};
  const Material& m = *it.material;
  if (!refraction || !m.transmissive()) return beyond;
  const int32_t from = media.current();
  if (entering) {
    beyond.false_interface = from >= 0 && m.priority < scene.materials[from].priority;
    beyond.media.enter(it.material_index, it.instance, m.priority);
    beyond.eta = ior_of(scene, from) / surface.ior;
  } else if (beyond.media.leave(it.material_index)) {
    beyond.false_interface = from != static_cast<int32_t>(it.material_index);
    beyond.eta = surface.ior / ior_of(scene, beyond.media.current());
  } else {
    // Leaving a medium it never entered (flipped normals, an open mesh): out into the
    // current medium, as a renderer without media lists would.
    beyond.eta = surface.ior / ior_of(scene, from);
  }
  return beyond;
}

// What fills a point, per unit length: the sum of the media it is inside, as Cycles sums
// the closures of overlapping volumes; a glass ball in fog is filled with the fog (and
// its own volume, if it has one). Those are the world's volume (everywhere), every medium
// whose bounds enclose the point and the dielectric owning it (MediumStack::current, the
// nested-dielectric rule). Several scatterings keep one Henyey-Greenstein lobe of their mean
// anisotropy weighted by their scattering, as the exporter does within a material
// (export/volume.py). read(material, instance) gives each one's coefficients.
template <class Read>
Medium sum_media(const CompiledScene& scene, const MediumStack& media, const Read& read) {
  Medium out;
  float weighed = 0.0f;  // sum of the scatterings' means, weighing the anisotropies
  const auto add = [&](const Medium& m) {
    out.absorption += m.absorption;
    out.scattering += m.scattering;
    out.emission += m.emission;
    const float w = mean_component(m.scattering);
    out.anisotropy += w * m.anisotropy;
    weighed += w;
  };
  const auto entry = [&](uint32_t material, uint32_t instance) {
    if (scene.materials[material].participating()) add(read(material, instance));
  };
  if (scene.world_medium.participating()) {
    add({scene.world_medium.volume_absorption, scene.world_medium.volume_scattering,
         scene.world_medium.volume_emission, scene.world_medium.volume_anisotropy});
  }
  int owner = -1;  // the dielectric owning the point, once
  const int32_t current = media.current();
  for (int i = 0; i < media.size(); ++i) {
    if (media.is_bound(i)) {
      entry(media.material(i), media.instance(i));
    } else if (static_cast<int32_t>(media.material(i)) == current) {
      owner = i;
    }
  }
  if (owner >= 0) entry(media.material(owner), media.instance(owner));
  out.anisotropy = weighed > 0.0f ? out.anisotropy / weighed : 0.0f;
  return out;
}

// What a ray's segment inside media (volume.h, heterogeneous.h) sends back along the ray,
// seen from the segment's start, and lets through: the media's own emission, the light of
// the lamps, emitters and world they scatter once towards the ray, and exp(-optical depth).
struct SegmentLight {
  Color emitted{0.0f};
  Color scattered{0.0f};
  Color transmittance{1.0f};
  int steps = 0;  // points a heterogeneous medium's program ran at (0: constant media)
  Color radiance() const { return emitted + scattered; }
};

// Whether some medium a point is inside is driven by its program (Material::heterogeneous):
// then what fills it is read point by point (march.h), else medium_at(scene, media) is it.
inline bool heterogeneous(const CompiledScene& scene, const MediumStack& media) {
  bool found = false;
  for (int i = 0; i < media.size(); ++i) {
    found |= scene.materials[media.material(i)].heterogeneous();
  }
  return found;
}

// What fills a point of media of constant coefficients: their sum (a heterogeneous one's
// constants left out: march.h reads those point by point).
inline Medium medium_at(const CompiledScene& scene, const MediumStack& media) {
  return sum_media(scene, media, [&](uint32_t material, uint32_t) {
    const Material& m = scene.materials[material];
    if (m.heterogeneous()) return Medium{};
    return Medium{m.volume_absorption, m.volume_scattering, m.volume_emission, m.volume_anisotropy};
  });
}

// What fills point x of `ray`: the sum, each program run at x (CompiledScene::medium).
inline Medium medium_at(const CompiledScene& scene, const MediumStack& media, const Vec3& x,
                        const Ray& ray, const RayContext& context) {
  return sum_media(scene, media, [&](uint32_t material, uint32_t instance) {
    return scene.medium(material, instance, x, ray, context);
  });
}

}  // namespace whitted
