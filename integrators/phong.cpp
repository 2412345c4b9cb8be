// phong: the lecture's local shading equation (ambient + Lambert + normalised Phong) at the
// nearest hit of each view ray. No shadows, no secondary rays.
//
// Parameters: --ambient (I_a), --background.
#include "integrators/direct.h"
#include "integrators/integrators.h"

namespace prism {
namespace {

class PhongIntegrator final : public Integrator {
 public:
  const char* name() const override { return "phong"; }
  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    render_tile_with(context, tile, image, counters, [&](const Ray& ray, RayCounters* c) {
      return direct_radiance<false>(context, ray, c);
    });
  }
};

}  // namespace

std::unique_ptr<Integrator> make_phong_integrator() { return std::make_unique<PhongIntegrator>(); }

}  // namespace prism
