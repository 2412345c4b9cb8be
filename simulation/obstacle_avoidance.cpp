#include "simulation/obstacle_avoidance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/geometry/sphere_intersect.h"

namespace prism {

using Imath::V3f;

V3f fallback_turn(const V3f& d) {
  // Turning sideways (perpendicular to both the heading and the vertical) keeps a flock in
  // its layer. No perpendicular is continuous over every heading (the hairy ball theorem),
  // so a heading within ~6 degrees of vertical switches to a turn about the x axis.
  V3f side = d.cross(V3f(0.0f, 1.0f, 0.0f));
  if (side.length2() < 1e-2f) side = d.cross(V3f(1.0f, 0.0f, 0.0f));
  return side.normalized();
}

ProbeResult probe_sphere(const V3f& o, const V3f& d, float speed, const SphereObstacle& sphere,
                         const ProbeShape& probe, float max_force) {
  ProbeResult result;
  const float grown = sphere.radius + probe.radius;
  const V3f to_centre = sphere.centre - o;
  const float along = to_centre.dot(d);  // |OE|, signed
  const V3f e = o + along * d;
  const V3f off_line = e - sphere.centre;
  result.miss_distance = off_line.length();

  // Beyond reach of the cylinder whatever the heading: no ray test needed.
  const float reach = grown + probe.look_ahead;
  if (to_centre.length2() > reach * reach) {
    result.kind = along < 0.0f ? ProbeCase::behind : ProbeCase::miss;
    return result;
  }
  // An unbounded far end, so a boid deep inside a sphere larger than the look-ahead still
  // sees the exit root, which is how the test says the origin is inside.
  const auto root =
      intersect_sphere(o, d, sphere.centre, grown, 0.0f, std::numeric_limits<float>::infinity());
  if (root && root->exiting) {
    result.kind = ProbeCase::inside;
    const V3f out = -to_centre;
    const float length = out.length();
    // From nothing at the grown surface to max_force at the sphere's own surface and more
    // within it, so a boid between two spheres is pushed off the nearer harder.
    const float depth = (grown - length) / probe.radius;
    result.force = (length > 0.0f ? out / length : fallback_turn(d)) * (max_force * depth);
    return result;
  }
  if (!root || root->t > probe.look_ahead) {
    result.kind = along < 0.0f ? ProbeCase::behind : ProbeCase::miss;
    return result;
  }
  result.kind = result.miss_distance < sphere.radius ? ProbeCase::hit : ProbeCase::skim;
  result.t = root->t;
  // Heading at the centre to within rounding, E - C has no direction of its own: turn the
  // way the heading alone decides, so the choice does not flicker between steps.
  const V3f direction =
      result.miss_distance > 1e-4f * grown ? off_line / result.miss_distance : fallback_turn(d);
  // The lateral acceleration that would carry the line of travel out of the grown sphere
  // by the time the boid reaches it (s = a t'^2 / 2 with t' = t / speed). t is kept at least
  // r so that a boid just touching the grown sphere gets a large force, not an infinite one.
  const float clear = grown - result.miss_distance;
  const float t = std::max(result.t, probe.radius);
  result.force = direction * (2.0f * clear * speed * speed / (t * t));
  return result;
}

V3f Avoidance::without_inward(V3f f) const {
  for (int k = 0; k < inside; ++k) {
    const float along = f.dot(outward[static_cast<size_t>(k)]);
    if (along < 0.0f) f -= along * outward[static_cast<size_t>(k)];
  }
  return f;
}

Avoidance avoid_spheres(const V3f& o, const V3f& d, float speed,
                        std::span<const SphereObstacle> spheres, const ProbeShape& probe,
                        float max_force) {
  Avoidance result;
  V3f nearest_force(0.0f);
  float nearest_t = std::numeric_limits<float>::infinity();
  for (const SphereObstacle& sphere : spheres) {
    const ProbeResult r = probe_sphere(o, d, speed, sphere, probe, max_force);
    if (r.kind == ProbeCase::inside) {
      result.force += r.force;
      const V3f out = o - sphere.centre;
      if (result.inside < Avoidance::kMaxInside && out.length2() > 0.0f)
        result.outward[static_cast<size_t>(result.inside++)] = out.normalized();
    } else if ((r.kind == ProbeCase::hit || r.kind == ProbeCase::skim) && r.t < nearest_t) {
      nearest_t = r.t;
      nearest_force = r.force;
    }
  }
  result.force += nearest_force;
  return result;
}

}  // namespace prism
