// The media a ray is inside, for nested dielectrics (water in a glass, overlapping
// glass, the camera inside glass).
//
// The rule (Schmidt & Budge 2002, "Simple Nested Dielectrics in Ray Traced Images"):
// where objects overlap, the medium of higher priority owns the overlap; among equal
// priorities the one entered last does. A ray is in its current medium: the one that
// owns the point. Crossing a surface whose medium does not become or stop being the
// current one is a false interface: the ray goes on straight and unshaded. Priorities
// default to 0, so by default the medium entered last is the current one.
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
    const int owner = current_entry();
    return owner < 0 ? -1 : static_cast<int32_t>(entries_[owner].material);
  }
  // The instance whose mesh bounds the current medium (what a heterogeneous medium's
  // program reads its object coordinates of); 0 in the surrounding air.
  uint32_t current_instance() const {
    const int owner = current_entry();
    return owner < 0 ? 0 : entries_[owner].instance;
  }
  bool empty() const { return size_ == 0; }

  // Entering the medium of `material` through the mesh of `instance`.
  void enter(uint32_t material, uint32_t instance, int32_t priority) {
    if (size_ == kCapacity) {
      for (int i = 1; i < kCapacity; ++i) entries_[i - 1] = entries_[i];
      --size_;
    }
    entries_[size_++] = {material, instance, priority};
  }

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
  };
  // The entry that owns the point (the rule above), -1 for none.
  int current_entry() const {
    int best = -1;
    for (int i = 0; i < size_; ++i) {
      if (best < 0 || entries_[i].priority >= entries_[best].priority) best = i;
    }
    return best;
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

}  // namespace whitted
