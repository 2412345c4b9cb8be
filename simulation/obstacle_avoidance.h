// Obstacle avoidance by a probe cylinder (Reynolds, "Steering Behaviors for Autonomous
// Characters", GDC 1999): a boid at O heading along the unit D sweeps a cylinder of radius r
// and length L ahead of it; a sphere (C, R) is in the way when the cylinder meets it, which is
// when the ray O + tD, 0 <= t <= L, meets the sphere grown to R + r. That ray test is the
// renderer's own (renderer/geometry/sphere_intersect.h), not a second copy of the algebra.
#pragma once

#include <array>
#include <span>

#include <Imath/ImathVec.h>

#include "simulation/flock_config.h"

namespace prism {

// The lecture's five situations.
enum class ProbeCase {
  miss,    // the sphere is ahead but the cylinder passes it, or it is beyond the look-ahead
  behind,  // the sphere is behind the boid
  skim,    // the line of travel misses the sphere but the cylinder clips it
  hit,     // the line of travel meets the sphere itself
  inside,  // the boid is already within the grown sphere
};

struct ProbeResult {
  ProbeCase kind = ProbeCase::miss;
  // Distance along D to where the cylinder first meets the sphere (0 when inside).
  float t = 0.0f;
  // |E - C|, E the closest point to C on the line of travel: the predicted miss distance
  // of the boid's centre from the sphere's centre.
  float miss_distance = 0.0f;
  // The steering acceleration: zero for miss and behind.
  Imath::V3f force{0.0f};
};

struct ProbeShape {
  float radius = 0.3f;      // the cylinder's radius
  float look_ahead = 3.0f;  // its length
};

// A unit vector perpendicular to the unit `d`, a continuous function of d: the direction a
// boid heading straight at a centre (E = C) turns to. It depends on nothing but the heading,
// so it stays the same from step to step while the heading does.
Imath::V3f fallback_turn(const Imath::V3f& d);

// One sphere against the probe of a boid at `o` moving at `speed` along the unit `d`.
// For skim and hit the force is the lecture's: f = (E - C)/|E - C|, perpendicular to D, scaled
// by the lateral acceleration that would carry the cylinder clear of the grown sphere before
// reaching it: 2 (R + r - |E - C|) speed^2 / t^2, which rises as the miss distance falls.
// Inside, the force points out along O - C, max_force times the depth below the grown
// surface in probe radii (max_force at the sphere's own surface).
ProbeResult probe_sphere(const Imath::V3f& o, const Imath::V3f& d, float speed,
                         const SphereObstacle& sphere, const ProbeShape& probe, float max_force);

// What the probe decides for one boid against every sphere.
struct Avoidance {
  // The pushes out of all spheres the boid is inside, plus the force of the nearest sphere
  // ahead (skim or hit), the one to deal with first.
  Imath::V3f force{0.0f};
  // The outward directions of the first kMaxInside spheres the boid is inside: no other
  // behaviour may steer it further in.
  static constexpr int kMaxInside = 4;
  int inside = 0;
  std::array<Imath::V3f, kMaxInside> outward;

  // `f` without its parts that point into a sphere the boid is inside.
  Imath::V3f without_inward(Imath::V3f f) const;
};

Avoidance avoid_spheres(const Imath::V3f& o, const Imath::V3f& d, float speed,
                        std::span<const SphereObstacle> spheres, const ProbeShape& probe,
                        float max_force);

}  // namespace prism
