// Where a hit's glossy rays (glossy.h), its emitter feelers and its lamps' feelers
// (lights.h) are drawn from: points of [0, 1)^2.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/sobol.h"
#include "integrator/whitted.h"

namespace whitted {

// The Sobol points of one node's chain in one dimension (a lamp's feelers, a glossy lobe,
// the emitter feelers), where the camera samples are Monte Carlo ones (jittered_samples,
// settings.h): the node's `count` points k are points index * count + k of the pixel's
// Owen-scrambled Sobol sequence of this depth and `salt` (NodeState::pixel, index;
// core/sobol.h), so that the draws of all of a pixel's camera samples are stratified
// together, not only each one's `count`.
struct ChainPoints {
  uint32_t seed;   // the sequence's
  uint32_t first;  // the index of point 0 in the sequence

  ChainPoints(const NodeState& state, uint32_t salt, int count)
      : seed(hash3(state.pixel, static_cast<uint32_t>(state.depth), salt)),
        first(state.index * static_cast<uint32_t>(count)) {}
  // Point k's index in the pixel's sequence: the index its ray's branch carries.
  uint32_t index(int k) const { return first + static_cast<uint32_t>(k); }
  // Point k.
  glm::vec2 point(int k) const { return sobol_point(index(k), seed); }
};

// The n x n points of [0, 1)^2 a glossy lobe's rays (or the emitter feelers) are drawn
// from: n = Glossy Samples (Emitter Samples) at a branch's first glossy hit and before,
// 1 after; `salt` tells the lobes of one hit apart.
// Monte Carlo camera samples (`sobol`: jittered_samples, settings.h): the chain's points
// (ChainPoints).
// Otherwise (the regular grid, Whitted's adaptive corners) one point in each stratum,
// placed by a hash of the branch's seed and depth, the stratum and `salt`. Jittered apart,
// not shifted together: a lattice shifted as one errs by O(1/n) (its offset from the
// cell centres), jittered strata by O(n^-1.5) (2% against 0.6% on a lit floor under a
// quad emitter at n = 16, mesh_light_test.cpp).
struct Strata {
  int n;
  float share;  // 1 / n^2: each ray's share of the lobe
  bool sobol;
  ChainPoints chain;  // its indices always; its points with `sobol`
  uint32_t strata;    // the strata's hash, without `sobol`

  static int side(const NodeState& state, int samples) { return state.glossy == 0 ? samples : 1; }
  Strata(const NodeState& state, int samples, uint32_t salt, bool sobol_points)
      : n(side(state, samples)),
        share(1.0f / static_cast<float>(n * n)),
        sobol(sobol_points),
        chain(state, salt, n * n),
        strata(sobol_points ? 0u : hash3(state.seed, static_cast<uint32_t>(state.depth), salt)) {}
  int count() const { return n * n; }
  // Point k's index in the pixel's sequence: the index its ray's branch carries.
  uint32_t index(int k) const { return chain.index(k); }
  // Point k.
  glm::vec2 point(int k) const {
    return sobol ? chain.point(k) : jittered_stratum(strata, 0x9e3779b9u, k, n);
  }
};

}  // namespace whitted
