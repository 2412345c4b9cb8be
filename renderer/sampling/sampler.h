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
inline uint32_t owen_scramble_bits(uint32_t x, uint64_t seed, int bits) {
  uint32_t flips = 0;
  for (int i = 0; i < bits; ++i) {
    // The node id (1 << i) | prefix numbers the tree's nodes uniquely across depths.
    const uint64_t prefix = i == 0 ? 0u : x >> (32 - i);
    const uint64_t node = (uint64_t{1} << i) | prefix;
    const uint64_t coin = mix64(seed ^ (node * 0x9e3779b97f4a7c15ULL)) >> 63;
    flips |= static_cast<uint32_t>(coin) << (31 - i);
  }
  return x ^ flips;
}
inline uint32_t owen_scramble24(uint32_t x, uint64_t seed) {
  return owen_scramble_bits(x, seed, 24) & 0xffffff00u;
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

// Beyond the pixel position: a sample has as many dimensions as an integrator asks for
// (a light choice, a BSDF lobe, a direction...), numbered from 2 in the order it asks.
// Dimensions come in pairs (2k, 2k + 1), each pair a (0,2)-sequence of its own: the pixel's
// sample index is first shuffled, seeded by (pixel, pair), then the pair takes Sobol
// dimensions 0 and 1 of the shuffled index, Owen-scrambled (the padding of pbrt-v4's
// PaddedSobolSampler, without its need to know the sample count). The shuffle is a nested
// uniform scramble of the index's bits from the most significant down: each bit is flipped
// by a coin that depends on the bits above it only, so every aligned block of 2^m indices
// maps onto an aligned block of 2^m indices. The first 2^m samples of a pair are then an
// aligned block of a (0,2)-sequence, a (0,m,2)-net, for every m: padding keeps the
// stratification while decorrelating the pairs from each other and from the pixel
// position. Pair 0 is the pixel position itself, unshuffled, as it always was.
inline uint32_t shuffled_sample_index(uint32_t sample_index, uint64_t seed) {
  return owen_scramble_bits(sample_index, seed, 32);
}

// Dimension `dimension` of sample `sample_index` of pixel `pixel_index`, in [0, 1): a pure
// function of the three, so any thread, tile or pass computes the same value.
inline float sample_dimension(uint64_t pixel_index, uint32_t sample_index, uint32_t dimension) {
  const uint32_t pair = dimension / 2;
  const uint32_t index =
      pair == 0 ? sample_index
                : shuffled_sample_index(sample_index, mix64(pixel_scramble_seed(pixel_index, pair) ^
                                                            0x2545f4914f6cdd1dULL));
  const uint32_t x = (dimension & 1u) ? sobol_dim1(index) : sobol_dim0(index);
  return fraction_to_float(owen_scramble24(x, pixel_scramble_seed(pixel_index, dimension)));
}

// One sample of one pixel, handing out its dimensions in order: what an integrator draws
// its random numbers from. Cheap to copy; holds no state but the next dimension.
class PixelSampler {
 public:
  // Dimensions 0 and 1 are the pixel position (the tile loop's), so an integrator's first
  // request gets dimension 2.
  static constexpr uint32_t kFirstIntegratorDimension = 2;

  PixelSampler(uint64_t pixel_index, uint32_t sample_index,
               uint32_t first_dimension = kFirstIntegratorDimension)
      : pixel_(pixel_index), sample_(sample_index), dimension_(first_dimension) {}

  float get1d() { return sample_dimension(pixel_, sample_, dimension_++); }
  // Two dimensions of one pair when the next dimension starts a pair (stratified together);
  // otherwise the odd one is used alone and the pair after it is taken.
  PixelSample2D get2d() {
    if (dimension_ & 1u) ++dimension_;
    const float x = sample_dimension(pixel_, sample_, dimension_);
    const float y = sample_dimension(pixel_, sample_, dimension_ + 1);
    dimension_ += 2;
    return {x, y};
  }
  uint32_t dimension() const { return dimension_; }

 private:
  uint64_t pixel_;
  uint32_t sample_;
  uint32_t dimension_;
};

}  // namespace prism
