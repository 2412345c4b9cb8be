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
  // The whole test runs in double on the float inputs and rounds t and the offset to float
  // once. o - centre is exact in double unless the two differ in magnitude by over 2^29, and
  // the squares of float-sized components are exact, so what is left is the robust form's own
  // small error: t within half an ulp for a unit sphere 10^5 away (tests/stress/01), where the
  // same form in float is off by up to 37 ulps for rays grazing the rim.
  const Imath::V3d dd(d.x, d.y, d.z);
  const double a = dd.dot(dd);
  if (!(a > 0.0)) return std::nullopt;  // a zero or NaN direction never hits
  const Imath::V3d f(double(o.x) - centre.x, double(o.y) - centre.y, double(o.z) - centre.z);
  const double r2 = double(radius) * radius;
  const double b_half = -f.dot(dd);  // b' = -b / 2
  // c = f.f - r^2 cancels almost entirely for an origin near the surface (every secondary
  // ray); the small root c / q below inherits its relative error.
  const double c = f.dot(f) - r2;

  // The quarter discriminant b'^2 - a c equals a (r^2 - |l|^2), where l = f + (b'/a) d is the
  // vector from the centre to the ray's closest approach:
  //   |l|^2 = f.f - 2 (f.d)^2 / a + (f.d)^2 / a = f.f - (f.d)^2 / a,
  //   a (r^2 - |l|^2) = a r^2 - a f.f + (f.d)^2 = b'^2 - a (f.f - r^2) = b'^2 - a c.
  // b'^2 and a c are both ~|f|^2 and their difference ~r^2; l is ~r, so r^2 - |l|^2 only
  // carries l's own rounding (~|f| eps from the projection) instead of |f|^2 eps.
  const Imath::V3d l = f + (b_half / a) * dd;
  const double delta = r2 - l.dot(l);
  if (!(delta >= 0.0)) return std::nullopt;  // also rejects NaN inputs

  // The two roots are (b' -+ sqrt(a delta)) / a. Adding the square root with b''s sign never
  // cancels; the other root then follows from t0 t1 = c / a without a subtraction.
  const double q = b_half + std::copysign(std::sqrt(a * delta), b_half);
  double t_small, t_large;
  if (q == 0.0) {
    // b' = 0 and delta = 0: the origin is the tangent point, a double root at 0.
    t_small = t_large = 0.0;
  } else {
    const double t0 = c / q, t1 = q / a;
    t_small = std::fmin(t0, t1);
    t_large = std::fmax(t0, t1);
  }

  SphereRoot root;
  const auto in_range = [&](double t) {
    return static_cast<float>(t) >= tnear && static_cast<float>(t) <= tfar;
  };
  if (in_range(t_small)) {
    root.t = static_cast<float>(t_small);
    root.exiting = false;
  } else if (in_range(t_large)) {
    root.t = static_cast<float>(t_large);
    root.exiting = true;
  } else {
    return std::nullopt;
  }
  // hit - centre = f + t d = l + (t - b'/a) d, and t - b'/a is exactly -+ sqrt(delta / a) for
  // the entering / exiting root, so the offset inherits none of t's rounding and the normal
  // stays exact at any distance.
  const double along = std::sqrt(delta / a);
  const Imath::V3d offset = l + (root.exiting ? along : -along) * dd;
  root.offset = Imath::V3f(float(offset.x), float(offset.y), float(offset.z));
  return root;
}

}  // namespace prism
