// A uniform grid over the flock's bounds for neighbour search: cells at least the search
// radius wide, so every neighbour of a point lies in its own cell or the 26 around it, and
// a step costs O(n x the neighbours each boid has) rather than O(n^2).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>

#include "simulation/flock_config.h"

namespace prism {

class NeighbourGrid {
 public:
  NeighbourGrid(const AxisBox& bounds, float radius);

  // Sorts the points into cells, each cell's points in index order: a counting sort, serial,
  // so the order (and every sum taken over it) is the same whatever runs the queries.
  void build(const std::vector<Imath::V3f>& points);

  // Calls f(index) for every point in the 27 cells around p, cell by cell in a fixed order;
  // callers keep those within their radius.
  template <typename F>
  void for_each_candidate(const Imath::V3f& p, F&& f) const {
    const Cell c = cell_of(p);
    for (int z = std::max(c.z - 1, 0); z <= std::min(c.z + 1, dims_[2] - 1); ++z)
      for (int y = std::max(c.y - 1, 0); y <= std::min(c.y + 1, dims_[1] - 1); ++y)
        for (int x = std::max(c.x - 1, 0); x <= std::min(c.x + 1, dims_[0] - 1); ++x) {
          const size_t cell = index(x, y, z);
          for (uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) f(order_[k]);
        }
  }

  int cells(int axis) const { return dims_[axis]; }

 private:
  struct Cell {
    int x, y, z;
  };
  // Points outside the bounds go to the nearest edge cell, so none is ever lost.
  Cell cell_of(const Imath::V3f& p) const;
  size_t index(int x, int y, int z) const {
    return (static_cast<size_t>(z) * dims_[1] + y) * dims_[0] + x;
  }

  Imath::V3f origin_;
  float inverse_cell_ = 1.0f;
  int dims_[3] = {1, 1, 1};
  std::vector<uint32_t> start_;  // cell i holds order_[start_[i] .. start_[i + 1])
  std::vector<uint32_t> order_;
  std::vector<uint32_t> cell_index_;
};

}  // namespace prism
