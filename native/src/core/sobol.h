// Owen-scrambled Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling",
// JCGT 9(4)): the Monte Carlo camera samples' draws, each 2D draw (film, lens, a lamp's
// feeler, a glossy lobe, an emitter feeler) stratified across a pixel's samples.
//
// The first two Sobol dimensions form a (0, 2)-sequence: every aligned block of 2^m
// consecutive points is a (0, m, 2)-net, one point in each elementary interval of area
// 2^-m. Each dimension is Owen-scrambled by a hash (each bit of a coordinate, read as a
// binary fraction, flipped by a function of the seed and the bits above it), which keeps
// that property and makes the points of different seeds independent; and the index is
// shuffled the same way (each bit of it flipped by a function of the bits above it),
// which maps aligned blocks of indices onto aligned blocks, so that every power-of-two
// prefix of a pixel's samples is still a net while two draws of the same sample with
// different seeds are not paired alike.
#pragma once

#include <algorithm>
#include <cstdint>

#include "core/math.h"

namespace whitted {

// x with its 32 bits in reverse order.
inline uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}

// A bijection of 32-bit integers in which each bit is flipped by a function of `seed` and
// the bits below it only (Laine and Karras 2011's form, with Burley's constants): each
// step is an xor with a multiple by an even number, an addition or a multiplication by an
// odd number, none of which carries information downwards.
inline uint32_t scramble_upwards(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Nested uniform (Owen) scrambling of x read as a binary fraction, its top bit first: each
// bit flipped by a function of `seed` and the bits above it.
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(scramble_upwards(reverse_bits(x), seed));
}

// Sobol dimension 0 (van der Corput) and 1 (the Pascal matrix mod 2) of point `index`, as
// binary fractions in 32 bits.
inline uint32_t sobol_0(uint32_t index) {
  return reverse_bits(index);
}
inline uint32_t sobol_1(uint32_t index) {
  uint32_t out = 0;
  // The direction numbers: v_1 = 1/2, v_{k+1} = v_k xor v_k / 2.
  for (uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1) {
    if ((index & 1u) != 0) out ^= v;
  }
  return out;
}

// Point `index` of the sequence `seed` chooses, in [0, 1)^2: the index shuffled, then its
// two Sobol coordinates each Owen-scrambled, each by its own hash of the seed.
inline glm::vec2 sobol_point(uint32_t index, uint32_t seed) {
  const uint32_t i = owen_scramble(index, hash3(seed, 0x5b0du, 0x1u));
  return {unit_float(owen_scramble(sobol_0(i), hash3(seed, 0x5b0du, 0x2u))),
          unit_float(owen_scramble(sobol_1(i), hash3(seed, 0x5b0du, 0x3u)))};
}

// Its 1D counterpart (a shutter time): the first coordinate alone.
inline float sobol_value(uint32_t index, uint32_t seed) {
  const uint32_t i = owen_scramble(index, hash3(seed, 0x5b0du, 0x1u));
  return unit_float(owen_scramble(sobol_0(i), hash3(seed, 0x5b0du, 0x2u)));
}

// Whether sample `index` of a pixel is in class A, the half of its samples whose mean
// noise-driven sampling compares with the whole's (Film): as Cycles' sample_is_class_A
// (after Christensen et al. 2018, section 10.2.1), the parity of its odd-numbered bits.
// Each aligned block of 4 samples has 2 in each class, so a power-of-two prefix's class
// A is itself spread over the pixel.
inline bool class_a(uint32_t index) {
  return (__builtin_popcount(index & 0xaaaaaaaau) & 1) != 0;
}

// How many of samples 0 .. n - 1 are in class A.
inline uint32_t class_a_count(uint32_t n) {
  const uint32_t rest = n % 4;
  const uint32_t last =
      rest == 0 ? 0 : (class_a(n - rest) ? std::min(rest, 2u) : rest - std::min(rest, 2u));
  return 2 * (n / 4) + last;
}

}  // namespace whitted
