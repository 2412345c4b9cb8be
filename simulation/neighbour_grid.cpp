#include "simulation/neighbour_grid.h"

#include <algorithm>
#include <cmath>

namespace prism {

namespace {
// A box far larger than the radius would need billions of cells; past this many per axis the
// cells grow instead (never narrower than radius / kReach, so the block still covers it).
constexpr int kMaxCellsPerAxis = 256;
}  // namespace

NeighbourGrid::NeighbourGrid(const AxisBox& bounds, float radius) : origin_(bounds.min) {
  const Imath::V3f extent = bounds.max - bounds.min;
  const float largest = std::max({extent.x, extent.y, extent.z});
  const float cell = std::max(radius / kReach, largest / kMaxCellsPerAxis);
  inverse_cell_ = 1.0f / cell;
  for (int axis = 0; axis < 3; ++axis)
    dims_[axis] =
        std::clamp(static_cast<int>(std::ceil(extent[axis] * inverse_cell_)), 1, kMaxCellsPerAxis);
  start_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
}

NeighbourGrid::Cell NeighbourGrid::cell_of(const Imath::V3f& p) const {
  int c[3];
  for (int axis = 0; axis < 3; ++axis) {
    const float f = std::floor((p[axis] - origin_[axis]) * inverse_cell_);
    // Compared in float first: a far-away (or NaN) coordinate must not overflow the int.
    c[axis] = f >= 0.0f ? (f < dims_[axis] ? static_cast<int>(f) : dims_[axis] - 1) : 0;
  }
  return {c[0], c[1], c[2]};
}

void NeighbourGrid::build(const std::vector<Imath::V3f>& points) {
  std::fill(start_.begin(), start_.end(), 0);
  cell_index_.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Cell c = cell_of(points[i]);
    cell_index_[i] = static_cast<uint32_t>(index(c.x, c.y, c.z));
    ++start_[cell_index_[i] + 1];
  }
  for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
  order_.resize(points.size());
  // Filling in index order with a moving cursor per cell keeps each cell sorted by index.
  std::vector<uint32_t> cursor(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i)
    order_[cursor[cell_index_[i]]++] = static_cast<uint32_t>(i);
}

}  // namespace prism
