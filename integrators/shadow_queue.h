// Shadow rays in packets: a packet of camera hits is shaded in two steps. First every hit's
// terms (the local shading equation, light by light: integrators/local_shading.h) are
// worked out and each facing light's shadow ray is queued instead of traced; then the queue
// is traced as 16-ray packets (rtcOccluded16: rays from neighbouring points towards one
// light are as coherent as camera rays) and each visible term added to its hit's radiance,
// in the lights' order, so every sum is the one shade_direct forms one hit at a time.
// Scenes with more lights than fit the queue shade one hit at a time instead.
#pragma once

#include <algorithm>
#include <cstddef>

#include "integrators/direct.h"
#include "integrators/tile_loop.h"

namespace prism {

class ShadowQueue {
 public:
  static constexpr int kMaxLights = 8;
  static constexpr int kCapacity = EmbreeScene::kPacketSize * kMaxLights;

  // Whether a packet's shadow rays towards `lights` lights always fit.
  static bool fits(size_t lights) { return lights <= static_cast<size_t>(kMaxLights); }

  void add(int lane, const Ray& ray, const Imath::V3f& contribution) {
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
    (*counters)[RayKind::shadow] += static_cast<uint64_t>(count_);
    count_ = 0;
  }

 private:
  int count_ = 0;
  int lane_[kCapacity];
  Ray rays_[kCapacity];
  Imath::V3f contribution_[kCapacity];
  bool blocked_[kCapacity];
};

// shade_direct<F> for every lane of a camera packet, with shadow rays (F.shadows must be
// set, and ShadowQueue::fits the scene's lights): results[i] is the hit's radiance, or the
// background for a miss; surfaces[i] the hit's material response, for whitted's secondary
// rays.
template <ShadingFlags F>
void shade_packet_direct(const RenderContext& context, const AmbientLight& ambient,
                         const CameraPacket& p, ShadowQueue* queue, SampleResult* results,
                         SurfaceResponse* surfaces, RayCounters* counters) {
  static_assert(F.shadows);
  for (int i = 0; i < p.count; ++i) {
    if (!p.found[i]) {
      results[i] = SampleResult{context.scene.environment().radiance(p.rays[i].direction), false};
      continue;
    }
    surfaces[i] = evaluate(context.scene.material(p.hits[i].material), p.hits[i]);
    results[i].hit = true;
    results[i].radiance =
        shade_local_with<true>(context, ambient, p.hits[i], surfaces[i], -p.rays[i].direction,
                               [&](Imath::V3f&, const Ray& shadow_ray, auto&& contribution) {
                                 queue->add(i, shadow_ray, contribution());
                               });
  }
  queue->resolve(context.scene.geometry(), results, counters);
  if constexpr (F.emission) {
    for (int i = 0; i < p.count; ++i)
      if (p.found[i]) results[i].radiance = surfaces[i].emission + results[i].radiance;
  }
}

// Renders the tile with the camera hits' direct light shaded by shade_packet_direct<F>, then
// hands each packet to `then(packet, results, surfaces, counters)` (whitted adds its
// secondary rays there), and returns true; returns false, having done nothing, when F has
// no shadow rays or the scene has more lights than the queue takes.
template <ShadingFlags F, typename ThenFn>
bool render_tile_queueing_shadows(const RenderContext& context, const AmbientLight& ambient,
                                  const TileRect& tile, Image* image, RayCounters* counters,
                                  ThenFn&& then) {
  if constexpr (F.shadows) {
    if (ShadowQueue::fits(context.scene.lights().size())) {
      // Per-tile scratch, not per packet: every lane that hit is overwritten before use.
      ShadowQueue queue;
      SurfaceResponse surfaces[EmbreeScene::kPacketSize];
      render_tile_packets(context, tile, image, counters,
                          [&](const CameraPacket& p, SampleResult* results, RayCounters* c) {
                            shade_packet_direct<F>(context, ambient, p, &queue, results, surfaces,
                                                   c);
                            then(p, results, surfaces, c);
                          });
      return true;
    }
  }
  return false;
}

}  // namespace prism
