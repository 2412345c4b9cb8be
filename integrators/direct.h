// The two integrators that see only direct light: `phong` (no shadows) and `shadow` (one
// shadow ray per light). They differ in one compile-time flag, so they share this template.
#pragma once

#include "integrators/local_shading.h"
#include "integrators/tile_loop.h"

namespace prism {

template <bool Shadows>
SampleResult direct_radiance(const RenderContext& context, const Ray& ray, RayCounters* counters) {
  SurfaceHit hit;
  if (!context.scene.geometry().intersect(ray, &hit)) return {context.settings.background, false};
  const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit.uv);
  return {surface.emission + shade_local<Shadows>(context, hit, surface, -ray.direction, counters),
          true};
}

}  // namespace prism
