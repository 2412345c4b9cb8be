#include "simulation/flock.h"

#include <cmath>
#include <random>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "simulation/obstacle_avoidance.h"

namespace prism {

using Imath::V3f;

namespace {

constexpr float kPi = 3.14159265358979f;

// A float in [0, 1) from the generator's top 24 bits: std::mt19937_64's sequence is fixed by
// the standard, the distributions' are not, so this keeps a seed's flock the same everywhere.
float unit_float(std::mt19937_64& rng) {
  return static_cast<float>(rng() >> 40) * 0x1p-24f;
}

V3f truncated(const V3f& v, float limit) {
  const float length = v.length();
  return length > limit ? v * (limit / length) : v;
}

// Reynolds' prioritised acceleration allocation: behaviours in order of importance take what
// they ask of the budget until it is spent, so a flock's pull never outweighs a wall or an
// obstacle.
class SteeringBudget {
 public:
  explicit SteeringBudget(float budget) : left_(budget) {}
  void keep_out_of(const Avoidance* avoidance) { avoidance_ = avoidance; }
  void add(V3f force) {
    if (avoidance_) force = avoidance_->without_inward(force);
    const float length = force.length();
    if (left_ <= 0.0f || !(length > 0.0f)) return;
    if (length <= left_) {
      total_ += force;
      left_ -= length;
    } else {
      total_ += force * (left_ / length);
      left_ = 0.0f;
    }
  }
  const V3f& total() const { return total_; }

