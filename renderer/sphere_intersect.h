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
  // hit point - centre, unnormalised, pointing out of the sphere: the exact offset for these
  // float inputs, rounded once (see below). Built from the closest approach rather than
  // o + t d - centre, so it inherits none of t's rounding.
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
  // c is the one input formed in double. For an origin near the surface (every secondary
  // ray) f.f and r^2 cancel almost entirely, and the small root c / q below inherits c's
  // relative error: in float 2e-5 for an origin 10^-4 r off the surface, in double none.
  // o - centre is exact in double unless the two differ in magnitude by over 2^29, and the
  // squares of its float-sized components are exact too.
  const Imath::V3d fd(double(o.x) - centre.x, double(o.y) - centre.y, double(o.z) - centre.z);
  const float c = float(fd.dot(fd) - double(radius) * radius);

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
  // hit - centre = f + t d = l + (t - b'/a) d, and t - b'/a is exactly -+ sqrt(delta / a) for
  // the entering / exiting root. In float, l carries the ~|f| eps rounding of its
  // cancellation, which at 10^5 radii tilts the normal by a degree; in double the same steps
  // cost a few scalar operations and leave only the final rounding to float. delta is clamped
  // because a ray float calls a hit may pass a hair outside in exact arithmetic; then the tangent
  // point is the answer.
  const Imath::V3d dd(d.x, d.y, d.z);
  const double ad = dd.dot(dd);
  const Imath::V3d ld = fd - (fd.dot(dd) / ad) * dd;
  const double along = std::sqrt(std::fmax(0.0, double(radius) * radius - ld.dot(ld)) / ad);
  const Imath::V3d offset = ld + (root.exiting ? along : -along) * dd;
  root.offset = Imath::V3f(float(offset.x), float(offset.y), float(offset.z));
  return root;
}

}  // namespace prism
