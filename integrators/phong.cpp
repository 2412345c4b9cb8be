// phong: the lecture's local shading equation (ambient plus each light through the surface's
// BRDF, glTF's by default) at the nearest hit of each view ray, plus emission. Emissive
// surfaces light it too, by one area-light sample per hit (integrators/local_shading.h). No
// shadows, no secondary rays.
//
// | parameter           | type   | default | meaning                                        |
// | ------------------- | ------ | ------- | ---------------------------------------------- |
// | ambient             | number | 0       | uniform radiance I_a, times the surface albedo |
// | environment-ambient | number | 1       | share of the environment's E(N)/pi in I_a      |
//
// The shading itself is integrators/direct.h and integrators/local_shading.h; rays that
// leave the scene see the scene's environment (--background, --environment), which also
// lights the ambient term.
#include "integrators/direct.h"
#include "integrators/registry.h"

namespace prism {
namespace {

constexpr ParameterInfo kParameters[] = {kAmbientParameter, kEnvironmentAmbientParameter};

}  // namespace

extern const IntegratorInfo kPhongIntegrator{
    "phong", "local shading at the nearest hit, no shadows", kParameters,
    [](const ParameterValues& values) -> std::unique_ptr<Integrator> {
      return std::make_unique<DirectLightIntegrator</*Shadows=*/false>>(values);
    }};

}  // namespace prism
