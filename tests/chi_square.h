// The chi-square test of a sampler against the density it claims, as pbrt-v4's and
// Mitsuba 3's sampling tests do: observed counts per bin against the expected ones, bins
// expected below 5 pooled into one.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace prism::testing {

// The upper tail probability of a chi-square value with k degrees of freedom, by the
// Wilson-Hilferty normal approximation (accurate to a few per cent of p for k > 30).
inline double chi_square_p_value(double chi2, int k) {
  const double z = (std::cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

// The p-value of `observed` against `expected` (the same bins), pooling the bins expected
// below 5; the pooled bins must not hold many samples where the density says there are
// almost none.
inline double chi_square_test(const std::vector<double>& observed,
                              const std::vector<double>& expected) {
  double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
  int dof = -1;
  for (size_t i = 0; i < expected.size(); ++i) {
    if (expected[i] < 5.0) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (pooled_exp >= 5.0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  } else {
    EXPECT_LT(pooled_obs, 20.0) << "samples where the pdf says there are almost none";
  }
  return chi_square_p_value(chi2, dof);
}

}  // namespace prism::testing
