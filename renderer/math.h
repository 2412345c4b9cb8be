// Small vector helpers on top of Imath that the shading and ray code share.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include <Imath/ImathVec.h>

namespace prism {

using Imath::V3f;

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;

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

// Moves a hit point off its surface so that a ray leaving along `n`'s side cannot hit the
// same surface again. The offset is a fixed number of ulps of each coordinate rather than a
// fixed distance, so it scales with the magnitude of the position (Waechter and Binder,
// "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6). Near
// the origin, where ulps become tiny, a small absolute offset takes over. `n` must point to
// the side the new ray leaves on.
inline V3f offset_ray_origin(const V3f& p, const V3f& n) {
  constexpr float kOriginBand = 1.0f / 32.0f;
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  V3f out;
  for (int i = 0; i < 3; ++i) {
    const auto ulps = static_cast<int32_t>(kIntScale * n[i]);
    const auto bits = std::bit_cast<int32_t>(p[i]);
    const float moved = std::bit_cast<float>(bits + (p[i] < 0.0f ? -ulps : ulps));
    out[i] = std::fabs(p[i]) < kOriginBand ? p[i] + kFloatScale * n[i] : moved;
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
  const float sin2_i = std::fmax(0.0f, 1.0f - cos_i * cos_i);
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
