// The per-pixel sample loop every integrator shares. `radiance(ray, counters)` is a
// template parameter, so each integrator's per-ray code is inlined into its own copy of the
// loop: no virtual call per ray.
#pragma once

#include <cmath>
#include <cstdint>

#include "renderer/integrator.h"
#include "renderer/sampler.h"

namespace prism {

struct SampleResult {
  Imath::V3f radiance;
  bool hit = false;  // the camera ray found geometry (feeds the alpha channel)
};

// The NaN firewall: a sample whose radiance is NaN or infinite is discarded and counted
// (RayCounters::discarded_samples) instead of poisoning its pixel for good. A pixel is the
// mean of its kept samples, and 0 with alpha 0 when none was kept. Without discards this is
// exactly the plain mean: the same float sums in sample order, divided the same way.
template <typename RadianceFn>
void render_tile_with(const RenderContext& context, const TileRect& tile, Image* image,
                      RayCounters* counters, RadianceFn&& radiance) {
  const int spp = context.settings.spp;
  const SamplePass& pass = context.pass;
  const int end = pass.end < 0 ? spp : pass.end;
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      const uint64_t pixel_index = static_cast<uint64_t>(y) * context.settings.width + x;
      if (pass.active && !pass.active[pixel_index]) continue;
      PixelSums sums = pass.sums ? pass.sums[pixel_index] : PixelSums{};
      for (int s = pass.first; s < end; ++s) {
        // Before sample 2^k: the sums of samples [0, 2^k), a complete (0,2)-net.
        if (pass.first_half && s > 0 && (s & (s - 1)) == 0) pass.first_half[pixel_index] = sums;
        // One sample goes through the pixel centre (the lecture's view ray); more are
        // spread over the pixel (a box filter) by the pixel's Owen-scrambled Sobol points,
        // which stratify where independent jitter clumps (renderer/sampler.h). Sample s
        // depends only on (pixel, s), so pass splitting and threads leave the image alone.
        const PixelSample2D j =
            spp == 1 ? PixelSample2D{0.5f, 0.5f}
                     : sobol_owen_pixel_sample(pixel_index, static_cast<uint32_t>(s));
        const Ray ray =
            context.camera.generate_ray(static_cast<float>(x) + j.x, static_cast<float>(y) + j.y);
        ++counters->camera;
        const SampleResult r = radiance(ray, counters);
        if (!std::isfinite(r.radiance.x) || !std::isfinite(r.radiance.y) ||
            !std::isfinite(r.radiance.z)) {
          ++counters->discarded_samples;
          continue;
        }
        sums.radiance += r.radiance;
        sums.radiance_squared += r.radiance * r.radiance;
        sums.hits += r.hit ? 1 : 0;
        ++sums.kept;
      }
      if (pass.sums) pass.sums[pixel_index] = sums;
      float* out = image->pixel(x, y);
      if (sums.kept == 0) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        continue;
      }
      const float inv_kept = 1.0f / static_cast<float>(sums.kept);
      out[0] = sums.radiance.x * inv_kept;
      out[1] = sums.radiance.y * inv_kept;
      out[2] = sums.radiance.z * inv_kept;
      out[3] = static_cast<float>(sums.hits) * inv_kept;
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
