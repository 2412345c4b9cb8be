// shadow: phong plus one shadow ray per light (rtcOccluded1) from each hit; lights behind
// the surface (N . L <= 0) are skipped without casting a ray.
//
// Parameters: --ambient (I_a), --background.
#include "integrators/direct.h"
#include "integrators/integrators.h"

namespace prism {
namespace {

class ShadowIntegrator final : public Integrator {
 public:
  const char* name() const override { return "shadow"; }
  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    render_tile_with(context, tile, image, counters, [&](const Ray& ray, RayCounters* c) {
      return direct_radiance<true>(context, ray, c);
    });
  }
};

}  // namespace

std::unique_ptr<Integrator> make_shadow_integrator() { return std::make_unique<ShadowIntegrator>(); }

}  // namespace prism
