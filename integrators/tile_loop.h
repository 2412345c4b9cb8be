// The per-pixel sample loop every integrator shares. `radiance(ray, counters)` is a
// template parameter, so each integrator's per-ray code is inlined into its own copy of the
// loop: no virtual call per ray.
#pragma once

#include <cstdint>

#include "renderer/integrator.h"
#include "renderer/random.h"

namespace prism {

struct SampleResult {
  Imath::V3f radiance;
  bool hit = false;  // the camera ray found geometry (feeds the alpha channel)
};

template <typename RadianceFn>
void render_tile_with(const RenderContext& context, const TileRect& tile, Image* image,
                      RayCounters* counters, RadianceFn&& radiance) {
  const int spp = context.settings.spp;
  const float inv_spp = 1.0f / static_cast<float>(spp);
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      const uint64_t pixel_index = static_cast<uint64_t>(y) * context.settings.width + x;
      Imath::V3f sum(0.0f);
      int hits = 0;
      for (int s = 0; s < spp; ++s) {
        // One sample goes through the pixel centre (the lecture's view ray); more are
        // spread uniformly over the pixel (a box filter).
        const float jx = spp == 1 ? 0.5f : sample_uniform(pixel_index, s, 0);
        const float jy = spp == 1 ? 0.5f : sample_uniform(pixel_index, s, 1);
        const Ray ray =
            context.camera.generate_ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
        ++counters->camera;
        const SampleResult r = radiance(ray, counters);
        sum += r.radiance;
        hits += r.hit ? 1 : 0;
      }
      float* out = image->pixel(x, y);
      out[0] = sum.x * inv_spp;
      out[1] = sum.y * inv_spp;
      out[2] = sum.z * inv_spp;
      out[3] = static_cast<float>(hits) * inv_spp;
    }
  }
}

// The common case: the camera ray's nearest hit is shaded by `shade(ray, hit, counters)`,
// and a ray that hits nothing sees the background.
template <typename ShadeFn>
void render_tile_shading_hits(const RenderContext& context, const TileRect& tile, Image* image,
                              RayCounters* counters, ShadeFn&& shade) {
  render_tile_with(context, tile, image, counters, [&](const Ray& ray, RayCounters* c) {
    SurfaceHit hit;
    if (!context.scene.geometry().intersect(ray, &hit))
      return SampleResult{context.settings.background, false};
    return SampleResult{shade(ray, hit, c), true};
  });
}

}  // namespace prism
