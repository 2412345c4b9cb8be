// path: unidirectional path tracing (pbrt-v4's PathIntegrator): at every hit one light is
// chosen by power among the punctual lights, the area lights and the environment
// (renderer/shading/emitter_sampler.h) and sampled (next-event estimation), and the BSDF is
// sampled for the next bounce; light that a bounce finds on an emitter or the environment is
// weighed against the light sample by multiple importance sampling, the power heuristic
// (Veach 1995) with beta = 2. Delta lights take the light sample's whole weight, delta lobes
// (a perfect mirror, alpha = 0; a smooth dielectric) the BSDF sample's.
//
// The BSDF is glTF's (renderer/shading/bsdf.h, Bsdf::path_traced): GGX sampled by its visible
// normals (Heitz 2018), Lambert by the cosine, and a rough transmissive part a rough dielectric
// (renderer/shading/rough_dielectric.h) whose transmitted directions are found by BSDF samples
// only (a light sample cannot see through the surface), their light counted whole.
//
// KHR_materials_volume: a transmission event through a volume material's surface (wi on the
// far side of the geometric normal) puts the path inside that object when it arrived on the
// front face and outside when on the back face; while inside, every segment, the segment of
// a light sample included, keeps exp(-sigma_a length) of the throughput (Beer-Lambert). Media
// do not nest: leaving any volume puts the path outside all of them.
//
// After --roulette-depth bounces a path continues with probability min(1, sqrt(max(beta))) and
// its throughput is divided by it (Russian roulette, unbiased). The square root, Cycles' choice,
// ends dim paths later than min(1, max(beta)) does: in pbrt's form a path through three
// bounces of albedo 0.7 survives with 0.34 and one that survives carries a throughput of 1, a
// spike that costs more variance than the bounces it saves (time to equal error 0.82x on the
// Cornell box, 0.92x on the material sweep; docs/cycles-path.md). --max-depth bounds
// the bounces; --clamp, off by default, caps each sample's radiance (its largest channel) and so
// biases bright paths down, for previews only. --strategy 1 or 2 keeps only the light samples or
// only the BSDF samples for lights that are not deltas: the same image in expectation, noisier, for
// checking MIS.
//
// Each bounce k draws its random numbers from fixed sample dimensions,
// 2 + kDimensionsPerBounce k onwards (renderer/sampling/sampler.h), so a pixel's sample is a
// pure function of (pixel, sample): the image is the same whatever the threads, tiles or passes.
//
// Specialised per tile, as the others (shading_flags.h): without emissive surfaces no emission or
// MIS weight is formed at hits, and under a black environment escaping rays are not looked up.
//
// | parameter | type    | default | meaning                                                  |
// | --------- | ------- | ------- | -------------------------------------------------------- |
// | max-depth | integer | 16      | most bounces after the camera ray                        |
// | clamp     | number  | 0       | largest radiance a sample keeps (largest channel); 0 off |
// | roulette-depth | integer | 3  | bounces before Russian roulette may end a path           |
// | strategy  | integer | 0       | 0 MIS, 1 light samples only, 2 BSDF samples only         |
#include <algorithm>
#include <cmath>
#include <limits>

#include "integrators/local_shading.h"
#include "integrators/registry.h"
#include "integrators/shading_flags.h"
#include "integrators/tile_loop.h"
#include "renderer/sampling/sampler.h"

