// whitted: shadow-ray direct lighting plus recursive mirror reflection and refraction
// (Whitted, 1979) with the exact dielectric Fresnel equations and total internal reflection.
//
// A surface is, by the material mapping (docs/materials.md), a blend of an opaque part and
// a transmissive dielectric part (weight `transmission`):
//   - the opaque part reflects a mirror ray when roughness <= kMirrorRoughness, weighted by
//     its specular layer's Schlick Fresnel (metals tint their reflections);
//   - the dielectric part reflects F and refracts (1 - F) of the light, F from the exact
//     Fresnel equations with the material's ior; the refracted light takes the base colour
//     as it enters (KHR_materials_transmission's tint).
// Both reflections share one reflection ray. Recursion stops at --max-depth. The ambient
// term reaches only the lobes not traced (Bsdf::albedo), and at the depth limit every lobe,
// so that each lobe's light is counted once.
//
// Specialised per tile on the scene's features (shading_flags.h): with no mirror and nothing
// transmissive it runs the shadow integrator's own code; in an opaque scene it leaves out
// Fresnel and refraction; without occluders it casts no shadow rays.
//
// | parameter           | type    | default | meaning                                         |
// | ------------------- | ------- | ------- | ----------------------------------------------- |
// | max-depth           | integer | 5       | longest chain of reflection and refraction rays |
// | ambient             | number  | 0       | ambient radiance I_a, times the surface albedo  |
// | environment-ambient | number  | 1       | share of the environment's E(N)/pi in I_a       |
//
// Rays that leave the scene see the scene's environment (--background, --environment),
// which also lights the ambient term. Emissive surfaces light every hit of the chain by one
// area-light sample each (integrators/local_shading.h), from dimensions of its own depth. The
// mirror and dielectric weights are the BSDF's delta lobes (Bsdf::specular_lobes).
#include "integrators/direct.h"
#include "integrators/registry.h"
#include "integrators/shadow_queue.h"
#include "integrators/tile_loop.h"

namespace prism {
namespace {

constexpr ParameterInfo kParameters[] = {
    {"max-depth", ParameterType::integer, 5, 0, 64,
     "Longest chain of reflection and refraction rays"},
    kAmbientParameter,
    kEnvironmentAmbientParameter,
};

// What one render's tracer needs besides the context: the integrator's parameters.
struct WhittedParameters {
  explicit WhittedParameters(const ParameterValues& values)
      : max_depth(values.integer("max-depth")),
        traced{Imath::V3f(values.real("ambient")), AlbedoScope::without_delta_lobes,
               static_cast<float>(values.real("environment-ambient"))},
        untraced{Imath::V3f(values.real("ambient")), AlbedoScope::all_lobes,
                 static_cast<float>(values.real("environment-ambient"))} {}
  int max_depth;
  // At a hit whose mirror and refraction rays are traced, the ambient light reaches the
  // other lobes only; at the depth limit, where they are not, every lobe.
  AmbientLight traced, untraced;
  const AmbientLight& ambient(int depth) const { return depth < max_depth ? traced : untraced; }
};

// The recursive tracer under flags F: without F.mirror the opaque part's mirror ray is never
// weighed, without F.transmission neither Fresnel nor refraction is computed. The feature
// set only clears a flag when no surface of the scene can take that branch, so each variant
// computes exactly what the general one does.
template <ShadingFlags F>
struct WhittedTracer {
  const RenderContext& context;
  const WhittedParameters& params;

