// Maps from the unit square to directions, with their densities: what BSDF and light
// sampling turn two sample dimensions into. Directions are built in a frame around an axis
// (from_local), so a lobe is sampled about whatever direction it is centred on.
#pragma once

#include <cmath>

#include <Imath/ImathVec.h>

#include "renderer/math.h"

namespace prism {

// The tangents t, s of the frame whose z is `axis` (unit): Duff et al.'s branchless basis
// ("Building an Orthonormal Basis, Revisited", 2017), continuous except at axis.z = -0.
inline void orthonormal_basis(const Imath::V3f& axis, Imath::V3f* t, Imath::V3f* s) {
  const float sign = std::copysign(1.0f, axis.z);
  const float a = -1.0f / (sign + axis.z);
  const float b = axis.x * axis.y * a;
  *t = Imath::V3f(1.0f + sign * axis.x * axis.x * a, sign * b, -sign * axis.x);
  *s = Imath::V3f(b, sign + axis.y * axis.y * a, -axis.y);
}

// A unit vector given in the frame whose z is `axis`, in world space.
inline Imath::V3f from_local(const Imath::V3f& local, const Imath::V3f& axis) {
  Imath::V3f t, s;
  orthonormal_basis(axis, &t, &s);
  return t * local.x + s * local.y + axis * local.z;
}

// The inverse of from_local: a world vector in the frame whose z is `axis`.
inline Imath::V3f to_local(const Imath::V3f& world, const Imath::V3f& axis) {
  Imath::V3f t, s;
  orthonormal_basis(axis, &t, &s);
  return Imath::V3f(t.dot(world), s.dot(world), axis.dot(world));
}

// Cosine-weighted hemisphere about +z (Malley's method on a concentric disc): pdf cos / pi.
inline Imath::V3f square_to_cosine_hemisphere(const Imath::V2f& u) {
  const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
  float r = 0.0f, phi = 0.0f;
  if (ox != 0.0f || oy != 0.0f) {
    if (std::fabs(ox) > std::fabs(oy)) {
      r = ox;
      phi = 0.25f * kPi * (oy / ox);
    } else {
      r = oy;
      phi = 0.5f * kPi - 0.25f * kPi * (ox / oy);
    }
  }
  const float x = r * std::cos(phi), y = r * std::sin(phi);
  return Imath::V3f(x, y, std::sqrt(fmax_inline(0.0f, 1.0f - x * x - y * y)));
}

// Density cos^n(alpha) (n + 1) / (2 pi) about +z, alpha the angle from +z: the normalised
// Phong lobe's own shape, so sampling it has the lobe's variance, not the hemisphere's.
inline Imath::V3f square_to_cosine_power(const Imath::V2f& u, float n) {
  const float cos_alpha = std::pow(1.0f - u.x, 1.0f / (n + 1.0f));
  const float sin_alpha = std::sqrt(fmax_inline(0.0f, 1.0f - cos_alpha * cos_alpha));
  const float phi = 2.0f * kPi * u.y;
  return Imath::V3f(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha);
}
inline float cosine_power_pdf(float cos_alpha, float n) {
  return (n + 1.0f) * (0.5f * kInvPi) * std::pow(cos_alpha, n);
}

}  // namespace prism
