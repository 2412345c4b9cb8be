// The lecture's local shading equation, shared by every integrator:
//
//   I = I_a k_a + sum_i I_i k_d (L_i . N) + sum_i I_i k_s (R_i . V)^n
//
// in radiometric form (docs/materials.md): I_i is the irradiance a light delivers facing it,
// k_d = rho_d / pi is glTF's Lambert BRDF and k_s (n + 2) / (2 pi) the normalised Phong lobe,
// so the sum is reflected radiance. k_a = rho_d + k_s, the albedo the surface shows under a
// uniform ambient radiance I_a.
#pragma once

#include <cmath>

#include "renderer/integrator.h"
#include "renderer/shading/material.h"
#include "renderer/math.h"

namespace prism {

// The local shading equation, with each light's term handed to
// `light(radiance, shadow_ray, contribution)` in the lights' order, for every light that
// faces the surface (lights behind it, N . L <= 0, are skipped without a ray):
// `contribution()` is its term, which `light` adds to `radiance` if the light is visible
// from the hit along `shadow_ray` (set only when Shadows). Returns `radiance` as the calls
// left it, the ambient term to begin with. shade_local decides visibility at once; the
// direct-light tile loop collects a packet's shadow rays first (integrators/direct.cpp).
template <bool Shadows, typename LightFn>
Imath::V3f shade_local_with(const RenderContext& context, const SurfaceHit& hit,
                            const SurfaceResponse& surface, const Imath::V3f& to_viewer,
                            LightFn&& light) {
  const V3f n = face_forward(surface.shading_normal, to_viewer);
  V3f radiance =
      hadamard(context.settings.ambient, surface.diffuse_albedo + surface.specular_colour) *
      surface.ambient_occlusion;
  const float lobe_norm = (surface.phong_exponent + 2.0f) * (0.5f * kInvPi);
  for (const LightSource& source : context.scene.lights()) {
    LightArrival arrival;
    if (!light_arrival(source, hit.position, &arrival)) continue;
    const float cos_light = dot(n, arrival.to_light);
    if (cos_light <= 0.0f) continue;
    Ray shadow_ray;
    if constexpr (Shadows) {
      // The light is on the shading normal's side. On the front side of a smooth-shaded
      // triangle the ray starts from Hanika's point on the smooth surface
      // (SurfaceHit::terminator_offset), and leaves along n: near the terminator the light
      // can be behind the flat triangle (N_g . L < 0) while the smooth surface faces it, and
      // an origin pushed behind the triangle would be shadowed by the mesh's own inside.
      // The offset is Hanika's for convex-from-the-front surfaces only, so seen from behind
      // (n on the back side) the hit point itself is used.
      const bool front = dot(n, hit.geometric_normal) > 0.0f;
      const V3f from = front ? hit.position + hit.terminator_offset : hit.position;
      shadow_ray.origin = offset_ray_origin(from, n, hit.surface_error);
      shadow_ray.direction = arrival.to_light;
      shadow_ray.tfar = arrival.distance;
    }
    light(radiance, shadow_ray, [&] {
      const V3f reflected = reflect(-arrival.to_light, n);
      const float cos_view = std::fmax(0.0f, dot(reflected, to_viewer));
      const float specular = surface.phong_exponent > 0.0f
                                 ? lobe_norm * std::pow(cos_view, surface.phong_exponent)
                                 : lobe_norm;
      const V3f brdf = surface.diffuse_albedo * kInvPi + surface.specular_colour * specular;
      return hadamard(brdf, arrival.irradiance) * cos_light;
    });
  }
  return radiance;
}

// Shadows = true casts one shadow ray per light that faces the surface, there and then.
template <bool Shadows>
Imath::V3f shade_local(const RenderContext& context, const SurfaceHit& hit,
                       const SurfaceResponse& surface, const Imath::V3f& to_viewer,
                       RayCounters* counters) {
  return shade_local_with<Shadows>(context, hit, surface, to_viewer,
                                   [&](V3f& radiance, const Ray& shadow_ray, auto&& contribution) {
                                     if constexpr (Shadows) {
                                       ++counters->shadow;
                                       if (context.scene.geometry().occluded(shadow_ray)) return;
                                     }
                                     radiance += contribution();
                                   });
}

}  // namespace prism
