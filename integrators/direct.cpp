// The direct-light tile loop in its four instantiations (shadow rays or not, emission or
// not), picked once per tile. phong, shadow and whitted without secondary rays all run
// these same functions.
#include "integrators/direct.h"

#include "integrators/shadow_queue.h"
#include "integrators/tile_loop.h"

namespace prism {
namespace {

// Direct light only: the secondary-ray flags mean nothing here and are off.
constexpr ShadingFlags direct_flags(bool shadows, bool emission) {
  return ShadingFlags{shadows, emission, /*mirror=*/false, /*transmission=*/false};
}

template <ShadingFlags F>
void render_direct_tile_with(const RenderContext& context, const AmbientLight& ambient, const TileRect& tile,
                             Image* image, RayCounters* counters) {
  const auto direct_only = [](const CameraPacket&, SampleResult*, SurfaceResponse*, RayCounters*) {
  };
  if (render_tile_queueing_shadows<F>(context, ambient, tile, image, counters, direct_only)) return;
  render_tile_shading_hits(
      context, tile, image, counters,
      [&](const Ray& ray, const SurfaceHit& hit, const PixelSampleId& sample, RayCounters* c) {
        const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit);
        return shade_direct<F>(context, ambient, hit, surface, -ray.direction, {sample, 0}, c);
      });
}

}  // namespace

void render_direct_tile(const ShadingFlags& flags, const RenderContext& context, const AmbientLight& ambient,
                        const TileRect& tile, Image* image, RayCounters* counters) {
  if (flags.shadows) {
    if (flags.emission)
      render_direct_tile_with<direct_flags(true, true)>(context, ambient, tile, image, counters);
    else
      render_direct_tile_with<direct_flags(true, false)>(context, ambient, tile, image, counters);
  } else {
    if (flags.emission)
      render_direct_tile_with<direct_flags(false, true)>(context, ambient, tile, image, counters);
    else
      render_direct_tile_with<direct_flags(false, false)>(context, ambient, tile, image, counters);
  }
}

}  // namespace prism