  void render_tile(const TileRect& tile, Image* image, RayCounters* counters) const {
    // The camera hits' shadow rays in packets (integrators/shadow_queue.h), then each hit's
    // reflection and refraction, one at a time: the same sums shade() forms.
    const auto secondary = [&](const CameraPacket& p, SampleResult* results,
                               SurfaceResponse* surfaces, RayCounters* c) {
      for (int i = 0; i < p.count; ++i) {
        if (p.found[i])
          results[i].radiance = add_secondary(p.rays[i], p.hits[i], surfaces[i], {p.id(i), 0},
                                              results[i].radiance, c);
      }
    };
    if (render_tile_queueing_shadows<F>(context, params.ambient(0), tile, image, counters,
                                        secondary))
      return;
    render_tile_shading_hits(
        context, tile, image, counters,
        [&](const Ray& ray, const SurfaceHit& hit, const PixelSampleId& sample, RayCounters* c) {
          return shade(ray, hit, {sample, 0}, c);
        });
  }

  // `sample.depth`: how many mirror or refraction rays led from the camera to `ray`'s hit.
  V3f trace(const Ray& ray, const ShadingSample& sample, RayCounters* counters) const {
    SurfaceHit hit;
    if (!context.scene.geometry().intersect(ray, &hit))
      return context.scene.environment().radiance(ray.direction);
    return shade(ray, hit, sample, counters);
  }

  V3f shade(const Ray& ray, const SurfaceHit& hit, const ShadingSample& sample,
            RayCounters* counters) const {
    const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit);
    const V3f direct = shade_direct<F>(context, params.ambient(sample.depth), hit, surface,
                                       -ray.direction, sample, counters);
    return add_secondary(ray, hit, surface, sample, direct, counters);
  }

  // `radiance` (the hit's direct light) plus what its mirror reflection and refraction
  // bring, unless the chain is `sample.depth` long already.
  V3f add_secondary(const Ray& ray, const SurfaceHit& hit, const SurfaceResponse& surface,
                    const ShadingSample& sample, V3f radiance, RayCounters* counters) const {
    if (sample.depth >= params.max_depth) return radiance;
    const V3f to_viewer = -ray.direction;
    const V3f n = surface.bsdf.normal_towards(to_viewer);
    const V3f outside = face_forward(hit.geometric_normal, to_viewer);  // the viewer's side
    SpecularLobe lobes[2];
    const int count =
        surface.bsdf.specular_lobes<F.mirror, F.transmission>(to_viewer, n, hit.back_face, lobes);
    for (int k = 0; k < count; ++k) {
      const SpecularLobe& lobe = lobes[k];
      Ray r;
      r.origin = offset_ray_origin(hit.position, lobe.transmission ? -outside : outside,
                                   hit.surface_error);
      r.direction = lobe.wi;
      ++(*counters)[lobe.transmission ? RayKind::refraction : RayKind::reflection];
      radiance +=
          hadamard(lobe.colour, trace(r, {sample.id, sample.depth + 1}, counters)) * lobe.scale;
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
  explicit WhittedIntegrator(const ParameterValues& values) : params_(values) {}

  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    const ShadingFlags flags = shading_flags(context);
    // No mirror and nothing transmissive: no ray beyond the shadow rays, so whitted is the
    // shadow integrator, and runs its very code.
    if (!flags.secondary())
      return render_direct_tile(flags, context, params_.untraced, tile, image, counters);
    if (flags.shadows) {
      if (flags.transmission)
        run<secondary_flags(true, true)>(context, tile, image, counters);
      else
        run<secondary_flags(true, false)>(context, tile, image, counters);
    } else {
      if (flags.transmission)
        run<secondary_flags(false, true)>(context, tile, image, counters);
      else
        run<secondary_flags(false, false)>(context, tile, image, counters);
    }
  }

 private:
  template <ShadingFlags F>
  void run(const RenderContext& context, const TileRect& tile, Image* image,
           RayCounters* counters) const {
    WhittedTracer<F>{context, params_}.render_tile(tile, image, counters);
  }

  WhittedParameters params_;
};

}  // namespace

extern const IntegratorInfo kWhittedIntegrator{
    "whitted", "shadow rays plus recursive mirror reflection and refraction (Whitted, 1979)",
    kParameters, [](const ParameterValues& values) -> std::unique_ptr<Integrator> {
      return std::make_unique<WhittedIntegrator>(values);
    }};

}  // namespace prism
