// Piecewise-constant sampling (renderer/sampling/piecewise_constant.h): the guide table must
// find exactly the bin that inverting the whole CDF finds, for every u, including u on cell
// and CDF boundaries and runs of empty bins, so that switching the search changes no image.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "renderer/sampling/piecewise_constant.h"

namespace prism {
namespace {

// The CDF the class builds, recomputed here in the same order of operations, and the last
// bin whose CDF entry is <= u, found by a scan of every entry.
size_t bin_by_scan(const std::vector<double>& weights, double u) {
  const size_t n = weights.size();
  std::vector<double> cdf(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + weights[i];
  const double total = cdf[n];
  for (size_t i = 1; i <= n; ++i)
    cdf[i] = total > 0.0 ? cdf[i] / total : static_cast<double>(i) / static_cast<double>(n);
  cdf[n] = 1.0;
  size_t bin = 0;
  for (size_t i = 0; i < n; ++i)
    if (cdf[i] <= u) bin = i;
  return bin;
}

std::vector<std::vector<double>> test_distributions() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<std::vector<double>> all;
  all.push_back({1.0});
  all.push_back({0.0, 0.0, 5.0, 0.0});
  all.push_back({0.0, 0.0, 0.0});  // all empty: drawn uniformly
  // A peak: most of the mass in one bin, many cells of u map to it.
  std::vector<double> peak(257, 1e-6);
  peak[100] = 1e6;
  all.push_back(peak);
  // Runs of empty bins between random weights, as a sky map's black lower half.
  for (size_t n : {3u, 16u, 100u, 512u}) {
    std::vector<double> w(n);
    for (size_t i = 0; i < n; ++i) w[i] = (i % 7 < 3) ? 0.0 : std::pow(uniform(rng), 4.0);
    all.push_back(w);
  }
  return all;
}

TEST(PiecewiseConstant, GuideTableFindsTheBinOfTheWholeCdf) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int checked = 0;
  for (const std::vector<double>& weights : test_distributions()) {
    const PiecewiseConstant1D d(weights);
    const size_t n = weights.size();
    std::vector<double> us = {0.0, std::nextafter(1.0, 0.0), 0.5};
    // Both sides of every cell boundary of the guide table.
    for (size_t k = 1; k < n; ++k) {
      const double start = static_cast<double>(k) / static_cast<double>(n);
      us.insert(us.end(), {start, std::nextafter(start, 0.0), std::nextafter(start, 1.0)});
    }
    for (int i = 0; i < 4000; ++i) us.push_back(uniform(rng));
    for (double u : us) {
      size_t bin = 0;
      double density = 0.0;
      const double x = d.sample(u, &bin, &density);
      ASSERT_EQ(bin, bin_by_scan(weights, u)) << "n " << n << " u " << u;
      EXPECT_GE(x, static_cast<double>(bin) / static_cast<double>(n));
      // (bin + offset) / n may round up onto the bin's upper edge, never past it.
      EXPECT_LE(x, static_cast<double>(bin + 1) / static_cast<double>(n));
      EXPECT_EQ(density, d.density(bin));
      if (d.total() > 0.0) {
        EXPECT_GT(weights[bin], 0.0) << "an empty bin was drawn";
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 30000);
}

TEST(PiecewiseConstant, ValuesOutsideTheUnitIntervalFallBackToTheWholeSearch) {
  const std::vector<double> weights = {0.0, 2.0, 0.0, 1.0};
  const PiecewiseConstant1D d(weights);
  for (double u : {-0.25, 1.0, 1.5}) {
    size_t bin = 0;
    double density = 0.0;
    d.sample(u, &bin, &density);
    EXPECT_EQ(bin, bin_by_scan(weights, u)) << u;
  }
}

}  // namespace
}  // namespace prism
