// shadow: phong plus one shadow ray per light (rtcOccluded1) from each hit; lights behind
// the surface (N . L <= 0) are skipped without casting a ray. The ray leaves from the hit
// point offset to the light's side of the geometric surface (renderer/math.h,
// offset_ray_origin) and ends at the light. In a scene where nothing can block a shadow ray
// (SceneFeatures::shadows = false) it casts none and runs phong's code (shading_flags.h).
//
// Parameters: --ambient (I_a), --background.
#include "integrators/direct.h"
#include "integrators/integrators.h"

namespace prism {

std::unique_ptr<Integrator> make_shadow_integrator() {
  return std::make_unique<DirectLightIntegrator</*Shadows=*/true>>();
}

}  // namespace prism
