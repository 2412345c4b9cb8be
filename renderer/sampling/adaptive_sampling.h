// Adaptive sampling: which pixels keep sampling after a round, and how long rounds are
// (docs/sampling.md has the reasoning and the measurements).
//
// The main error estimate splits a pixel's n samples into its first 2^k (2^k the largest
// power of two below n) and the rest. Both parts are unbiased estimates of the pixel; with Prism's
// Owen-scrambled Sobol points (renderer/sampling/sampler.h) the first part is a complete (0,2)-net
// and the rest a union of aligned nets, so both are as well stratified as the whole. The spread of
// their means therefore tracks the real, stratified error of the pixel (falling close to n^-3/4 at
// an edge), where the i.i.d. variance of the mean (sums of squares) would assume n^-1/2 and keep
// sampling converged edges. Splitting by sample parity, as done for random samplers, would be wrong
// here: Sobol's even samples all lie in one half of the pixel.
//
// Every decision reads only sums after complete rounds, so the set of samples each pixel
// takes, and the image, are the same for any thread count or tile order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/integrator.h"

namespace prism {

// The error of n Owen-scrambled Sobol samples of a pixel crossed by an edge, as a multiple
// of the samples' standard deviation times n^-3/4: 0.72 to 0.73 at 16, 64 and 256 spp in
// tests/sampler_test.cpp's disc (docs/sampling.md); rounded up.
inline constexpr double kEdgeErrorConstant = 0.75;

// The floor under the relative error's denominator: relMSE's epsilon (image_metrics.h), so
// that a pixel whose estimate is below the target keeps its relMSE share below target^2.
inline constexpr double kAdaptiveErrorFloorSquared = 1e-2;

// Where the round that starts after `samples_done` samples ends: the first round takes
// `min_spp`, then each adds the largest power of two not above a quarter of what is done (4
// after 16, 8 after 32, ...), so rounds stay aligned to the sampler's nets while every
// decision comes after at most 25% more samples. Never past `max_spp`.
int next_round_end(int samples_done, int min_spp, int max_spp);

// The estimated relative error of a pixel's mean, from its sums over all its samples and
// over its first 2^k. Per channel, the larger of
//  - the spread of the two parts, |mean(first) - mean(rest)| sqrt(a b) / (a + b) (the
//    standard error of the mean of a + b samples when the parts hold a and b), which sees
//    whatever converges slower than an edge (small features, highlights);
//  - the edge model, kEdgeErrorConstant * s * n^-3/4 with s the samples' standard
//    deviation: at a straight edge both nets can land their points alike and agree by luck,
//    while s, the edge's contrast, is measured reliably from the first samples;
// divided by sqrt(mean^2 + floor); then the root mean square over R, G, B. Infinite while
// either part is empty.
double pixel_relative_error(const PixelSums& all, const PixelSums& first_half);

// How much a neighbour's error counts in a pixel's decision: a pixel keeps sampling while
// its own error, or kNeighbourWeight times a neighbour's, is above the target. At full
// weight (what Prism did first) the 3x3 dilation kept three to five pixels sampling on the
// engine for every one above the target; at half weight the silhouette of
// tests/adaptive_sampling_test.cpp still comes out below the target (docs/sampling.md).
inline constexpr float kNeighbourWeight = 0.5f;

// The error a pixel's neighbourhood-weighed estimate is held to after a round, for `goal`:
//  - ErrorGoal::pixel: `target` itself;
//  - ErrorGoal::image: infinity (every pixel stops) once the image's estimated relative RMS error,
//    sqrt(mean over pixels of e_i^2), is at most `target`; before that, the error at which a
//    pixel of n samples has its share of an allocation that meets the target with the fewest
//    samples. A pixel's mean has e_i^2 = v_i / n_i for its samples' relative variance v_i, and
//    the mean of v_i / n_i is smallest for a given sum of n_i when n_i is proportional to
//    sqrt(v_i) (a Lagrange multiplier: v_i / n_i^2 equal everywhere), which meets target^2
//    with n_i = sqrt(v_i) S / (P target^2), S the sum over the P pixels of sqrt(v_j) =
//    e_j sqrt(n_j). Pixel i is short of it while e_i > sqrt(n_i) P target^2 / S. Per-pixel
//    thresholds (the pixel goal, Cycles') give n_i proportional to v_i instead, which for the
//    mean of v_i / n_i is no better than uniform sampling.
// `samples_done`: the active pixels' count; stopped pixels count their `samples_taken`;
// pixels that take no samples (outside the region) count for nothing. The sums run over rows
// in order, so the result is the same for any thread count.
double active_threshold(int width, int height, const float* error, const uint8_t* active,
                        const uint32_t* samples_taken, double target, ErrorGoal goal,
                        uint32_t samples_done);

// After the round that ended at `samples_done` samples: a pixel stays active when it was
// and the largest of its own error and kNeighbourWeight times the errors of the rest of its
// 3x3 neighbourhood is above active_threshold(). The neighbourhood keeps a pixel whose two
// halves agreed by luck sampling as long as the edge it lies on has clearly not converged.
// `error` keeps each pixel's last estimate between calls (sized here on the first; only
// active pixels are estimated again). A pixel that stops gets `samples_done` in
// `samples_taken`. Returns how many pixels stay active.
size_t update_active_pixels(int width, int height, const PixelSums* sums,
                            const PixelSums* first_half, double target, ErrorGoal goal,
                            uint32_t samples_done, std::vector<float>* error, uint8_t* active,
                            uint32_t* samples_taken);

}  // namespace prism
