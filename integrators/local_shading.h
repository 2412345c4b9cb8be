// The lecture's local shading equation, shared by every integrator:
//
//   I = I_a k_a + sum_i I_i f(V, L_i) (L_i . N)
//
// in radiometric form (docs/materials.md): I_i is the irradiance a light delivers facing it
// (LightSource::sample), f the BSDF's non-delta lobes (Bsdf::eval: glTF's GGX layer over
// Lambert, or the lecture's Phong lobe), so the sum is reflected radiance. k_a is the
// surface's albedo towards the viewer (Bsdf::albedo), what it reflects of a uniform ambient
// radiance I_a through the lobes the integrator does not trace itself: every lobe for phong
// and shadow, the non-delta ones for whitted until its depth limit. I_a is the integrator's
// `ambient` parameter plus the scene's environment as seen from the surface: E(N) / pi, the
// uniform radiance that would deliver the environment's irradiance about the normal
// (Environment::irradiance), so an environment lights these integrators as a uniform
// ambient of its own brightness there would; like the lecture's ambient term it ignores
// occlusion. The `environment-ambient` parameter weighs it (0: the environment is only seen
// by rays that leave the scene). So a white furnace (a uniform environment of 1) renders 1, never
// more, with every integrator.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "renderer/integrator.h"
#include "renderer/math.h"
#include "renderer/shading/light_culling.h"
#include "renderer/shading/material.h"

namespace prism {

// A uniform radiance from every direction, reflected through the lobes `scope` names.
struct AmbientLight {
  Imath::V3f radiance{0.0f};
  AlbedoScope scope = AlbedoScope::all_lobes;
  // How much of the environment's irradiance about the normal, E(N) / pi, joins `radiance`
  // (the integrators' environment-ambient parameter; 0 for a term already counted).
  float environment = 1.0f;
};

// Where a shadow ray towards a light on the side of `n` (the shading normal on that side)
// leaves `hit`. On the front side of a smooth-shaded triangle the ray starts from Hanika's point
// on the smooth surface (SurfaceHit::terminator_offset), and leaves along n: near the terminator
// the light can be behind the flat triangle (N_g . L < 0) while the smooth surface faces it, and
// an origin pushed behind the triangle would be shadowed by the mesh's own inside. The offset is
// Hanika's for convex-from-the-front surfaces only, so seen from behind (n on the back side) the
// hit point itself is used.
inline Imath::V3f shadow_ray_origin(const SurfaceHit& hit, const Imath::V3f& n) {
  const bool front = dot(n, hit.geometric_normal) > 0.0f;
  const V3f from = front ? hit.position + hit.terminator_offset : hit.position;
  return offset_ray_origin(from, n, hit.surface_error);
}

// Which of the scene's lights a call shades: [first, last), clamped to the lights there are.
struct LightRange {
  size_t first = 0;
  size_t last = std::numeric_limits<size_t>::max();
};

// The local shading equation, with each light's term handed to
// `light(radiance, shadow_ray, contribution, index)` in the lights' order, for every light of
// `range` that faces the surface and can reach it (lights behind it, N . L <= 0, and lights
// light_may_reach rules out are skipped without a ray):
// `index` is the light's in the scene, `contribution()` its term, which `light` adds to `radiance`
// if the light is visible from the hit along `shadow_ray` (set only when Shadows). Returns
// `radiance` as the calls left it, the ambient term to begin with. shade_local decides visibility
// at once; the direct-light tile loop collects a packet's shadow rays first
// (integrators/direct.cpp).
template <bool Shadows, typename LightFn>
Imath::V3f shade_local_with(const RenderContext& context, const AmbientLight& ambient,
                            const SurfaceHit& hit, const SurfaceResponse& surface,
                            const Imath::V3f& to_viewer, LightFn&& light, LightRange range = {}) {
  const Bsdf& bsdf = surface.bsdf;
  const V3f n = bsdf.normal_towards(to_viewer);
  V3f radiance(0.0f);
  V3f incident = ambient.radiance;
  if (ambient.environment != 0.0f && !context.scene.environment().black())
    incident += context.scene.environment().irradiance(n) * (ambient.environment * kInvPi);
  if (incident.x != 0.0f || incident.y != 0.0f || incident.z != 0.0f)
    radiance = hadamard(incident, bsdf.albedo(to_viewer, n, hit.back_face, ambient.scope)) *
               surface.ambient_occlusion;
  const auto& lights = context.scene.lights();
  const size_t last = std::min(range.last, lights.size());
  for (size_t l = range.first; l < last; ++l) {
    const LightSource& source = lights[l];
    if (!light_may_reach(source, hit.position, n)) continue;
    // Every light is a delta light today, whose sample needs no random numbers.
    LightSample arrival;
    if (!source.sample(hit.position, Imath::V2f(0.0f), &arrival)) continue;
    const float cos_light = dot(n, arrival.wi);
    if (cos_light <= 0.0f) continue;
    Ray shadow_ray;
    if constexpr (Shadows) {
      // The light is on the shading normal's side (shadow_ray_origin).
      shadow_ray.origin = shadow_ray_origin(hit, n);
      shadow_ray.direction = arrival.wi;
      shadow_ray.tfar = arrival.distance;
    }
    light(
        radiance, shadow_ray,
        [&] { return hadamard(bsdf.eval(to_viewer, arrival.wi, n), arrival.radiance) * cos_light; },
        l);
  }
  return radiance;
}

// Shadows = true casts one shadow ray per light that faces the surface, there and then.
template <bool Shadows>
Imath::V3f shade_local(const RenderContext& context, const AmbientLight& ambient,
                       const SurfaceHit& hit, const SurfaceResponse& surface,
                       const Imath::V3f& to_viewer, RayCounters* counters) {
  return shade_local_with<Shadows>(
      context, ambient, hit, surface, to_viewer,
      [&](V3f& radiance, const Ray& shadow_ray, auto&& contribution, size_t) {
        if constexpr (Shadows) {
          ++(*counters)[RayKind::shadow];
          if (context.scene.geometry().occluded(shadow_ray)) return;
        }
        radiance += contribution();
      });
}

}  // namespace prism
