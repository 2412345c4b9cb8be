// Deterministic per-sample random numbers.
//
// Each (pixel, sample, dimension) draws from a hash of those integers instead of a stream
// shared by a thread, so the image does not depend on how tiles are scheduled or on the
// thread count: the same options give bit-identical images. Pixel positions use the
// low-discrepancy points of renderer/sampling/sampler.h instead; these independent numbers are for
// dimensions that have no stratified sequence (and the sampler's scramble hashes).
#pragma once

#include <cstdint>

namespace prism {

// A 64-bit finaliser (splitmix64's): every input bit affects every output bit.
inline uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

// A uniform float in [0, 1) for one dimension of one sample of one pixel.
inline float sample_uniform(uint64_t pixel_index, uint32_t sample_index, uint32_t dimension) {
  const uint64_t key = mix64(pixel_index * 0x9e3779b97f4a7c15ULL + sample_index) ^
                       (static_cast<uint64_t>(dimension) << 32);
  // The top 24 bits give every float in [0, 1) with spacing 2^-24, never 1.0.
  return static_cast<float>(mix64(key) >> 40) * 0x1.0p-24f;
}

}  // namespace prism
