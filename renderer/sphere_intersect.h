// Ray/sphere intersection that stays accurate for small, distant and grazed spheres.
//
// The textbook test solves a t^2 + b t + c = 0 with b^2 - 4ac. In float that subtracts two
// numbers of size |O - C|^2 to get something of size r^2, so a unit sphere 10^4 units away has
// lost every bit of its discriminant (ulp(1e8) = 8 > r^2), and the root (-b +- sqrt) / 2a
// cancels again whenever one root is near 0. This follows Haines, Guenther and
// Akenine-Moller, "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
// (2019), ch. 7: measure the discriminant at the ray's closest approach, and take the roots
// from Vieta's formulas so neither involves a cancelling subtraction. docs/spheres-rendering.md
// has the measured errors.
#pragma once

#include <cmath>
#include <optional>

#include <Imath/ImathVec.h>

namespace prism {

struct SphereRoot {
  float t = 0.0f;
  // The root is the larger of the two: the ray meets the sphere from inside (its origin is
  // inside, or the near root lies before tnear), so it is leaving the surface here.
  bool exiting = false;
  // hit point - centre, unnormalised, pointing out of the sphere. Built from the closest
  // approach rather than o + t d - centre, so it does not subtract two numbers of size
  // |o - centre| and inherits no error from t.
  Imath::V3f offset;
};

// The nearest root of |o + t d - centre| = radius with tnear <= t <= tfar. The range is
// closed at both ends, as for Embree's own primitives, so every sphere mode agrees on a hit
// exactly at tnear. d need not be normalised; t is in units of |d|.
inline std::optional<SphereRoot> intersect_sphere(const Imath::V3f& o, const Imath::V3f& d,
                                                  const Imath::V3f& centre, float radius,
                                                  float tnear, float tfar) {
  const Imath::V3f f = o - centre;
  const float a = d.dot(d);
  if (!(a > 0.0f)) return std::nullopt;  // a zero or NaN direction never hits
  const float b_half = -f.dot(d);        // b' = -b / 2
  const float c = f.dot(f) - radius * radius;

  // The quarter discriminant b'^2 - a c equals a (r^2 - |l|^2), where l = f + (b'/a) d is the
  // vector from the centre to the ray's closest approach:
  //   |l|^2 = f.f - 2 (f.d)^2 / a + (f.d)^2 / a = f.f - (f.d)^2 / a,
  //   a (r^2 - |l|^2) = a r^2 - a f.f + (f.d)^2 = b'^2 - a (f.f - r^2) = b'^2 - a c.
  // b'^2 and a c are both ~|f|^2 and their difference ~r^2; l is ~r, so r^2 - |l|^2 only
  // carries l's own rounding (~|f| eps from the projection) instead of |f|^2 eps.
  const Imath::V3f l = f + (b_half / a) * d;
  const float delta = radius * radius - l.dot(l);
  if (delta < 0.0f) return std::nullopt;  // NaN inputs fail the tests below instead

  // The two roots are (b' -+ sqrt(a delta)) / a. Adding the square root with b''s sign never
  // cancels; the other root then follows from t0 t1 = c / a without a subtraction.
  const float s = std::sqrt(a * delta);
  const float q = b_half + std::copysign(s, b_half);
  float t_small, t_large;
  if (q == 0.0f) {
    // b' = 0 and delta = 0: the origin is the tangent point, a double root at 0.
    t_small = t_large = 0.0f;
  } else {
    const float t0 = c / q;
    const float t1 = q / a;
    t_small = std::fmin(t0, t1);
    t_large = std::fmax(t0, t1);
  }

  SphereRoot root;
  if (t_small >= tnear && t_small <= tfar) {
    root.t = t_small;
    root.exiting = false;
  } else if (t_large >= tnear && t_large <= tfar) {
    root.t = t_large;
    root.exiting = true;
  } else {
    return std::nullopt;
  }
  // hit - centre = f + t d = l + (t - b'/a) d, and t - b'/a is exactly -+ s / a for the
  // entering / exiting root.
  const float along = s / a;
  root.offset = l + (root.exiting ? along : -along) * d;
  return root;
}

}  // namespace prism
