#include "renderer/sampling/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace prism {

int next_round_end(int samples_done, int min_spp, int max_spp) {
  if (samples_done <= 0) return std::min(std::max(1, min_spp), max_spp);
  int step = 1;
  while (step * 2 <= samples_done / 4) step *= 2;
  return std::min(samples_done + step, max_spp);
}

double pixel_relative_error(const PixelSums& all, const PixelSums& first_half) {
  const double a = first_half.kept;
  const double b = static_cast<double>(all.kept) - a;
  if (a <= 0.0 || b <= 0.0) return std::numeric_limits<double>::infinity();
  const double n = a + b;
  const double scale = std::sqrt(a * b) / n;
  const double edge_rate = std::pow(n, -0.75);
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double total = all.radiance[c];
    const double first = first_half.radiance[c];
    const double spread = std::abs(first / a - (total - first) / b) * scale;
    const double mean = total / n;
    const double variance =
        std::max(0.0, (all.radiance_squared[c] / n - mean * mean) * n / (n - 1.0));
    const double edge = kEdgeErrorConstant * std::sqrt(variance) * edge_rate;
    const double error = std::max(spread, edge);
    sum += error * error / (mean * mean + kAdaptiveErrorFloorSquared);
  }
  return std::sqrt(sum / 3.0);
}

double active_threshold(int width, int height, const float* error, const uint8_t* active,
                        const uint32_t* samples_taken, double target, ErrorGoal goal,
                        uint32_t samples_done) {
  if (goal == ErrorGoal::pixel) return target;
  // Per row in parallel, then the rows in order: the same sums for any thread count.
  struct RowSums {
    double squared_error = 0.0, share = 0.0;  // sums of e^2 and of e sqrt(n)
    size_t pixels = 0;
  };
  std::vector<RowSums> rows(static_cast<size_t>(height));
  tbb::parallel_for(0, height, [&](int y) {
    RowSums r;
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const uint32_t n = active[i] ? samples_done : samples_taken[i];
      if (n == 0) continue;
      const double e = error[i];
      r.squared_error += e * e;
      r.share += e * std::sqrt(static_cast<double>(n));
      ++r.pixels;
    }
    rows[static_cast<size_t>(y)] = r;
  });
  RowSums image;
  for (const RowSums& r : rows) {
    image.squared_error += r.squared_error;
    image.share += r.share;
    image.pixels += r.pixels;
  }
  const double target_squared = target * target;
  if (image.pixels == 0 || image.squared_error <= image.pixels * target_squared)
    return std::numeric_limits<double>::infinity();
  // An infinite estimate (a pixel with an empty half) makes S infinite: every pixel above
  // 0 keeps sampling until the estimates are finite.
  return std::sqrt(static_cast<double>(samples_done)) * image.pixels * target_squared / image.share;
}

size_t update_active_pixels(int width, int height, const PixelSums* sums,
                            const PixelSums* first_half, double target, ErrorGoal goal,
                            uint32_t samples_done, std::vector<float>* error, uint8_t* active,
                            uint32_t* samples_taken) {
  error->resize(static_cast<size_t>(width) * height);
  float* e = error->data();
  // Rows are independent and each value a pure function of its pixel's sums, so running
  // them in parallel cannot change the result. A stopped pixel's sums, so its error, no
  // longer change: only active pixels are estimated again.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const size_t i = static_cast<size_t>(y) * width + x;
        if (active[i]) e[i] = static_cast<float>(pixel_relative_error(sums[i], first_half[i]));
      }
  });
  // The active flags are read from the error alone and written only for their own pixel;
  // the count is a sum of integers, the same in any order.
  const float threshold = static_cast<float>(
      active_threshold(width, height, e, active, samples_taken, target, goal, samples_done));
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, height), size_t{0},
      [&](const tbb::blocked_range<int>& rows, size_t count) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < width; ++x) {
            const size_t i = static_cast<size_t>(y) * width + x;
            if (!active[i]) continue;
            float neighbours = 0.0f;
            for (int ny = std::max(0, y - 1); ny <= std::min(height - 1, y + 1); ++ny)
              for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx)
                if (ny != y || nx != x)
                  neighbours = std::max(neighbours, e[static_cast<size_t>(ny) * width + nx]);
            if (std::max(e[i], kNeighbourWeight * neighbours) > threshold) {
              ++count;
            } else {
              active[i] = 0;
              samples_taken[i] = samples_done;
            }
          }
        return count;
      },
      std::plus<size_t>());
}

}  // namespace prism
