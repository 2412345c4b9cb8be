// The GGX (Trowbridge-Reitz) microfacet lobe as glTF 2.0's specification, Appendix B, defines
// it: the distribution D with alpha = roughness^2, the height-correlated Smith visibility
// V = G / (4 |N.L| |N.V|), and Schlick's Fresnel weight. All cosines are taken against the
// shading normal, in the frame the caller chooses; the functions see only the cosines, so
// the same code serves eval, pdf and the albedo tables.
//
// Sampling is Heitz's visible-normal distribution ("Sampling the GGX Distribution of
// Visible Normals", JCGT 2018), in the local frame where the normal is +z.
#pragma once

#include <algorithm>
#include <cmath>

#include <Imath/ImathVec.h>

#include "renderer/math.h"

namespace prism {

// The smallest alpha the lobe is evaluated with: below it D's peak (1 / (pi alpha^2)) is
// past what float cosines resolve (1 - cos^2 loses every digit near the peak), and the
// surface is a mirror for every integrator that traces one anyway.
inline constexpr float kMinGgxAlpha = 1e-3f;

// (1 - cos)^5, Schlick's weight: F = F0 + (F90 - F0) schlick_weight(cos).
inline float schlick_weight(float cos_theta) {
  const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  return (m * m) * (m * m) * m;
}

// D(h) for cos_h = N.H > 0, with sin^2 from the caller so that it can be exact near the peak.
inline float ggx_d(float cos_h, float alpha) {
  if (!(cos_h > 0.0f)) return 0.0f;
  const float a2 = alpha * alpha;
  const float c2 = cos_h * cos_h;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// The height-correlated Smith visibility for |N.L| = cos_l and |N.V| = cos_v (glTF's V).
inline float ggx_visibility(float cos_l, float cos_v, float alpha) {
  const float a2 = alpha * alpha;
  const float gv = cos_l * std::sqrt(cos_v * cos_v * (1.0f - a2) + a2);
  const float gl = cos_v * std::sqrt(cos_l * cos_l * (1.0f - a2) + a2);
  const float sum = gv + gl;
  return sum > 0.0f ? 0.5f / sum : 0.0f;
}

// Smith's masking for one direction, G1(v) = 2 cos / (cos + sqrt(a^2 + (1 - a^2) cos^2)).
inline float ggx_g1(float cos_v, float alpha) {
  const float a2 = alpha * alpha;
  return 2.0f * cos_v / (cos_v + std::sqrt(a2 + (1.0f - a2) * cos_v * cos_v));
}

// A microfacet normal drawn with density D_v(h) = G1(v) max(0, v.h) D(h) / cos_v for the
// view direction v (local frame, v.z > 0), from u in [0, 1)^2.
inline Imath::V3f sample_ggx_visible_normal(const Imath::V3f& v, float alpha, const Imath::V2f& u) {
  // The view direction in the hemisphere configuration of a unit-roughness distribution.
  const Imath::V3f vh = normalize(Imath::V3f(alpha * v.x, alpha * v.y, v.z));
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  const Imath::V3f t1 =
      len2 > 0.0f ? Imath::V3f(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : Imath::V3f(1.0f, 0.0f, 0.0f);
  const Imath::V3f t2 = cross(vh, t1);
  // A point on the projected hemisphere: a disk, its half below vh's horizon squeezed.
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  const Imath::V3f nh =
      t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize(Imath::V3f(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

}  // namespace prism
