// whitted: shadow-ray direct lighting plus recursive mirror reflection and refraction
// (Whitted, 1979) with the exact dielectric Fresnel equations and total internal reflection.
//
// A surface is, by the material mapping (docs/materials.md), a blend of an opaque part and
// a transmissive dielectric part (weight `transmission`):
//   - the opaque part reflects a mirror ray when roughness <= kMirrorRoughness, weighted by
//     Schlick's Fresnel with F0 = k_s (metals tint their reflections);
//   - the dielectric part reflects F and refracts (1 - F) of the light, F from the exact
//     Fresnel equations with the material's ior; the refracted light takes the base colour
//     as it enters (KHR_materials_transmission's tint).
// Both reflections share one reflection ray. Recursion stops at --max-depth.
//
// Specialised per tile on the scene's features (shading_flags.h): with no mirror and nothing
// transmissive it runs the shadow integrator's own code; in an opaque scene it leaves out
// Fresnel and refraction; without occluders it casts no shadow rays.
//
// Parameters: --max-depth, --ambient (I_a), --background.
#include "integrators/direct.h"
#include "integrators/integrators.h"
#include "integrators/shadow_queue.h"
#include "integrators/tile_loop.h"

namespace prism {
namespace {

float schlick_weight(float cos_theta) {
  const float m = std::fmax(0.0f, 1.0f - cos_theta);
  return (m * m) * (m * m) * m;
}

// The recursive tracer under flags F: without F.mirror the opaque part's mirror ray is never
// weighed, without F.transmission neither Fresnel nor refraction is computed. The feature
// set only clears a flag when no surface of the scene can take that branch, so each variant
// computes exactly what the general one does.
template <ShadingFlags F>
struct WhittedTracer {
  static void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                          RayCounters* counters) {
    // The camera hits' shadow rays in packets (integrators/shadow_queue.h), then each hit's
    // reflection and refraction, one at a time: the same sums shade() forms.
    const auto secondary = [&](const CameraPacket& p, SampleResult* results,
                               SurfaceResponse* surfaces, RayCounters* c) {
      for (int i = 0; i < p.count; ++i) {
        if (p.found[i])
          results[i].radiance =
              add_secondary(context, p.rays[i], p.hits[i], surfaces[i], 0, results[i].radiance, c);
      }
    };
    if (render_tile_queueing_shadows<F>(context, tile, image, counters, secondary)) return;
    render_tile_shading_hits(context, tile, image, counters,
                             [&](const Ray& ray, const SurfaceHit& hit, RayCounters* c) {
                               return shade(context, ray, hit, 0, c);
                             });
  }

  static V3f trace(const RenderContext& context, const Ray& ray, int depth, RayCounters* counters) {
    SurfaceHit hit;
    if (!context.scene.geometry().intersect(ray, &hit)) return context.settings.background;
    return shade(context, ray, hit, depth, counters);
  }

  static V3f shade(const RenderContext& context, const Ray& ray, const SurfaceHit& hit, int depth,
                   RayCounters* counters) {
    const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit);
    const V3f direct = shade_direct<F>(context, hit, surface, -ray.direction, counters);
    return add_secondary(context, ray, hit, surface, depth, direct, counters);
  }

  // `radiance` (the hit's direct light) plus what its mirror reflection and refraction
  // bring, unless the chain is `depth` long already.
  static V3f add_secondary(const RenderContext& context, const Ray& ray, const SurfaceHit& hit,
                           const SurfaceResponse& surface, int depth, V3f radiance,
                           RayCounters* counters) {
    if (depth >= context.settings.max_depth) return radiance;
    const V3f to_viewer = -ray.direction;

    const V3f n = face_forward(surface.shading_normal, to_viewer);
    const V3f outside = face_forward(hit.geometric_normal, to_viewer);  // the viewer's side
    const float cos_i = std::fmin(1.0f, std::fmax(0.0f, dot(to_viewer, n)));

    V3f reflect_weight(0.0f);
    if constexpr (F.mirror) {
      if (surface.mirror && surface.transmission < 1.0f) {
        const V3f f0 = surface.specular_colour;
        reflect_weight +=
            (f0 + (V3f(1.0f) - f0) * schlick_weight(cos_i)) * (1.0f - surface.transmission);
      }
    }
    if constexpr (F.transmission) {
      if (surface.transmission > 0.0f) {
        // eta = n_transmitted / n_incident: entering from the front, or leaving from inside.
        const float eta = hit.back_face ? 1.0f / surface.ior : surface.ior;
        const float fresnel = fresnel_dielectric(cos_i, eta);
        reflect_weight += V3f(surface.transmission * fresnel);
        V3f refracted;
        if (fresnel < 1.0f && refract(ray.direction, n, eta, &refracted)) {
          Ray r;
          r.origin = offset_ray_origin(hit.position, -outside, hit.surface_error);
          r.direction = refracted;
          ++counters->refraction;
          const V3f tint = hit.back_face ? V3f(1.0f) : surface.transmission_tint;
          radiance += hadamard(tint, trace(context, r, depth + 1, counters)) *
                      (surface.transmission * (1.0f - fresnel));
        }
      }
    }
    if (reflect_weight.x > 0.0f || reflect_weight.y > 0.0f || reflect_weight.z > 0.0f) {
      Ray r;
      r.origin = offset_ray_origin(hit.position, outside, hit.surface_error);
      r.direction = normalize(reflect(ray.direction, n));
      ++counters->reflection;
      radiance += hadamard(reflect_weight, trace(context, r, depth + 1, counters));
    }
    return radiance;
  }
};

// The variants with secondary rays: mirrors in an opaque scene, or everything, each with or
// without shadow rays. Emission stays on in both: adding it costs nothing next to a
// reflection ray, and one more flag would double the variants.
constexpr ShadingFlags secondary_flags(bool shadows, bool transmission) {
  return ShadingFlags{shadows, /*emission=*/true, /*mirror=*/true, transmission};
}

class WhittedIntegrator final : public Integrator {
 public:
  const char* name() const override { return "whitted"; }

  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    const ShadingFlags flags = shading_flags(context);
    // No mirror and nothing transmissive: no ray beyond the shadow rays, so whitted is the
    // shadow integrator, and runs its very code.
    if (!flags.secondary()) return render_direct_tile(flags, context, tile, image, counters);
    if (flags.shadows) {
      if (flags.transmission)
        WhittedTracer<secondary_flags(true, true)>::render_tile(context, tile, image, counters);
      else
        WhittedTracer<secondary_flags(true, false)>::render_tile(context, tile, image, counters);
    } else {
      if (flags.transmission)
        WhittedTracer<secondary_flags(false, true)>::render_tile(context, tile, image, counters);
      else
        WhittedTracer<secondary_flags(false, false)>::render_tile(context, tile, image, counters);
    }
  }
};

}  // namespace

std::unique_ptr<Integrator> make_whitted_integrator() {
  return std::make_unique<WhittedIntegrator>();
}

}  // namespace prism