 private:
  float left_;
  V3f total_{0.0f};
  const Avoidance* avoidance_ = nullptr;
};

// The grid is sized from the parameters, so they are checked before anything is built.
const FlockParameters& checked(const FlockParameters& p) {
  check_flock_parameters(p);
  return p;
}

}  // namespace

Flock::Flock(const FlockParameters& parameters, int threads)
    : p_(checked(parameters)),
      grid_(parameters.bounds, parameters.neighbour_radius),
      arena_(threads > 0 ? threads : tbb::task_arena::automatic) {
  if (p_.field_of_view_degrees < 360.0f)
    cos_half_fov_ = std::cos(p_.field_of_view_degrees * (kPi / 360.0f));
  const size_t n = static_cast<size_t>(p_.boids);
  position_.reserve(n);
  velocity_.reserve(n);
  std::mt19937_64 rng(p_.seed);
  const V3f extent = p_.spawn.max - p_.spawn.min;
  const float jitter = 0.3f * std::max(p_.spawn_velocity.length(), p_.cruise_speed);
  const size_t max_tries = 1000 * n + 1000;
  for (size_t tries = 0; position_.size() < n; ++tries) {
    if (tries == max_tries)
      throw FlockConfigError("spawn: no room for " + std::to_string(n) +
                             " boids outside the obstacles (grown by the probe radius)");
    const V3f pos = p_.spawn.min + V3f(unit_float(rng) * extent.x, unit_float(rng) * extent.y,
                                       unit_float(rng) * extent.z);
    bool clear = true;
    for (const SphereObstacle& s : p_.obstacles) {
      const float keep = s.radius + p_.probe_radius + p_.boid_radius;
      clear = clear && (pos - s.centre).length2() > keep * keep;
    }
    V3f jitter_direction(2.0f * unit_float(rng) - 1.0f, 2.0f * unit_float(rng) - 1.0f,
                         2.0f * unit_float(rng) - 1.0f);
    if (!clear) continue;
    position_.push_back(pos);
    velocity_.push_back(truncated(p_.spawn_velocity + jitter * jitter_direction, p_.max_speed));
  }
  next_position_.resize(n);
  next_velocity_.resize(n);
  heading_.resize(n);
}

V3f Flock::steering(size_t i) const {
  const V3f& p = position_[i];
  const V3f& v = velocity_[i];
  const float speed = v.length();
  // A boid at rest still has a heading, so it can see and be steered.
  const V3f d = speed > 0.0f ? v / speed : V3f(1.0f, 0.0f, 0.0f);

  V3f separation(0.0f), heading_sum(0.0f), centre_sum(0.0f);
  int neighbours = 0;
  const float r2 = p_.neighbour_radius * p_.neighbour_radius;
  const float s2 = p_.separation_radius * p_.separation_radius;
  grid_.for_each_candidate(p, [&](uint32_t j) {
    if (j == i) return;
    const V3f offset = position_[j] - p;
    const float d2 = offset.length2();
    if (d2 > r2 || d2 == 0.0f) return;  // a boid on top of this one gives no direction
    if (cos_half_fov_ > -1.0f && offset.dot(d) < cos_half_fov_ * std::sqrt(d2)) return;
    heading_sum += heading_[j];
    centre_sum += position_[j];
    ++neighbours;
    // Away, from full strength at contact to nothing at the separation radius.
    if (d2 < s2) {
      const float distance = std::sqrt(d2);
      separation -= offset * ((1.0f - distance / p_.separation_radius) / distance);
    }
  });

  const auto towards = [&](const V3f& desired) { return truncated(desired - v, p_.max_force); };
  SteeringBudget budget(p_.max_force);

  const ProbeShape probe{p_.probe_radius, p_.look_ahead};
  const Avoidance avoidance = avoid_spheres(p, d, speed, p_.obstacles, probe, p_.max_force);
  budget.add(p_.avoidance_weight * avoidance.force);
  // Near a sphere, nothing that follows may steer a boid into it: the flock's pull towards a
  // neighbour on the far side would otherwise undo the push out.
  budget.keep_out_of(&avoidance);

  V3f wall(0.0f);
  if (p_.bounds_margin > 0.0f) {
    for (int axis = 0; axis < 3; ++axis) {
      const float low = p_.bounds.min[axis] + p_.bounds_margin - p[axis];
      const float high = p[axis] - (p_.bounds.max[axis] - p_.bounds_margin);
      if (low > 0.0f) wall[axis] += low / p_.bounds_margin;
      if (high > 0.0f) wall[axis] -= high / p_.bounds_margin;
    }
  }
  budget.add(wall * p_.max_force);

  // Holding the cruise speed comes before the flock's pulls: it acts along the heading only,
  // and a flock whose members' pulls spend the whole budget would otherwise huddle and stall.
  budget.add(p_.cruise_weight * truncated((p_.cruise_speed - speed) * d, p_.max_force));
  // Separation, alignment and cohesion turn a boid; only the cruise and the migratory urge
  // change its speed. Written as velocity matching (desired - v) they would each also brake
  // it, and a flock whose pulls disagree would crawl.
  budget.add(p_.separation_weight * p_.max_force * truncated(separation, 1.0f));
  if (neighbours > 0) {
    if (heading_sum.length2() > 0.0f)
      budget.add(p_.alignment_weight *
                 truncated(heading_sum.normalized() * speed - v, p_.max_force));
    const V3f to_centre = centre_sum / static_cast<float>(neighbours) - p;
    budget.add(p_.cohesion_weight * p_.max_force *
               truncated(to_centre / p_.neighbour_radius, 1.0f));
  }
  if (p_.migration_weight > 0.0f) budget.add(p_.migration_weight * towards(p_.migration));
  return budget.total();
}

void Flock::step() {
  grid_.build(position_);
  const float dt = p_.time_step;
  arena_.execute([&] {
    // Each boid's unit heading once per step, not once for every boid that sees it.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, velocity_.size(), 1024),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i) {
                          const float speed = velocity_[i].length();
                          heading_[i] = speed > 0.0f ? velocity_[i] / speed : V3f(0.0f);
                        }
                      });
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, position_.size(), 256),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            V3f v = truncated(velocity_[i] + steering(i) * dt, p_.max_speed);
            V3f x = position_[i] + v * dt;
            // The box is a hard wall: a boid that crosses it bounces back in.
            for (int axis = 0; axis < 3; ++axis) {
              if (x[axis] < p_.bounds.min[axis]) {
                x[axis] = std::min(2.0f * p_.bounds.min[axis] - x[axis], p_.bounds.max[axis]);
                v[axis] = std::fabs(v[axis]);
              } else if (x[axis] > p_.bounds.max[axis]) {
                x[axis] = std::max(2.0f * p_.bounds.max[axis] - x[axis], p_.bounds.min[axis]);
                v[axis] = -std::fabs(v[axis]);
              }
            }
            next_position_[i] = x;
            next_velocity_[i] = v;
          }
        });
  });
  position_.swap(next_position_);
  velocity_.swap(next_velocity_);
  ++steps_;
}

}  // namespace prism
