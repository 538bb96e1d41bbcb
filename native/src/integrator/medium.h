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

namespace whitted {

class MediumStack {
 public:
  static constexpr int kCapacity = 8;  // deeper nesting keeps the 8 entered last

  // Material index of the current medium, or -1 for the surrounding air (IOR 1).
  int32_t current() const {
    int best = -1;
    for (int i = 0; i < size_; ++i) {
      if (best < 0 || entries_[i].priority >= entries_[best].priority) best = i;
    }
    return best < 0 ? -1 : static_cast<int32_t>(entries_[best].material);
  }
  bool empty() const { return size_ == 0; }

  void enter(uint32_t material, int32_t priority) {
    if (size_ == kCapacity) {
      for (int i = 1; i < kCapacity; ++i) entries_[i - 1] = entries_[i];
      --size_;
    }
    entries_[size_++] = {material, priority};
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
    int32_t priority;
  };
  std::array<Entry, kCapacity> entries_{};
  int size_ = 0;
};

}  // namespace whitted
