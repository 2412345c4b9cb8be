// Pearson's chi-square test of a histogram against expected counts, shared by the sampling
// tests (BSDFs, area lights, the environment), as pbrt-v4's and Mitsuba 3's sampling tests
// do: observed counts per bin against the expected ones, bins expected below 5 pooled.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace prism::testing {

// The upper tail probability of a chi-square value with k degrees of freedom, by the
// Wilson-Hilferty normal approximation (accurate to a few per cent of p for k > 30).
inline double chi_square_p_value(double chi2, int k) {
  const double z = (std::cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

struct ChiSquareResult {
  double p_value = 0.0;
  // The cells expecting fewer than 5, merged into one (left out when they expect fewer
  // than 5 together: then the caller checks that few samples fell there).
  double pooled_observed = 0.0, pooled_expected = 0.0;
};

inline ChiSquareResult chi_square(const std::vector<double>& observed,
                                  const std::vector<double>& expected) {
  ChiSquareResult r;
  double chi2 = 0.0;
  int dof = -1;
  for (size_t i = 0; i < expected.size(); ++i) {
    if (expected[i] < 5.0) {
      r.pooled_observed += observed[i];
      r.pooled_expected += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (r.pooled_expected >= 5.0) {
    const double d = r.pooled_observed - r.pooled_expected;
    chi2 += d * d / r.pooled_expected;
    ++dof;
  }
  r.p_value = chi_square_p_value(chi2, dof > 0 ? dof : 1);
  return r;
}

// The p-value alone, failing the calling test when the pooled bins, too few to count,
// still hold many samples where the density says there are almost none.
inline double chi_square_test(const std::vector<double>& observed,
                              const std::vector<double>& expected) {
  const ChiSquareResult r = chi_square(observed, expected);
  if (r.pooled_expected < 5.0) {
    EXPECT_LT(r.pooled_observed, 20.0) << "samples where the pdf says there are almost none";
  }
  return r.p_value;
}

}  // namespace prism::testing
