// Directions uniformly distributed over the solid angle a triangle subtends (Arvo 1995,
// "Stratified Sampling of Spherical Triangles"): a light sampled this way has no 1/d^2 in its
// estimator, which is what makes a large light seen from close by (a Cornell box's ceiling
// panel from the walls beside it) noisy when it is sampled by area.
//
// The arithmetic is in double: the construction subtracts nearly equal cosines when the
// triangle is small, and float loses the sample's position there long before double does.
// Callers keep area sampling for triangles that subtend little (where it is already close to
// uniform in solid angle and cheaper), so the small-angle corner is never the common case.
#pragma once

#include <cmath>

#include <Imath/ImathVec.h>

namespace prism {

// The triangle seen from a point: unit directions towards its corners.
struct SphericalTriangle {
  Imath::V3d a, b, c;
};

namespace spherical_triangle_detail {

inline Imath::V3d unit_normal(const Imath::V3d& u, const Imath::V3d& v) {
  const Imath::V3d c = u.cross(v);
  const double len = c.length();
  return len > 0.0 ? c / len : Imath::V3d(0.0);
}

// The part of `v` orthogonal to unit `axis`, made unit; `axis` itself when none is left.
inline Imath::V3d orthogonal_unit(const Imath::V3d& v, const Imath::V3d& axis) {
  const Imath::V3d w = v - axis * v.dot(axis);
  const double len = w.length();
  return len > 0.0 ? w / len : axis;
}

}  // namespace spherical_triangle_detail

// The triangle `corners` as seen from `point`; false when `point` is on a corner.
inline bool spherical_triangle_from(const Imath::V3f& point, const Imath::V3f* corners,
                                    SphericalTriangle* out) {
  Imath::V3d d[3];
  for (int i = 0; i < 3; ++i) {
    d[i] = Imath::V3d(corners[i]) - Imath::V3d(point);
    const double len = d[i].length();
    if (!(len > 0.0)) return false;
    d[i] /= len;
  }
  *out = SphericalTriangle{d[0], d[1], d[2]};
  return true;
}

// The solid angle, by Van Oosterom and Strackee's formula (one atan2, accurate for small
// triangles, where Girard's angle sum cancels).
inline double spherical_triangle_area(const SphericalTriangle& t) {
  const double triple = std::fabs(t.a.dot(t.b.cross(t.c)));
  return 2.0 * std::atan2(triple, 1.0 + t.a.dot(t.b) + t.b.dot(t.c) + t.c.dot(t.a));
}

// A direction uniformly distributed over the triangle's solid angle `area` (as given by
// spherical_triangle_area), drawn from (u0, u1) in [0,1)^2; its density is 1 / area. u0 picks
// the sub-triangle of area u0 x area that shares the corner a, u1 the point along the arc
// from b to that sub-triangle's third corner.
inline Imath::V3d sample_spherical_triangle(const SphericalTriangle& t, double area, double u0,
                                            double u1) {
  using spherical_triangle_detail::orthogonal_unit;
  using spherical_triangle_detail::unit_normal;
  // The angle alpha at a, between the great circles through a and b and through a and c: its
  // cosine and sine from the circles' normals, so that no angle needs an inverse cosine.
  const Imath::V3d n_ab = unit_normal(t.a, t.b), n_ac = unit_normal(t.a, t.c);
  const double cos_alpha = n_ab.dot(n_ac), sin_alpha = n_ab.cross(n_ac).length();
  const double sub_area = u0 * area;
  const double sin_sub = std::sin(sub_area), cos_sub = std::cos(sub_area);
  // sin and cos of (sub_area - alpha).
  const double s = sin_sub * cos_alpha - cos_sub * sin_alpha;
  const double c = cos_sub * cos_alpha + sin_sub * sin_alpha;
  const double p = c - cos_alpha;
  const double q = s + sin_alpha * t.a.dot(t.b);
  // The cosine of the arc from a to the sub-triangle's third corner, on the arc from a to c.
  const double denominator = (q * s + p * c) * sin_alpha;
  double cos_arc = denominator != 0.0 ? ((q * c - p * s) * cos_alpha - q) / denominator : 1.0;
  cos_arc = std::fmin(1.0, std::fmax(-1.0, cos_arc));
  const Imath::V3d corner =
      t.a * cos_arc + orthogonal_unit(t.c, t.a) * std::sqrt(1.0 - cos_arc * cos_arc);
  const double z = std::fmin(1.0, std::fmax(-1.0, 1.0 - u1 * (1.0 - corner.dot(t.b))));
  return t.b * z + orthogonal_unit(corner, t.b) * std::sqrt(1.0 - z * z);
}

}  // namespace prism
