// Where a hit's glossy rays (glossy.h) and its emitter feelers (lights.h) are drawn from:
// n x n points of [0, 1)^2.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/sobol.h"
#include "integrator/whitted.h"

namespace whitted {

// The n x n points of [0, 1)^2 a glossy lobe's rays (or the emitter feelers) are drawn
// from: n = Glossy Samples (Emitter Samples) at a branch's first glossy hit and before,
// 1 after; `salt` tells the lobes of one hit apart.
// Monte Carlo camera samples (`sobol`: jittered_samples, settings.h): point k is point
// index * n^2 + k of the pixel's Owen-scrambled Sobol sequence of this depth and salt
// (NodeState::pixel, index; core/sobol.h), so that the draws of all of a pixel's camera
// samples are stratified together, not only each one's n x n.
// Otherwise (the regular grid, Whitted's adaptive corners) one point in each stratum,
// placed by a hash of the branch's seed and depth, the stratum and `salt`. Jittered apart,
// not shifted together: a lattice shifted as one errs by O(1/n) (its offset from the
// cell centres), jittered strata by O(n^-1.5) (2% against 0.6% on a lit floor under a
// quad emitter at n = 16, mesh_light_test.cpp).
struct Strata {
  int n;
  float share;  // 1 / n^2: each ray's share of the lobe
  bool sobol;
  uint32_t base;   // the sequence's seed, or the strata's hash
  uint32_t first;  // the index of point 0 in the sequence (Sobol)

  static int side(const NodeState& state, int samples) { return state.glossy == 0 ? samples : 1; }
  Strata(const NodeState& state, int samples, uint32_t salt, bool sobol_points)
      : n(side(state, samples)),
        share(1.0f / static_cast<float>(n * n)),
        sobol(sobol_points),
        base(hash3(sobol_points ? state.pixel : state.seed, static_cast<uint32_t>(state.depth),
                   salt)),
        first(state.index * static_cast<uint32_t>(n * n)) {}
  int count() const { return n * n; }
  // Point k's index in the pixel's sequence: the index its ray's branch carries.
  uint32_t index(int k) const { return first + static_cast<uint32_t>(k); }
  // Point k.
  glm::vec2 point(int k) const {
    return sobol ? sobol_point(index(k), base) : jittered_stratum(base, 0x9e3779b9u, k, n);
  }
};

}  // namespace whitted
