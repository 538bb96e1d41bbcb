// Where a hit's glossy rays (glossy.h) and its emitter feelers (lights.h) are drawn from:
// n x n strata of [0, 1)^2, one point in each.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "integrator/whitted.h"

namespace whitted {

// The n x n strata of [0, 1)^2 a glossy lobe's rays (or the emitter feelers) are drawn
// from: n = Glossy Samples (Emitter Samples) at a branch's first glossy hit and before,
// 1 after; one point in each stratum, placed by a hash of the branch's seed and depth,
// the stratum and `salt` (which tells the lobes of one hit apart). Jittered apart,
// not shifted together: a lattice shifted as one errs by O(1/n) (its offset from the
// cell centres), jittered strata by O(n^-1.5) (2% against 0.6% on a lit floor under a
// quad emitter at n = 16, mesh_light_test.cpp).
struct Strata {
  int n;
  float share;  // 1 / n^2: each ray's share of the lobe
  uint32_t base;

  static int side(const NodeState& state, int samples) { return state.glossy == 0 ? samples : 1; }
  Strata(const NodeState& state, int samples, uint32_t salt)
      : n(side(state, samples)),
        share(1.0f / static_cast<float>(n * n)),
        base(hash3(state.seed, static_cast<uint32_t>(state.depth), salt)) {}
  int count() const { return n * n; }
  // Stratum k's point.
  glm::vec2 point(int k) const { return jittered_stratum(base, 0x9e3779b9u, k, n); }
};

}  // namespace whitted
