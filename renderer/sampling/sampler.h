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
// index's least significant bit feeding the output's most significant bit. The byte order
// is reversed by one instruction (bswap on x86-64, rev on AArch64) and the bits within each
// byte by three swaps, two swaps fewer than five: every pair of dimensions reverses four
// times (0.7 % of a path-traced Cornell box's instructions saved).
inline uint32_t reverse_bits32(uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

// Reverses the bits of each 32-bit half of x, the halves swapped: reverse_bits32 of two
// values at the cost of one, for a pair of dimensions' two outputs.
inline uint64_t reverse_bits64(uint64_t x) {
  x = __builtin_bswap64(x);
  x = ((x >> 4) & 0x0f0f0f0f0f0f0f0fULL) | ((x & 0x0f0f0f0f0f0f0f0fULL) << 4);
  x = ((x >> 2) & 0x3333333333333333ULL) | ((x & 0x3333333333333333ULL) << 2);
  return ((x >> 1) & 0x5555555555555555ULL) | ((x & 0x5555555555555555ULL) << 1);
}

// Sobol dimension 0: the generator matrix is the identity, i.e. the base-2 radical
// inverse (van der Corput). Returned as a 0.32 fixed-point fraction.
inline uint32_t sobol_dim0(uint32_t index) {
  return reverse_bits32(index);
}

// Sobol dimension 1 with its bits reversed (bit j of the result is the fraction's bit
// 31 - j). The primitive polynomial x + 1 (degree 1, m_1 = 1) gives the direction numbers
// m_(k+1) = m_k xor (m_k << 1): the rows of Pascal's triangle mod 2, so by Lucas' theorem
// index bit k sets bit j exactly when j's bits are a subset of k's. Bit j of the result is
// then the parity of the index bits k that are supersets of j: five butterfly steps, one per
// bit of j, instead of a loop over the index's 32 bits.
inline uint32_t sobol_dim1_reversed(uint32_t index) {
  uint32_t x = index;
  x ^= (x >> 1) & 0x55555555u;
  x ^= (x >> 2) & 0x33333333u;
  x ^= (x >> 4) & 0x0f0f0f0fu;
  x ^= (x >> 8) & 0x00ff00ffu;
  x ^= x >> 16;
  return x;
}

// Sobol dimension 1 as a 0.32 fraction: index bit k (from the least significant) selects
// the direction number v_(k+1), v_1 = 1/2 and v_(k+1) = v_k xor (v_k >> 1).
inline uint32_t sobol_dim1(uint32_t index) {
  return reverse_bits32(sobol_dim1_reversed(index));
}

// Owen's nested uniform scramble, applied to a value whose bits are reversed (the fraction's
// most significant bit in bit 0): the hash of Laine and Karras as Burley uses it ("Practical
// Hash-based Owen Scrambling", JCGT 2020), with the constants of Vegdahl's better-mixing
// variant (2021). Every step (adding the seed, multiplying by an odd number, xoring with a
// multiple by an even number) is a bijection in which bit i of the result depends only on
// bits 0..i of its input, i.e. on the fraction's i leading bits: each bit is flipped by a
// function of the seed and the bits above it, the definition of a nested scramble. Points in
// one dyadic interval share the flips of their leading bits, so every elementary interval
// maps onto one of the same size and the net property survives; over random seeds each
// point is uniform. Unlike a coin hashed per bit it is not exactly Owen's uniform random
// tree, but Burley measures the same convergence; tests/sampler_test.cpp checks the nets
// and the edge error.
inline uint32_t owen_scramble_reversed(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// A 0.32 fraction with 24 significant bits as a float in [0, 1), never 1.0.
inline float fraction_to_float(uint32_t x) {
  return static_cast<float>(x >> 8) * 0x1.0p-24f;
}

// The scramble seeds of one pair of dimensions of one pixel, 64 bits: the high half seeds
// the pair's first dimension's scramble, the low half its second's, and a product of both
// the shuffle of the sample index (below). Each half is uniform and, for a hash of full
// avalanche, independent of the other, so x and y are scrambled independently (a shared
// seed would correlate them); the shuffle seed is uniform too and independent of either
// half alone, and the multiplication's carries keep it from being a bitwise (linear)
// function of the two.
inline uint64_t pair_seeds(uint64_t pixel_index, uint32_t pair) {
  return mix64(pixel_index * 0x9e3779b97f4a7c15ULL +
               (static_cast<uint64_t>(pair) + 1) * 0xd1b54a32d192ed03ULL);
}
inline uint32_t scramble_seed(uint64_t seeds, bool second) {
  return static_cast<uint32_t>(second ? seeds : seeds >> 32);
}
inline uint32_t shuffle_seed(uint64_t seeds) {
  return (static_cast<uint32_t>(seeds >> 32) ^ static_cast<uint32_t>(seeds)) * 0x9e3779b1u;
}

// The point's fraction, given its unscrambled bits reversed: the dimension's Owen scramble
// and the reversal back, as a float.
inline float scrambled_fraction(uint32_t reversed_bits, uint32_t seed) {
  return fraction_to_float(reverse_bits32(owen_scramble_reversed(reversed_bits, seed)));
}

struct PixelSample2D {
  float x, y;  // in [0, 1) across the pixel
};

// Beyond the pixel position: a sample has as many dimensions as an integrator asks for
// (a light choice, a BSDF lobe, a direction...), numbered from 2 in the order it asks.
// Dimensions come in pairs (2k, 2k + 1), each pair a (0,2)-sequence of its own: the pixel's
// sample index is first shuffled, seeded by (pixel, pair), then the pair takes Sobol
// dimensions 0 and 1 of the shuffled index, Owen-scrambled (the padding of pbrt-v4's
// PaddedSobolSampler, without its need to know the sample count). The shuffle is a nested
// scramble of the index's bits from the most significant down (the same hash on the
// reversed index): each bit is flipped by a function of the bits above it only, so every
// aligned block of 2^m indices maps onto an aligned block of 2^m indices. The first 2^m
// samples of a pair are then an aligned block of a (0,2)-sequence, a (0,m,2)-net, for every
// m: padding keeps the stratification while decorrelating the pairs from each other and from
// the pixel position. Pair 0 is the pixel position itself, unshuffled, as it always was.
//
// `reversed_index` is reverse_bits32(sample_index), which every dimension of a sample
// shares: PixelSampler computes it once.
inline uint32_t pair_sample_index(uint32_t sample_index, uint32_t reversed_index, uint32_t pair,
                                  uint64_t seeds) {
  if (pair == 0) return sample_index;
  return reverse_bits32(owen_scramble_reversed(reversed_index, shuffle_seed(seeds)));
}

// Both dimensions of pair `pair`: one seed hash, one shuffle and one 64-bit reversal for the
// two, the same values as two scrambled_fraction calls.
inline PixelSample2D sample_pair(uint64_t pixel_index, uint32_t sample_index,
                                 uint32_t reversed_index, uint32_t pair) {
  const uint64_t seeds = pair_seeds(pixel_index, pair);
  const uint32_t index = pair_sample_index(sample_index, reversed_index, pair, seeds);
  // Sobol dimension 0 reversed is the index itself. The first dimension goes in the high
  // half, so that after the reversal swaps the halves it is in the low half.
  const uint64_t both = reverse_bits64(
      static_cast<uint64_t>(owen_scramble_reversed(index, scramble_seed(seeds, false))) << 32 |
      owen_scramble_reversed(sobol_dim1_reversed(index), scramble_seed(seeds, true)));
  return {fraction_to_float(static_cast<uint32_t>(both)),
          fraction_to_float(static_cast<uint32_t>(both >> 32))};
}

// One dimension alone: the same value as its half of sample_pair. Always inlined: a call
// costs more than its body, and GCC stops inlining it where a path tracer's loop is large.
[[gnu::always_inline]] inline float sample_dimension_reversed(uint64_t pixel_index,
                                                              uint32_t sample_index,
                                                              uint32_t reversed_index,
                                                              uint32_t dimension) {
  const uint32_t pair = dimension >> 1;
  const bool second = (dimension & 1u) != 0;
  const uint64_t seeds = pair_seeds(pixel_index, pair);
  const uint32_t index = pair_sample_index(sample_index, reversed_index, pair, seeds);
  return scrambled_fraction(second ? sobol_dim1_reversed(index) : index,
                            scramble_seed(seeds, second));
}

// Dimension `dimension` of sample `sample_index` of pixel `pixel_index`, in [0, 1): a pure
// function of the three, so any thread, tile or pass computes the same value.
inline float sample_dimension(uint64_t pixel_index, uint32_t sample_index, uint32_t dimension) {
  return sample_dimension_reversed(pixel_index, sample_index, reverse_bits32(sample_index),
                                   dimension);
}

// Both dimensions of pair `pair` as independent uniforms, not stratified: one splitmix64 step
// of a stream seeded by (pixel, pair), at the sample's position. A sixth of the cost of
// sample_pair, for dimensions whose stratification no longer shows in the image (a path's
// later bounces, docs/sampling.md).
inline PixelSample2D independent_pair(uint64_t pixel_index, uint32_t sample_index, uint32_t pair) {
  const uint64_t bits = mix64(pair_seeds(pixel_index, pair) +
                              (static_cast<uint64_t>(sample_index) + 1) * 0x9e3779b97f4a7c15ULL);
  return {fraction_to_float(static_cast<uint32_t>(bits >> 32)),
          fraction_to_float(static_cast<uint32_t>(bits))};
}

// The key a pixel's samples are scrambled and shuffled by, in place of its index: the index
// itself for seed 0 (so every image rendered before seeds existed is unchanged), else the
// index and the seed hashed together, so that another seed draws scrambles independent of
// seed 0's for every pixel. Distinct (pixel, seed) give distinct keys: the index fits in the
// low 32 bits for any image Prism renders, and mix64 is a bijection.
inline uint64_t pixel_sample_key(uint64_t pixel_index, uint32_t seed) {
  if (seed == 0) return pixel_index;
  return mix64(pixel_index ^ (static_cast<uint64_t>(seed) << 32) ^ 0x6a09e667f3bcc909ULL);
}

// Sample `sample_index` of pixel `pixel_index`: a point of the pixel's own Owen-scrambled
// Sobol (0,2)-sequence, dimensions 0 and 1.
inline PixelSample2D sobol_owen_pixel_sample(uint64_t pixel_index, uint32_t sample_index) {
  return sample_pair(pixel_index, sample_index, 0, 0);
}

// Which sample of which pixel: the pixel's key (pixel_sample_key) and the sample's index, what
// an integrator makes its PixelSampler from.
struct PixelSampleId {
  uint64_t pixel_key = 0;
  uint32_t sample_index = 0;
};

// One sample of one pixel, handing out its dimensions in order: what an integrator draws
// its random numbers from. Cheap to copy; holds no state but the next dimension.
//
// Dimensions below `stratified_end` are the padded Sobol pairs above; those from it on are
// independent_pair's uniforms, for an integrator that knows where stratification stops paying
// (both kinds are uniform, so either keeps every estimate unbiased).
class PixelSampler {
 public:
  // Dimensions 0 and 1 are the pixel position (the tile loop's), so an integrator's first
  // request gets dimension 2.
  static constexpr uint32_t kFirstIntegratorDimension = 2;
  static constexpr uint32_t kAllStratified = ~0u;

  PixelSampler(uint64_t pixel_index, uint32_t sample_index,
               uint32_t first_dimension = kFirstIntegratorDimension,
               uint32_t stratified_end = kAllStratified)
      : pixel_(pixel_index),
        sample_(sample_index),
        reversed_sample_(reverse_bits32(sample_index)),
        dimension_(first_dimension),
        stratified_end_(stratified_end) {}

  float get1d() { return dimension_value(dimension_++); }
  // Two dimensions of one pair when the next dimension starts a pair (stratified together);
  // otherwise the odd one is used alone and the pair after it is taken.
  PixelSample2D get2d() {
    if (dimension_ & 1u) ++dimension_;
    const PixelSample2D p = dimension_ < stratified_end_
                                ? sample_pair(pixel_, sample_, reversed_sample_, dimension_ >> 1)
                                : independent_pair(pixel_, sample_, dimension_ >> 1);
    dimension_ += 2;
    return p;
  }
  uint32_t dimension() const { return dimension_; }
  // Dimension `dimension` alone, without moving on: for a value an integrator needs only on
  // some paths (a lobe choice, a roulette), drawn where it is needed from the dimension it
  // would have had in order, so skipping it changes no other value.
  [[gnu::always_inline]] float get1d_at(uint32_t dimension) const {
    return dimension_value(dimension);
  }

 private:
  [[gnu::always_inline]] float dimension_value(uint32_t dimension) const {
    if (dimension >= stratified_end_) {
      const PixelSample2D p = independent_pair(pixel_, sample_, dimension >> 1);
      return dimension & 1u ? p.y : p.x;
    }
    return sample_dimension_reversed(pixel_, sample_, reversed_sample_, dimension);
  }

  uint64_t pixel_;
  uint32_t sample_;
  uint32_t reversed_sample_;
  uint32_t dimension_;
  uint32_t stratified_end_;
};

}  // namespace prism