namespace prism {
namespace {

constexpr ParameterInfo kParameters[] = {
    {"max-depth", ParameterType::integer, 16, 0, 1024, "Most bounces after the camera ray"},
    {"clamp", ParameterType::real, 0.0, 0.0, 3.4e38,
     "Largest radiance a sample keeps (largest channel), biasing bright paths; 0 = off"},
    {"roulette-depth", ParameterType::integer, 3, 0, 1024,
     "Bounces before Russian roulette may end a path (at max-depth or more: never)"},
    {"strategy", ParameterType::integer, 0, 0, 2,
     "Light sampling: 0 = both, weighed by MIS; 1 = light samples only; 2 = BSDF samples only"},
};

// How light from lights that are not deltas is found; every strategy is unbiased, MIS has
// the lowest variance, the other two are there to check it (tests/path_test.cpp).
enum class Strategy : uint8_t { mis, light_only, bsdf_only };
// Per bounce: the light's point (a pair), the BSDF's direction (a pair), the light's choice,
// the BSDF's lobe and the roulette; one dimension spare keeps bounces on pair boundaries.
constexpr uint32_t kDimensionsPerBounce = 8;
// The bounces whose dimensions are stratified (padded Sobol); later bounces draw independent
// uniforms, at a sixth of the cost, with no measurable change in the error (docs/sampling.md).
constexpr uint32_t kStratifiedBounces = 2;
constexpr uint32_t kStratifiedEnd =
    PixelSampler::kFirstIntegratorDimension + kDimensionsPerBounce * kStratifiedBounces;
constexpr float kInfiniteDistance = std::numeric_limits<float>::infinity();

float power_heuristic(float f, float g) {
  const float f2 = f * f, g2 = g * g;
  return f2 / (f2 + g2);
}

struct PathParameters {
  explicit PathParameters(const ParameterValues& values)
      : max_depth(values.integer("max-depth")),
        roulette_depth(values.integer("roulette-depth")),
        clamp(static_cast<float>(values.real("clamp"))),
        strategy(static_cast<Strategy>(values.integer("strategy"))) {}
  int max_depth;
  int roulette_depth;
  float clamp;
  Strategy strategy;

  // Under MIS the BSDF samples find the environment's light below its mean, so light samples
  // leave it out (EnvironmentDensity::beside_bsdf); with one strategy alone, each must find
  // all the light.
  EnvironmentDensity environment_density() const {
    return strategy == Strategy::mis ? EnvironmentDensity::beside_bsdf
                                     : EnvironmentDensity::complete;
  }
  // The weights of a BSDF sample and a light sample of densities `bsdf` and `light`.
  float bsdf_weight(float bsdf, float light) const {
    switch (strategy) {
      case Strategy::mis:
        break;
      case Strategy::light_only:
        return light > 0.0f ? 0.0f : 1.0f;
      case Strategy::bsdf_only:
        return 1.0f;
    }
    return power_heuristic(bsdf, light);
  }
  float light_weight(float light, float bsdf) const {
    switch (strategy) {
      case Strategy::mis:
        break;
      case Strategy::light_only:
        return 1.0f;
      case Strategy::bsdf_only:
        return bsdf > 0.0f ? 0.0f : 1.0f;
    }
    return power_heuristic(light, bsdf);
  }
};

// Emission: some surface emits (area lights exist). Environment: the environment is not black.
template <bool HasEmission, bool HasEnvironment>
struct PathTracer {
  const RenderContext& context;
  const PathParameters& params;

  void render_tile(const TileRect& tile, Image* image, RayCounters* counters) const {
    render_tile_packets(context, tile, image, counters,
                        [&](const CameraPacket& p, SampleResult* results, RayCounters* c) {
                          for (int i = 0; i < p.count; ++i) {
                            results[i].hit = p.found[i];
                            results[i].radiance = trace(p.rays[i], p.hits[i], p.found[i],
                                                        p.sample_key[i], p.sample_index, c);
                          }
                        });
  }

  // Light arriving at `point` from the environment along -wi, as a ray escaping the scene
  // after a BSDF sample of density `bsdf_pdf` sees it (bsdf_pdf < 0: counted whole). A camera
  // ray sees the environment's background (black when it is hidden from the camera).
  V3f escaped(const V3f& direction, float bsdf_pdf, bool camera_ray) const {
    if constexpr (!HasEnvironment) {
      return V3f(0.0f);
    } else {
      const Environment& env = context.scene.environment();
      if (camera_ray) return env.background(direction);
      if (bsdf_pdf < 0.0f) return env.radiance(direction);
      float env_pdf = 0.0f;
      const V3f radiance = env.radiance_and_pdf(direction, &env_pdf, params.environment_density());
      const float light_pdf = context.scene.emitter_sampler().pmf_environment() * env_pdf;
      return radiance * params.bsdf_weight(bsdf_pdf, light_pdf);
    }
  }

