// Reynolds' boids (separation, alignment, cohesion within a radius and field of view) that
// steer around spheres with a probe cylinder (obstacle_avoidance.h), stay inside a box and
// move at a fixed time step. A step reads only the previous state and writes each boid's
// next state into its own slot, so the result is bit-identical for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>
#include <tbb/task_arena.h>

#include "simulation/flock_config.h"
#include "simulation/neighbour_grid.h"

namespace prism {

class Flock {
 public:
  // Checks the parameters (FlockConfigError) and places the boids: uniformly in the spawn
  // box from the seed, outside every obstacle grown by the probe radius and the body.
  // threads = 0 uses every core.
  explicit Flock(const FlockParameters& parameters, int threads = 0);

  void step();
  void run(int steps) {
    for (int i = 0; i < steps; ++i) step();
  }

  const std::vector<Imath::V3f>& positions() const { return position_; }
  const std::vector<Imath::V3f>& velocities() const { return velocity_; }
  const FlockParameters& parameters() const { return p_; }
  uint64_t steps_taken() const { return steps_; }

 private:
  // The acceleration of boid i from the current state, within the max_force budget.
  Imath::V3f steering(size_t i) const;

  FlockParameters p_;
  float cos_half_fov_ = -1.0f;
  NeighbourGrid grid_;
  std::vector<Imath::V3f> position_, velocity_;
  std::vector<Imath::V3f> next_position_, next_velocity_;
  std::vector<Imath::V3f> heading_;  // velocity / speed, or 0 at rest: this step's
  uint64_t steps_ = 0;
  tbb::task_arena arena_;
};

}  // namespace prism
