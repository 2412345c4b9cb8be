// Low-discrepancy pixel samples: the first two dimensions of the Sobol sequence, Owen
// scrambled per pixel (docs/sampling.md).
//
// Why Sobol: its first two dimensions form a (0,2)-sequence in base 2, so the first 2^m
// points of any pixel put exactly one point in each of the 2^m elementary intervals of
// every shape (1 x 2^m, 2 x 2^(m-1), ..., 2^m x 1). A pixel's coverage of an edge is then
// integrated with error falling close to spp^-3/4 instead of the spp^-1/2 of independent
// samples. The sequence is progressive: sample k depends only on k, not on how many samples
// the pixel gets, so passes of one sample each (--reference) and a single pass agree.
//
// Why Owen scrambling: unscrambled, every pixel would use the same points and the error
// would form a pattern. A nested uniform (Owen) scramble, seeded by the pixel index, keeps
// the net property, makes each point uniform over the pixel (so the estimate stays
// unbiased) and makes pixels independent of each other.
//
// Everything is a pure function of (pixel, sample, dimension): no state, no allocation, so
// images stay bit-identical whatever the thread count, tile size or pass splitting.
#pragma once

#include <cstdint>

#include "renderer/sampling/random.h"

namespace prism {

// Reverses the 32 bits of x: the Sobol generator matrices below are written with the
// index's least significant bit feeding the output's most significant bit.
inline uint32_t reverse_bits32(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Sobol dimension 0: the generator matrix is the identity, i.e. the base-2 radical
// inverse (van der Corput). Returned as a 0.32 fixed-point fraction.
inline uint32_t sobol_dim0(uint32_t index) {
  return reverse_bits32(index);
}

// Sobol dimension 1: primitive polynomial x + 1 (degree 1, m_1 = 1). The direction-number
// recurrence m_k = 2 m_(k-1) xor m_(k-1) becomes, for v_k = m_k / 2^k as a 0.32 fraction,
// v_1 = 1/2 and v_(k+1) = v_k xor (v_k >> 1): the columns of the Pascal matrix mod 2.
// Index bit k (from the least significant) selects v_(k+1); the loop stops at the index's
// highest set bit, so small indices cost few steps.
inline uint32_t sobol_dim1(uint32_t index) {
  uint32_t result = 0;
  for (uint32_t v = 0x80000000u; index != 0; index >>= 1, v ^= v >> 1) {
    if (index & 1u) result ^= v;
  }
  return result;
}

// Owen's nested uniform scramble of a 0.32 fraction, on the 24 leading bits a float keeps.
// Bit i (from the most significant) is flipped by a coin that depends on the seed and on
// the i bits above it only: the node of the binary tree of dyadic intervals the point lies
// in. Points in the same dyadic interval of length 2^-i share the flips of their first i
// bits, so every elementary interval is mapped onto an elementary interval of the same size
// (the net property survives), while each point becomes uniform on [0, 1).
inline uint32_t owen_scramble24(uint32_t x, uint64_t seed) {
  uint32_t flips = 0;
  for (int i = 0; i < 24; ++i) {
    // The node id (1 << i) | prefix numbers the tree's nodes uniquely across depths.
    const uint64_t prefix = i == 0 ? 0u : x >> (32 - i);
    const uint64_t node = (uint64_t{1} << i) | prefix;
    const uint64_t coin = mix64(seed ^ (node * 0x9e3779b97f4a7c15ULL)) >> 63;
    flips |= static_cast<uint32_t>(coin) << (31 - i);
  }
  return (x ^ flips) & 0xffffff00u;
}

// A 0.32 fraction with 24 significant bits as a float in [0, 1), never 1.0.
inline float fraction_to_float(uint32_t x) {
  return static_cast<float>(x >> 8) * 0x1.0p-24f;
}

// The scramble seed of one dimension of one pixel: separate seeds for the two dimensions
// keep their scrambles independent (a shared seed would correlate x and y).
inline uint64_t pixel_scramble_seed(uint64_t pixel_index, uint32_t dimension) {
  return mix64(mix64(pixel_index ^ 0x5bd1e9955bd1e995ULL) + dimension + 1);
}

struct PixelSample2D {
  float x, y;  // in [0, 1) across the pixel
};

// Sample `sample_index` of pixel `pixel_index`: a point of the pixel's own Owen-scrambled
// Sobol (0,2)-sequence.
inline PixelSample2D sobol_owen_pixel_sample(uint64_t pixel_index, uint32_t sample_index) {
  return {fraction_to_float(
              owen_scramble24(sobol_dim0(sample_index), pixel_scramble_seed(pixel_index, 0))),
          fraction_to_float(
              owen_scramble24(sobol_dim1(sample_index), pixel_scramble_seed(pixel_index, 1)))};
}

}  // namespace prism