  V3f trace(Ray ray, SurfaceHit hit, bool found, uint64_t pixel, uint32_t sample,
            RayCounters* counters) const {
    const RenderScene& scene = context.scene;
    V3f radiance(0.0f), beta(1.0f);
    // The previous bounce's BSDF density, < 0 after a delta lobe (and for the camera ray),
    // whose light is counted whole; and the point it left from.
    float bsdf_pdf = -1.0f;
    V3f from(0.0f);
    // The absorption of the volume the path is in, if any (the camera is outside).
    bool inside = false;
    V3f absorption(0.0f);
    for (int depth = 0;; ++depth) {
      if (inside)
        beta = hadamard(beta, transmittance(absorption, found ? hit.t : kInfiniteDistance));
      if (!found) {
        radiance += hadamard(beta, escaped(ray.direction, bsdf_pdf, depth == 0));
        break;
      }
      const Material& material = scene.material(hit.material);
      const SurfaceResponse surface = evaluate(material, hit);
      if constexpr (HasEmission) {
        const V3f& e = surface.emission;
        if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) {
          float weight = 1.0f;
          if (bsdf_pdf >= 0.0f && hit.emitter != kNoEmitter) {
            const float light_pdf =
                scene.emitter_sampler().pmf_area(hit.emitter, from) *
                scene.area_lights()[hit.emitter].pdf_towards(from, hit.position);
            weight = params.bsdf_weight(bsdf_pdf, light_pdf);
          }
          radiance += hadamard(beta, e) * weight;
        }
      }
      if (depth >= params.max_depth) break;
      const Bsdf bsdf = surface.bsdf.path_traced(hit.back_face);
      const V3f wo = -ray.direction;
      const V3f n = bsdf.normal_towards(wo);
      PixelSampler sampler(pixel, sample,
                           PixelSampler::kFirstIntegratorDimension +
                               kDimensionsPerBounce * static_cast<uint32_t>(depth),
                           kStratifiedEnd);
      const PixelSample2D u_light = sampler.get2d();
      const PixelSample2D u_bsdf = sampler.get2d();
      // The light's choice and the BSDF's lobe are one pair of dimensions, drawn together
      // (one seed hash) when there is a lobe to choose; the lobe's and the roulette's
      // dimensions are drawn only where they are used.
      const uint32_t choice_dimension = sampler.dimension();
      const uint32_t roulette_dimension = choice_dimension + 2;
      float u_choice = 0.0f, u_lobe = 0.0f;
      if (bsdf.single_lobe()) {
        u_choice = sampler.get1d_at(choice_dimension);
      } else {
        const PixelSample2D choice_and_lobe = sampler.get2d();
        u_choice = choice_and_lobe.x;
        u_lobe = choice_and_lobe.y;
      }

      // Lights are sampled from the shadow rays' origin, off the surface on the lit side: a
      // point on an emissive sphere itself is then unambiguously inside or outside it.
      const V3f reference = shadow_ray_origin(hit, n);
      if (bsdf.flags() & (kDiffuseReflection | kGlossyReflection))
        radiance += hadamard(
            beta, light_sample(reference, bsdf, wo, n, u_choice, Imath::V2f(u_light.x, u_light.y),
                               inside ? &absorption : nullptr, counters));

      BsdfSample bs;
      if (!bsdf.sample(wo, u_lobe, Imath::V2f(u_bsdf.x, u_bsdf.y), hit.back_face, &bs)) break;
      beta = hadamard(beta, bs.f) * (std::fabs(dot(n, bs.wi)) / bs.pdf);
      bsdf_pdf = bs.specular() || bs.lobe == kGlossyTransmission ? -1.0f : bs.pdf;
      from = reference;
      if (depth + 1 >= params.roulette_depth) {
        const float survive = fmin_inline(1.0f, std::sqrt(max_component(beta)));
        if (!(sampler.get1d_at(roulette_dimension) < survive)) break;
        beta /= survive;
      }
      const V3f outside = face_forward(hit.geometric_normal, wo);
      const bool crosses = dot(bs.wi, outside) < 0.0f;
      if (crosses && !material.thin_walled) {
        inside = !hit.back_face;
        absorption = material.absorption;
      }
      // Made whole before it replaces the ray: Imath's vectors start uninitialised.
      Ray next;
      next.origin =
          offset_ray_origin(hit.position, crosses ? -outside : outside, hit.surface_error);
      next.direction = bs.wi;
      ray = next;
      ++(*counters)[RayKind::bounce];
      found = scene.geometry().intersect(ray, &hit);
    }
    if (params.clamp > 0.0f) {
      const float m = max_component(radiance);
      if (m > params.clamp) radiance *= params.clamp / m;
    }
    return radiance;
  }

