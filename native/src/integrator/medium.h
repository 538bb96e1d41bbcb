// The media a ray is inside, for nested dielectrics (water in a glass, overlapping
// glass, the camera inside glass).
//
// The rule: the medium a ray is in is the one it entered last. Entering a surface
// switches from that medium to the surface's; leaving the current medium returns to the
// one entered before it; leaving a medium that is not the current one (where two
// objects overlap) is a false interface: the ray goes on straight and unshaded.
#pragma once

#include <array>
#include <cstdint>

namespace whitted {

class MediumStack {
 public:
  static constexpr int kCapacity = 8;  // deeper nesting keeps the innermost 8

  // Material index of the current medium, or -1 for the surrounding air (IOR 1).
  int32_t current() const { return size_ == 0 ? -1 : static_cast<int32_t>(media_[size_ - 1]); }
  bool empty() const { return size_ == 0; }

  void enter(uint32_t material) {
    if (size_ == kCapacity) {
      for (int i = 1; i < kCapacity; ++i) media_[i - 1] = media_[i];
      --size_;
    }
    media_[size_++] = material;
  }

  // Removes the most recent entry of `material`; false if the ray was not inside it.
  bool leave(uint32_t material) {
    for (int i = size_ - 1; i >= 0; --i) {
      if (media_[i] != material) continue;
      for (int j = i + 1; j < size_; ++j) media_[j - 1] = media_[j];
      --size_;
      return true;
    }
    return false;
  }

 private:
  std::array<uint32_t, kCapacity> media_{};
  int size_ = 0;
};

}  // namespace whitted
