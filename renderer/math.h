// Small vector helpers on top of Imath that the shading and ray code share.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>

namespace prism {

using Imath::V3f;

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;

// std::fmax and std::fmin of two floats, with the result glibc's gives on x86-64 for every
// input (the first argument unless the second is strictly greater/smaller or the first is a
// NaN, so fmax(+0, -0) is +0 and fmax(-0, +0) is -0), but inline: without -ffast-math GCC calls
// libm for them, and a call inside a BSDF costs the spill of every live float register too.
// Floats only, checked at compile time: a double would be narrowed silently.
template <typename A, typename B>
inline float fmax_inline(A a, B b) {
  static_assert(std::is_same_v<A, float> && std::is_same_v<B, float>, "floats only");
  return (a >= b || b != b) ? a : b;
}
template <typename A, typename B>
inline float fmin_inline(A a, B b) {
  static_assert(std::is_same_v<A, float> && std::is_same_v<B, float>, "floats only");
  return (a <= b || b != b) ? a : b;
}

// Rec. 709 luminance, never negative: what weighs one colour against another in a choice.
inline float luminance(const V3f& c) {
  return fmax_inline(0.0f, 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
}

inline float max_component(const V3f& c) {
  return fmax_inline(c.x, fmax_inline(c.y, c.z));
}

inline bool is_finite(const V3f& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline bool is_finite(const Imath::M44d& m) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m[i][j])) return false;
  return true;
}

inline float dot(const V3f& a, const V3f& b) {
  return a.dot(b);
}
inline V3f cross(const V3f& a, const V3f& b) {
  return a.cross(b);
}
inline V3f normalize(const V3f& v) {
  return v.normalized();
}
inline V3f hadamard(const V3f& a, const V3f& b) {
  return V3f(a.x * b.x, a.y * b.y, a.z * b.z);
}

// Mirror reflection of the incident direction d (pointing at the surface) about n.
inline V3f reflect(const V3f& d, const V3f& n) {
  return d - 2.0f * dot(d, n) * n;
}

// n flipped, if need be, onto the same side as `reference`.
inline V3f face_forward(const V3f& n, const V3f& reference) {
  return dot(n, reference) < 0.0f ? -n : n;
}

// The spacing of floats just above |x|: one ulp of x.
inline float ulp_of(float x) {
  const float a = std::fabs(x);
  return std::bit_cast<float>(std::bit_cast<int32_t>(a) + 1) - a;
}

// The neighbouring float towards +infinity (towards -infinity for next_float_down): what
// std::nextafter(x, +-infinity) gives for every x, NaN aside, inline instead of a call into
// libm on every secondary ray (it cost 1.4 % of a shadow render). Infinities stay.
inline float next_float_up(float x) {
  if (x == std::numeric_limits<float>::infinity()) return x;
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();  // +0 and -0
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits + 1 : bits - 1);
}
inline float next_float_down(float x) {
  return -next_float_up(-x);
}

// Moves a hit point off its surface so that a ray leaving along `n`'s side cannot hit the
// same surface again. `n` must point to the side the new ray leaves on.
//
// A rebuilt hit point is trusted to a bounded number of ulps of each of its coordinates
// (Waechter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
// Tracing Gems ch. 6, whose constants are used here: 256 ulps, and 2^-16 absolute for
// coordinates within 1/32 of the origin, where ulps become too small to cover the error of
// the vertices the point was built from). How far off the surface that can put the point is
// the sum over coordinates of |n_i| times coordinate i's error, so the point moves along n
// by that distance (the form of pbrt-v4's OffsetRayOrigin), and each moved coordinate is
// then pushed one more float outward so rounding the sum cannot give any of it back.
//
// Moving each coordinate by 256 of its own ulps times n_i, as Waechter and Binder do, is
// not enough when the coordinates differ in magnitude: a coordinate with |n_i| < 1/256
// gets no offset at all, yet its rounding error, times |n_i|, can be far larger than what
// the small coordinates' offsets add up to (a triangle 8e10 long in z with its normal
// within 2e-4 of +y, hit at y = 0.03: tests/stress/02_reintersect_test.cpp).
//
// `surface_error` adds how far the intersector may misplace the surface itself (see
// SurfaceHit::surface_error), which no bound on the point's own rounding can know.
inline V3f offset_ray_origin(const V3f& p, const V3f& n, float surface_error = 0.0f) {
  constexpr float kOriginBand = 1.0f / 32.0f;
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  float distance = surface_error;
  for (int i = 0; i < 3; ++i) {
    const float error = std::fabs(p[i]) < kOriginBand ? kFloatScale : kIntScale * ulp_of(p[i]);
    distance += std::fabs(n[i]) * error;
  }
  V3f out;
  for (int i = 0; i < 3; ++i) {
    const float step = distance * n[i];
    const float moved = p[i] + step;
    out[i] = step > 0.0f ? next_float_up(moved) : step < 0.0f ? next_float_down(moved) : moved;
  }
  return out;
}

// Fresnel reflectance of a smooth dielectric boundary for unpolarised light.
// cos_i is the cosine between the incident direction's reverse and the normal on the side
// the light comes from; eta = n_transmitted / n_incident. Returns 1 under total internal
// reflection. cos_t receives the cosine of the refracted direction (0 under TIR).
inline float fresnel_dielectric(float cos_i, float eta, float* cos_t_out = nullptr) {
  if (cos_i < 0.0f) {
    eta = 1.0f / eta;
    cos_i = -cos_i;
  }
  const float sin2_i = fmax_inline(0.0f, 1.0f - cos_i * cos_i);
  const float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1.0f) {
    if (cos_t_out) *cos_t_out = 0.0f;
    return 1.0f;
  }
  const float cos_t = std::sqrt(1.0f - sin2_t);
  if (cos_t_out) *cos_t_out = cos_t;
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// Refraction of the incident direction d (unit, pointing at the surface) through a surface
// with unit normal n facing the incident side, eta = n_transmitted / n_incident.
// Returns false under total internal reflection.
inline bool refract(const V3f& d, const V3f& n, float eta, V3f* out) {
  const float cos_i = -dot(d, n);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return false;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  *out = normalize(d / eta + (cos_i / eta - cos_t) * n);
  return true;
}

}  // namespace prism
