// Pearson's chi-square test of a histogram against expected counts, shared by the sampling
// tests (BSDFs, area lights, the environment), as pbrt-v4's and Mitsuba 3's sampling tests
// do: observed counts per bin against the expected ones, bins expected below 5 pooled.
#pragma once

#include <gtest/gtest.h>

#include <Imath/ImathVec.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
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

// The (cos theta, phi) grid over the sphere of directions that the sampling tests histogram
// on: every cell has the same solid angle, and a point of a cell is found from sub-cell
// indices for the midpoint rule that integrates a pdf over it.
struct DirectionGrid {
  int theta_cells, phi_cells;

  static Imath::V3f direction(double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return Imath::V3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta));
  }
  size_t cells() const { return size_t(theta_cells) * size_t(phi_cells); }
  double cell_solid_angle() const {
    return (2.0 / theta_cells) * (2.0 * std::numbers::pi / phi_cells);
  }
  // The cell a unit direction falls in, row-major (theta, then phi).
  size_t cell_of(const Imath::V3f& w) const {
    const double c = std::clamp(double(w.z), -1.0, 1.0);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0) phi += 2.0 * std::numbers::pi;
    const int t = std::min(theta_cells - 1, int((c + 1.0) * 0.5 * theta_cells));
    const int p = std::min(phi_cells - 1, int(phi / (2.0 * std::numbers::pi) * phi_cells));
    return size_t(t) * size_t(phi_cells) + size_t(p);
  }
  // The centre of sub-cell (a, b) of `sub` x `sub` in cell (t, p).
  Imath::V3f point(int t, int p, int a, int b, int sub) const {
    const double c = -1.0 + (t + (a + 0.5) / sub) * 2.0 / theta_cells;
    const double phi = (p + (b + 0.5) / sub) * 2.0 * std::numbers::pi / phi_cells;
    return direction(c, phi);
  }
};

}  // namespace prism::testing
