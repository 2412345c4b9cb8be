// The direct-light tile loop in its four instantiations (shadow rays or not, emission or
// not), picked once per tile. phong, shadow and whitted without secondary rays all run
// these same functions.
#include "integrators/direct.h"

#include <algorithm>

#include "integrators/tile_loop.h"

namespace prism {
namespace {

// Direct light only: the secondary-ray flags mean nothing here and are off.
constexpr ShadingFlags direct_flags(bool shadows, bool emission) {
  return ShadingFlags{shadows, emission, /*mirror=*/false, /*transmission=*/false};
}

// Shadow rays in packets: a packet of camera hits is shaded in two steps. First every hit's
// terms (renderer's local shading equation, light by light) are worked out and each facing
// light's shadow ray is queued instead of traced; then the queue is traced as 16-ray
// packets (rtcOccluded16: rays from neighbouring points towards one light are as coherent
// as camera rays) and each visible term added to its hit's radiance, in the lights' order,
// so every sum is the one shade_direct forms. Scenes with more lights than fit the queue
// shade one hit at a time instead.
constexpr int kMaxQueuedLights = 8;

class ShadowQueue {
 public:
  static constexpr int kCapacity = EmbreeScene::kPacketSize * kMaxQueuedLights;

  void add(int lane, const Ray& ray, const V3f& contribution) {
    lane_[count_] = lane;
    rays_[count_] = ray;
    contribution_[count_] = contribution;
    ++count_;
  }
  // Traces the queue and adds each unblocked term to its lane's radiance, in queue order.
  void resolve(const EmbreeScene& geometry, SampleResult* results, RayCounters* counters) {
    for (int first = 0; first < count_; first += EmbreeScene::kPacketSize) {
      const int n = std::min(EmbreeScene::kPacketSize, count_ - first);
      geometry.occluded_packet(&rays_[first], n, &blocked_[first]);
    }
    for (int k = 0; k < count_; ++k)
      if (!blocked_[k]) results[lane_[k]].radiance += contribution_[k];
    counters->shadow += static_cast<uint64_t>(count_);
    count_ = 0;
  }

 private:
  int count_ = 0;
  int lane_[kCapacity];
  Ray rays_[kCapacity];
  V3f contribution_[kCapacity];
  bool blocked_[kCapacity];
};

template <ShadingFlags F>
void render_direct_tile_with(const RenderContext& context, const TileRect& tile, Image* image,
                             RayCounters* counters) {
  const bool queue_shadows =
      F.shadows && context.scene.lights().size() <= static_cast<size_t>(kMaxQueuedLights);
  if (!queue_shadows) {
    render_tile_shading_hits(
        context, tile, image, counters, [&](const Ray& ray, const SurfaceHit& hit, RayCounters* c) {
          const SurfaceResponse surface = evaluate(context.scene.material(hit.material), hit);
          return shade_direct<F>(context, hit, surface, -ray.direction, c);
        });
    return;
  }
  ShadowQueue queue;
  render_tile_packets(context, tile, image, counters,
                      [&](const CameraPacket& p, SampleResult* results, RayCounters* c) {
                        V3f emission[EmbreeScene::kPacketSize];
                        for (int i = 0; i < p.count; ++i) {
                          if (!p.found[i]) {
                            results[i] = SampleResult{context.settings.background, false};
                            continue;
                          }
                          const SurfaceResponse surface =
                              evaluate(context.scene.material(p.hits[i].material), p.hits[i]);
                          emission[i] = surface.emission;
                          results[i].hit = true;
                          results[i].radiance = shade_local_with<true>(
                              context, p.hits[i], surface, -p.rays[i].direction,
                              [&](V3f&, const Ray& shadow_ray, auto&& contribution) {
                                queue.add(i, shadow_ray, contribution());
                              });
                        }
                        queue.resolve(context.scene.geometry(), results, c);
                        if constexpr (F.emission) {
                          for (int i = 0; i < p.count; ++i)
                            if (p.found[i]) results[i].radiance = emission[i] + results[i].radiance;
                        }
                      });
}

}  // namespace

void render_direct_tile(const ShadingFlags& flags, const RenderContext& context,
                        const TileRect& tile, Image* image, RayCounters* counters) {
  if (flags.shadows) {
    if (flags.emission)
      render_direct_tile_with<direct_flags(true, true)>(context, tile, image, counters);
    else
      render_direct_tile_with<direct_flags(true, false)>(context, tile, image, counters);
  } else {
    if (flags.emission)
      render_direct_tile_with<direct_flags(false, true)>(context, tile, image, counters);
    else
      render_direct_tile_with<direct_flags(false, false)>(context, tile, image, counters);
  }
}

}  // namespace prism
