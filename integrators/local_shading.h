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
//
// Emissive triangles and spheres (renderer/shading/area_lights.h) are lights of this sum too:
// one more term after the punctual lights, the area lights' light estimated by one sample per
// shading (a light chosen by RenderScene::area_light_sampler(), a point on it from the
// pixel's own sample), f (L . N) L_e / pdf, with the same shadow ray as a punctual light's.
// The term is unbiased, so a scene lit only by an emissive panel renders as `path` does with
// --max-depth 1 (no indirect light), the noise going down with the samples per pixel. Only the
// BSDF's non-delta lobes take part, and under whitted, which meets an emitter's emission along
// its mirror rays, not the GGX lobe of a layer or coat it traces as a mirror: nothing is
// counted twice.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "renderer/integrator.h"
#include "renderer/math.h"
#include "renderer/render_scene.h"
#include "renderer/sampling/sampler.h"
#include "renderer/shading/light_culling.h"
#include "renderer/shading/material.h"

namespace prism {

// A uniform radiance from every direction, reflected through the lobes `scope` names: those
// the integrator does not trace itself, which the area lights' sample also keeps to.
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

// Which of the scene's lights a call shades: [first, last), clamped to the lights there are;
// index lights().size() is the area lights' term, when the scene has area lights.
struct LightRange {
  size_t first = 0;
  size_t last = std::numeric_limits<size_t>::max();
};

// How many light terms a hit has: one per punctual light, and one for all the area lights.
inline size_t light_terms(const RenderScene& scene) {
  return scene.lights().size() + (scene.area_lights().empty() ? 0 : 1);
}

// Which pixel sample a shading belongs to, and how many mirror or refraction rays led from the
// camera to its hit: what its area-light sample is drawn from.
struct ShadingSample {
  PixelSampleId id;
  int depth = 0;
};

// The area-light term's dimensions: four per depth after the pixel position (a pair for the
// point on the light, one for the light's choice), so each depth of whitted's chain has its
// own. Past the second depth independent uniforms, as the path tracer's.
inline constexpr uint32_t kAreaLightDimensions = 4;
inline constexpr int kStratifiedAreaLightDepths = 2;

// The light the area lights send to `hit` along one sampled direction, with the shadow ray
// that decides whether it arrives: `*contribution` is f (L . N) L_e / pdf. False when the
// sample brings nothing (a light behind the surface, a zero density or BSDF). `scope`: the
// lobes the integrator does not trace itself; where it traces the delta lobes, a smooth
// surface's GGX lobe is left to its mirror ray (Bsdf::without_traced_mirrors).
inline bool sample_area_lights(const RenderScene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                               AlbedoScope scope, const Imath::V3f& to_viewer, const Imath::V3f& n,
                               const ShadingSample& sample, Ray* shadow_ray,
                               Imath::V3f* contribution) {
  PixelSampler sampler(
      sample.id.pixel_key, sample.id.sample_index,
      PixelSampler::kFirstIntegratorDimension +
          kAreaLightDimensions * static_cast<uint32_t>(sample.depth),
      PixelSampler::kFirstIntegratorDimension + kAreaLightDimensions * kStratifiedAreaLightDepths);
  const PixelSample2D u = sampler.get2d();
  const float u_choice = sampler.get1d();
  // From where the shadow ray leaves, as the path tracer samples: the light is on n's side.
  const V3f reference = shadow_ray_origin(hit, n);
  ChosenEmitter chosen;
  if (!scene.area_light_sampler().sample(u_choice, reference, &chosen)) return false;
  const AreaLight& light = scene.area_lights()[chosen.index];
  LightSample arrival;
  if (!(chosen.has_view ? light.sample(reference, chosen.view, Imath::V2f(u.x, u.y), &arrival)
                        : light.sample(reference, Imath::V2f(u.x, u.y), &arrival)))
    return false;
  const float cos_light = dot(n, arrival.wi);
  const float pdf = chosen.pmf * arrival.pdf;
  if (cos_light <= 0.0f || !(pdf > 0.0f)) return false;
  const V3f f = scope == AlbedoScope::without_delta_lobes && bsdf.has_traced_mirror()
                    ? bsdf.without_traced_mirrors().eval(to_viewer, arrival.wi, n)
                    : bsdf.eval(to_viewer, arrival.wi, n);
  if (!(max_component(f) > 0.0f)) return false;
  shadow_ray->origin = reference;
  shadow_ray->direction = arrival.wi;
  shadow_ray->tfar = arrival.distance * kAreaLightShadowRayEnd;
  *contribution = hadamard(f, arrival.radiance) * (cos_light / pdf);
  return true;
}

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
                            const Imath::V3f& to_viewer, const ShadingSample& sample,
                            LightFn&& light, LightRange range = {}) {
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
  const size_t area_term = lights.size();
  if (!context.scene.area_lights().empty() && range.first <= area_term && area_term < range.last) {
    Ray shadow_ray;
    V3f contribution;
    if (sample_area_lights(context.scene, hit, bsdf, ambient.scope, to_viewer, n, sample,
                           &shadow_ray, &contribution))
      light(
          radiance, shadow_ray, [&] { return contribution; }, area_term);
  }
  return radiance;
}

// Shadows = true casts one shadow ray per light that faces the surface, there and then.
template <bool Shadows>
Imath::V3f shade_local(const RenderContext& context, const AmbientLight& ambient,
                       const SurfaceHit& hit, const SurfaceResponse& surface,
                       const Imath::V3f& to_viewer, const ShadingSample& sample,
                       RayCounters* counters) {
  return shade_local_with<Shadows>(
      context, ambient, hit, surface, to_viewer, sample,
      [&](V3f& radiance, const Ray& shadow_ray, auto&& contribution, size_t) {
        if constexpr (Shadows) {
          ++(*counters)[RayKind::shadow];
          if (context.scene.geometry().occluded(shadow_ray)) return;
        }
        radiance += contribution();
      });
}

}  // namespace prism
