// Which lights can reach a shading point, decided before the light's sample is taken and its
// shadow ray queued: in a scene with dozens of ranged or spot lights most lights light little
// of what a pixel sees, and a few multiplications here are cheaper than a sample (a square
// root, divisions, the falloff) for each light at every hit.
#pragma once

#include <Imath/ImathVec.h>

#include "renderer/math.h"
#include "renderer/shading/lights.h"

namespace prism {

// False only when `light` can deliver nothing to a surface at `point` whose shading normal,
// on the side being shaded, is `n` (unit): beyond the light's range, outside its spot cone,
// or behind the surface. Each test keeps a margin far wider than float rounding (1e-5 in a
// cosine; 1e-4 in a squared distance), so a light it rejects is one that
// LightSource::sample or the N . L <= 0 test would have rejected too: culling changes no
// pixel, only the cost of finding out. A new kind of light adds its case here (a light with
// an extent reaches points behind the plane of its centre).
inline bool light_may_reach(const LightSource& light, const Imath::V3f& point,
                            const Imath::V3f& n) {
  // A directional light arrives along -direction everywhere: only the surface's side counts.
  if (light.type() == LightType::directional) return dot(n, light.direction()) < 1e-6f;
  const Imath::V3f offset = light.position() - point;
  const float d2 = offset.length2();
  // N . L < -1e-5, without the square root: N . offset < 0 and (N . offset)^2 > 1e-10 d^2.
  const float along = dot(n, offset);
  if (along < 0.0f && along * along > 1e-10f * d2) return false;
  const float range = light.range();
  if (range > 0.0f && d2 > range * range * 1.0001f) return false;
  if (light.type() == LightType::spot) {
    // cos(angle from the axis) <= cos_outer - 1e-5, as c / d <= k with c = cos * d.
    const float c = -dot(light.direction(), offset);
    const float k = light.cos_outer() - 1e-5f;
    const bool outside =
        k >= 0.0f ? (c <= 0.0f || c * c <= k * k * d2) : (c < 0.0f && c * c >= k * k * d2);
    if (outside) return false;
  }
  return true;
}

}  // namespace prism
