// shadow: phong plus one shadow ray per light (rtcOccluded1) from each hit, and one for the
// area-light sample of emissive surfaces; lights behind the surface (N . L <= 0) are skipped
// without casting a ray. The ray leaves from the hit
// point offset to the light's side of the geometric surface (renderer/math.h,
// offset_ray_origin) and ends at the light. In a scene where nothing can block a shadow ray
// (SceneFeatures::shadows = false) it casts none and runs phong's code (shading_flags.h).
//
// | parameter           | type   | default | meaning                                        |
// | ------------------- | ------ | ------- | ---------------------------------------------- |
// | ambient             | number | 0       | uniform radiance I_a, times the surface albedo |
// | environment-ambient | number | 1       | share of the environment's E(N)/pi in I_a      |
#include "integrators/direct.h"
#include "integrators/registry.h"

namespace prism {
namespace {

constexpr ParameterInfo kParameters[] = {kAmbientParameter, kEnvironmentAmbientParameter};

}  // namespace

extern const IntegratorInfo kShadowIntegrator{
    "shadow", "local shading with one shadow ray per light", kParameters,
    [](const ParameterValues& values) -> std::unique_ptr<Integrator> {
      return std::make_unique<DirectLightIntegrator</*Shadows=*/true>>(values);
    }};

}  // namespace prism
