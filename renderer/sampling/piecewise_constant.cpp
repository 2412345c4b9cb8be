#include "renderer/sampling/piecewise_constant.h"

#include <algorithm>
#include <cmath>

namespace prism {

PiecewiseConstant1D::PiecewiseConstant1D(std::span<const double> weights) {
  const size_t n = weights.size();
  cdf_.assign(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + weights[i];
  total_ = cdf_[n];
  for (size_t i = 1; i <= n; ++i)
    cdf_[i] = total_ > 0.0 ? cdf_[i] / total_ : static_cast<double>(i) / static_cast<double>(n);
  cdf_[n] = 1.0;
  guide_.assign(n + 1, 0);
  size_t entry = 0;
  for (size_t k = 0; k <= n; ++k) {
    const double start = cell_start(k);
    while (entry <= n && cdf_[entry] <= start) ++entry;
    guide_[k] = entry;
  }
}

double PiecewiseConstant1D::sample(double u, size_t* bin, double* density) const {
  // The last bin whose CDF is <= u: its successor's CDF is > u, so the bin has weight.
  auto above = cdf_.end();
  const size_t n = size();
  if (u >= 0.0 && u < 1.0) {
    size_t k = std::min(static_cast<size_t>(u * static_cast<double>(n)), n - 1);
    // u * n rounds, and may land in a neighbouring cell: step to the one that holds u.
    while (k > 0 && cell_start(k) > u) --k;
    while (k + 1 < n && cell_start(k + 1) <= u) ++k;
    above = std::upper_bound(cdf_.begin() + static_cast<ptrdiff_t>(guide_[k]),
                             cdf_.begin() + static_cast<ptrdiff_t>(guide_[k + 1]), u);
  } else {
    above = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  }
  const size_t b =
      std::min(static_cast<size_t>(std::max<ptrdiff_t>(above - cdf_.begin() - 1, 0)), size() - 1);
  const double width = cdf_[b + 1] - cdf_[b];
  const double offset = std::clamp((u - cdf_[b]) / width, 0.0, std::nextafter(1.0, 0.0));
  *bin = b;
  *density = this->density(b);
  return std::min((static_cast<double>(b) + offset) / static_cast<double>(size()),
                  std::nextafter(1.0, 0.0));
}

PiecewiseConstant2D::PiecewiseConstant2D(std::span<const double> weights, size_t width,
                                         size_t height) {
  std::vector<double> row_totals(height);
  rows_.reserve(height);
  for (size_t r = 0; r < height; ++r) {
    rows_.emplace_back(weights.subspan(r * width, width));
    row_totals[r] = rows_.back().total();
  }
  marginal_ = PiecewiseConstant1D(row_totals);
}

void PiecewiseConstant2D::sample(double u0, double u1, double* x, double* y, size_t* column,
                                 size_t* row, double* density) const {
  double row_density = 0.0, column_density = 0.0;
  *y = marginal_.sample(u1, row, &row_density);
  *x = rows_[*row].sample(u0, column, &column_density);
  *density = row_density * column_density;
}

}  // namespace prism
