// Piecewise-constant densities sampled by inverting their cumulative distribution, in one
// and two dimensions (pbrt-v4's PiecewiseConstant1D and 2D): what an environment map is
// importance sampled by. The density of each bin is computed from the very CDF that
// sampling inverts, so what sample() draws and what density() reports agree exactly.
//
// The inversion starts from a guide table (Chen and Asau's cutpoints): for each of size()
// equal cells of u, the range of CDF entries its u can land between, so a search visits a
// bin or two instead of log2(size()) scattered entries, and finds exactly the bin a binary
// search of the whole CDF finds.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace prism {

class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  // `weights` non-negative and finite, at least one; all zero makes total() 0, and
  // sample() then draws uniformly so that a caller never divides by a zero density.
  explicit PiecewiseConstant1D(std::span<const double> weights);

  size_t size() const { return cdf_.empty() ? 0 : cdf_.size() - 1; }
  double total() const { return total_; }
  // x in [0, 1) for u in [0, 1), from bin `*bin` with density `*density` there (per unit x).
  double sample(double u, size_t* bin, double* density) const;
  // The density per unit x in `bin`: size() times its probability.
  double density(size_t bin) const {
    return static_cast<double>(size()) * (cdf_[bin + 1] - cdf_[bin]);
  }

 private:
  // The lower end of cell k of u; build and lookup compute it the same way.
  double cell_start(size_t k) const { return static_cast<double>(k) / static_cast<double>(size()); }

  std::vector<double> cdf_;  // cdf_[0] = 0, cdf_[size()] = 1
  // guide_[k]: the first CDF entry above cell_start(k), k = 0 .. size() (cell_start = 1
  // there); a u in cell k has its first entry above it in [guide_[k], guide_[k + 1]].
  std::vector<size_t> guide_;
  double total_ = 0.0;
};

// A density over [0, 1)^2 on a width x height grid of non-negative weights (row-major, row
// 0 first): a row from the marginal, then a column from that row's conditional.
class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  PiecewiseConstant2D(std::span<const double> weights, size_t width, size_t height);

  size_t width() const { return rows_.empty() ? 0 : rows_[0].size(); }
  size_t height() const { return rows_.size(); }
  double total() const { return marginal_.total(); }
  // (x, y) in [0, 1)^2 for u in [0, 1)^2 (u0 the column, u1 the row), with its density per
  // unit area and the bin it fell in.
  void sample(double u0, double u1, double* x, double* y, size_t* column, size_t* row,
              double* density) const;
  double density(size_t column, size_t row) const {
    return marginal_.density(row) * rows_[row].density(column);
  }

 private:
  std::vector<PiecewiseConstant1D> rows_;
  PiecewiseConstant1D marginal_;
};

}  // namespace prism
