// The two integrators that see only direct light, `phong` (no shadows) and `shadow` (one
// shadow ray per light), differ in one compile-time flag, so they are one template; their
// files (phong.cpp, shadow.cpp) document and create them.
#pragma once

#include "integrators/local_shading.h"
#include "integrators/tile_loop.h"

namespace prism {

template <bool Shadows>
class DirectLightIntegrator final : public Integrator {
 public:
  const char* name() const override { return Shadows ? "shadow" : "phong"; }

  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    render_tile_shading_hits(
        context, tile, image, counters, [&](const Ray& ray, const SurfaceHit& hit, RayCounters* c) {
          const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit);
          return surface.emission + shade_local<Shadows>(context, hit, surface, -ray.direction, c);
        });
  }
};

}  // namespace prism
