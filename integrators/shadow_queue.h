// Shadow rays in packets: a packet of camera hits is shaded in two steps. First every hit's
// terms (the local shading equation, light by light: integrators/local_shading.h) are
// worked out and the shadow ray of each light that faces the hit and can reach it is queued
// instead of traced; then the queue is traced as 16-ray packets (rtcOccluded16), sorted by
// light so that a packet holds rays from neighbouring points towards one light, and each
// visible term is added to its hit's radiance in the lights' order, so every sum is the one
// shade_direct forms one hit at a time. Any number of lights stays in packets: the lights are
// taken in chunks of kLightsPerChunk, each chunk queued for every hit and traced before the
// next, so the queue has a fixed size and a hit's terms still arrive in the lights' order,
// chunk after chunk. (Which rays share a packet changed with the sorting; occlusion is a
// yes or no, and images of 1 to 64 lights stayed bit-identical: docs/benchmarks.md.)
#pragma once

#include <algorithm>
#include <cstddef>

#include "integrators/direct.h"
#include "integrators/tile_loop.h"

namespace prism {

class ShadowQueue {
 public:
  static constexpr int kLightsPerChunk = 8;
  static constexpr int kCapacity = EmbreeScene::kPacketSize * kLightsPerChunk;

  // `slot`: the light's place in its chunk, 0 .. kLightsPerChunk - 1.
  void add(int lane, int slot, const Ray& ray, const Imath::V3f& contribution) {
    lane_[count_] = lane;
    slot_[count_] = slot;
    rays_[count_] = ray;
    contribution_[count_] = contribution;
    ++count_;
  }
  // Traces the queue and adds each unblocked term to its lane's radiance, in queue order.
  // The rays are traced sorted by light (a stable counting sort), so a packet holds rays
  // from neighbouring points towards one light, as coherent as camera rays, while the terms
  // are still added lane by lane in the order they were queued.
  void resolve(const EmbreeScene& geometry, SampleResult* results, RayCounters* counters) {
    int start[kLightsPerChunk + 1] = {};
    for (int k = 0; k < count_; ++k) ++start[slot_[k] + 1];
    for (int s = 0; s < kLightsPerChunk; ++s) start[s + 1] += start[s];
    for (int k = 0; k < count_; ++k) {
      const int at = start[slot_[k]]++;
      order_[at] = k;
      sorted_[at] = rays_[k];
    }
    for (int first = 0; first < count_; first += EmbreeScene::kPacketSize) {
      const int n = std::min(EmbreeScene::kPacketSize, count_ - first);
      geometry.occluded_packet(&sorted_[first], n, &sorted_blocked_[first]);
    }
    for (int k = 0; k < count_; ++k) blocked_[order_[k]] = sorted_blocked_[k];
    for (int k = 0; k < count_; ++k)
      if (!blocked_[k]) results[lane_[k]].radiance += contribution_[k];
    (*counters)[RayKind::shadow] += static_cast<uint64_t>(count_);
    count_ = 0;
  }

 private:
  int count_ = 0;
  int lane_[kCapacity];
  int slot_[kCapacity];
  int order_[kCapacity];  // order_[j]: the queue entry traced j-th
  Ray rays_[kCapacity];
  Ray sorted_[kCapacity];
  bool sorted_blocked_[kCapacity];
  Imath::V3f contribution_[kCapacity];
  bool blocked_[kCapacity];
};

// shade_direct<F> for every lane of a camera packet, with shadow rays (F.shadows must be
// set): results[i] is the hit's radiance, or the background for a miss; surfaces[i] the
// hit's material response, for whitted's secondary rays.
template <ShadingFlags F>
void shade_packet_direct(const RenderContext& context, const AmbientLight& ambient,
                         const CameraPacket& p, ShadowQueue* queue, SampleResult* results,
                         SurfaceResponse* surfaces, RayCounters* counters) {
  static_assert(F.shadows);
  for (int i = 0; i < p.count; ++i) {
    if (!p.found[i]) {
      results[i] = SampleResult{context.scene.environment().background(p.rays[i].direction), false};
      continue;
    }
    surfaces[i] = evaluate(context.scene.material(p.hits[i].material), p.hits[i]);
    results[i].hit = true;
  }
  // The first chunk's call also forms the ambient term, where each sum starts.
  const size_t terms = light_terms(context.scene);
  const AmbientLight none{Imath::V3f(0.0f), ambient.scope, /*environment=*/0.0f};
  for (size_t first = 0; first == 0 || first < terms; first += ShadowQueue::kLightsPerChunk) {
    const LightRange chunk{first, first + ShadowQueue::kLightsPerChunk};
    for (int i = 0; i < p.count; ++i) {
      if (!p.found[i]) continue;
      const Imath::V3f start = shade_local_with<true>(
          context, first == 0 ? ambient : none, p.hits[i], surfaces[i], -p.rays[i].direction,
          ShadingSample{p.id(i), 0},
          [&](Imath::V3f&, const Ray& shadow_ray, auto&& contribution, size_t light) {
            queue->add(i, static_cast<int>(light - first), shadow_ray, contribution());
          },
          chunk);
      if (first == 0) results[i].radiance = start;
    }
    queue->resolve(context.scene.geometry(), results, counters);
  }
  if constexpr (F.emission) {
    for (int i = 0; i < p.count; ++i)
      if (p.found[i]) results[i].radiance = surfaces[i].emission + results[i].radiance;
  }
}

// Renders the tile with the camera hits' direct light shaded by shade_packet_direct<F>, then
// hands each packet to `then(packet, results, surfaces, counters)` (whitted adds its
// secondary rays there), and returns true; returns false, having done nothing, when F has
// no shadow rays.
template <ShadingFlags F, typename ThenFn>
bool render_tile_queueing_shadows(const RenderContext& context, const AmbientLight& ambient,
                                  const TileRect& tile, Image* image, RayCounters* counters,
                                  ThenFn&& then) {
  if constexpr (F.shadows) {
    // Per-tile scratch, not per packet: every lane that hit is overwritten before use.
    ShadowQueue queue;
    SurfaceResponse surfaces[EmbreeScene::kPacketSize];
    render_tile_packets(context, tile, image, counters,
                        [&](const CameraPacket& p, SampleResult* results, RayCounters* c) {
                          shade_packet_direct<F>(context, ambient, p, &queue, results, surfaces, c);
                          then(p, results, surfaces, c);
                        });
    return true;
  }
  return false;
}

}  // namespace prism
