// phong: the lecture's local shading equation (ambient + Lambert + normalised Phong) at the
// nearest hit of each view ray, plus emission. No shadows, no secondary rays.
//
// Parameters: --ambient (I_a), --background. The shading itself is integrators/direct.h and
// integrators/local_shading.h.
#include "integrators/direct.h"
#include "integrators/integrators.h"

namespace prism {

std::unique_ptr<Integrator> make_phong_integrator() {
  return std::make_unique<DirectLightIntegrator</*Shadows=*/false>>();
}

}  // namespace prism