  // One light sample from `reference` (shadow_ray_origin of the hit), weighed against the
  // BSDF's density for the same direction; `absorption`: the volume the point is in, if any.
  V3f light_sample(const V3f& reference, const Bsdf& bsdf, const V3f& wo, const V3f& n,
                   float u_choice, const Imath::V2f& u, const V3f* absorption,
                   RayCounters* counters) const {
    const RenderScene& scene = context.scene;
    ChosenEmitter chosen;
    if (!scene.emitter_sampler().sample(u_choice, reference, &chosen)) return V3f(0.0f);
    LightSample arrival;
    arrival.wi = arrival.radiance = V3f(0.0f);
    bool delta = false;
    switch (chosen.kind) {
      case EmitterKind::punctual:
        if (!scene.lights()[chosen.index].sample(reference, u, &arrival)) return V3f(0.0f);
        delta = true;
        break;
      case EmitterKind::area:
        if constexpr (HasEmission) {
          const AreaLight& light = scene.area_lights()[chosen.index];
          if (!(chosen.has_view ? light.sample(reference, chosen.view, u, &arrival)
                                : light.sample(reference, u, &arrival)))
            return V3f(0.0f);
          arrival.distance *= kAreaLightShadowRayEnd;
          break;
        } else {
          return V3f(0.0f);
        }
      case EmitterKind::environment:
        if constexpr (HasEnvironment) {
          EnvironmentSample es;
          if (!scene.environment().sample(u, &es, params.environment_density())) return V3f(0.0f);
          arrival.wi = es.wi;
          arrival.radiance = es.radiance;
          arrival.pdf = es.pdf;
          break;
        } else {
          return V3f(0.0f);
        }
    }
    const float cos_light = dot(n, arrival.wi);
    if (cos_light <= 0.0f || !(arrival.pdf > 0.0f)) return V3f(0.0f);
    const V3f f = bsdf.eval(wo, arrival.wi, n);
    if (!(max_component(f) > 0.0f)) return V3f(0.0f);
    Ray shadow;
    shadow.origin = reference;
    shadow.direction = arrival.wi;
    shadow.tfar = arrival.distance;
    ++(*counters)[RayKind::shadow];
    if (scene.geometry().occluded(shadow)) return V3f(0.0f);
    V3f contribution = hadamard(f, arrival.radiance) * cos_light;
    if (absorption)
      contribution = hadamard(contribution, transmittance(*absorption, arrival.distance));
    if (delta) return contribution / chosen.pmf;
    const float light_pdf = chosen.pmf * arrival.pdf;
    const float weight = params.light_weight(light_pdf, bsdf.pdf(wo, arrival.wi));
    if (weight == 0.0f) return V3f(0.0f);
    return contribution * (weight / light_pdf);
  }
};

class PathIntegrator final : public Integrator {
 public:
  explicit PathIntegrator(const ParameterValues& values) : params_(values) {}

  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    // Without emissive or unlit materials the emission term is zero everywhere.
    const bool emission = shading_flags(context).emission;
    const bool environment = !context.settings.specialise || !context.scene.environment().black();
    if (emission) {
      if (environment)
        run<true, true>(context, tile, image, counters);
      else
        run<true, false>(context, tile, image, counters);
    } else {
      if (environment)
        run<false, true>(context, tile, image, counters);
      else
        run<false, false>(context, tile, image, counters);
    }
  }

 private:
  template <bool HasEmission, bool HasEnvironment>
  void run(const RenderContext& context, const TileRect& tile, Image* image,
           RayCounters* counters) const {
    PathTracer<HasEmission, HasEnvironment>{context, params_}.render_tile(tile, image, counters);
  }

  PathParameters params_;
};

}  // namespace

extern const IntegratorInfo kPathIntegrator{
    "path",
    "unidirectional path tracing with next-event estimation and multiple importance sampling",
    kParameters, [](const ParameterValues& values) -> std::unique_ptr<Integrator> {
      return std::make_unique<PathIntegrator>(values);
    }};

}  // namespace prism
