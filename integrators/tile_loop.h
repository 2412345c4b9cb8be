// The per-pixel sample loop every integrator shares. `shade(ray, hit, counters)` is a
// template parameter, so each integrator's per-ray code is inlined into its own copy of the
// loop: no virtual call per ray.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "renderer/geometry/embree_scene.h"
#include "renderer/integrator.h"
#include "renderer/sampling/sampler.h"

namespace prism {

struct SampleResult {
  Imath::V3f radiance;
  bool hit = false;  // the camera ray found geometry (feeds the alpha channel)
};

// Adds one sample to a pixel's sums. The NaN firewall: a sample whose radiance is NaN or
// infinite is discarded and counted (RayCounters::discarded_samples) instead of poisoning
// its pixel for good. A pixel is the mean of its kept samples, and 0 with alpha 0 when none
// was kept. Without discards this is exactly the plain mean: the same float sums in sample
// order, divided the same way.
inline void add_sample(const SampleResult& r, PixelSums* sums, RayCounters* counters) {
  if (!std::isfinite(r.radiance.x) || !std::isfinite(r.radiance.y) ||
      !std::isfinite(r.radiance.z)) {
    ++counters->discarded_samples;
    return;
  }
  sums->radiance += r.radiance;
  sums->radiance_squared += r.radiance * r.radiance;
  sums->hits += r.hit ? 1 : 0;
  ++sums->kept;
}

// A packet of camera rays and their nearest hits, as the tile loop hands them to an
// integrator: lanes [0, count).
struct CameraPacket {
  int count = 0;
  // Which sample of which pixels: an integrator draws the rest of each lane's sample from
  // PixelSampler(sample_key[i], sample_index), dimensions 0 and 1 being the pixel position;
  // the key is the pixel's index under the render's seed (pixel_sample_key).
  uint32_t sample_index = 0;
  uint64_t sample_key[EmbreeScene::kPacketSize];
  Ray rays[EmbreeScene::kPacketSize];
  SurfaceHit hits[EmbreeScene::kPacketSize];
  bool found[EmbreeScene::kPacketSize];

  PixelSampleId id(int lane) const { return {sample_key[lane], sample_index}; }
};

// Takes context.pass's samples of every pixel of the tile; `shade_packet(packet, results,
// counters)` turns each packet of camera rays, traced, into one SampleResult per lane.
//
// Camera rays are traced in packets (EmbreeScene::intersect_packet): the tile is walked in
// blocks of 4 x 4 pixels, and sample s of every pixel of a block makes one packet, rays that
// start at one point and spread over 4 x 4 pixels, the coherent case packets are for.
// Embree may resolve a ray whose packet has other members differently in the last bit than
// alone (a shared edge goes to either triangle: tests/packet_trace_test.cpp), so what shares
// a packet is fixed by the tile and the sample index alone: the thread count, the tile size
// (tiles start at multiples of 4: renderer/render.cpp), and taking the samples in one pass
// or one per pass leave the image bit for bit alone. Each pixel's samples are summed in
// sample order.
template <typename ShadePacketFn>
void render_tile_packets(const RenderContext& context, const TileRect& tile, Image* image,
                         RayCounters* counters, ShadePacketFn&& shade_packet) {
  constexpr int kBlock = kPacketBlock;
  static_assert(kBlock * kBlock == EmbreeScene::kPacketSize);
  const int spp = context.settings.spp;
  const SamplePass& pass = context.pass;
  const int end = pass.end < 0 ? spp : pass.end;
  struct BlockPixel {
    int x, y;
    uint64_t index;  // into the image and the pass's per-pixel state
    uint64_t key;    // what its samples are drawn by
    PixelSums sums;
  };
  BlockPixel pixels[EmbreeScene::kPacketSize];
  CameraPacket packet;
  SampleResult results[EmbreeScene::kPacketSize];
  for (int by = tile.y0; by < tile.y1; by += kBlock) {
    for (int bx = tile.x0; bx < tile.x1; bx += kBlock) {
      int count = 0;
      for (int y = by; y < std::min(by + kBlock, tile.y1); ++y) {
        for (int x = bx; x < std::min(bx + kBlock, tile.x1); ++x) {
          const uint64_t index = static_cast<uint64_t>(y) * context.settings.width + x;
          if (pass.active && !pass.active[index]) continue;
          const uint64_t key = pixel_sample_key(index, context.settings.seed);
          packet.sample_key[count] = key;
          pixels[count++] = {x, y, index, key, pass.sums ? pass.sums[index] : PixelSums{}};
        }
      }
      if (count == 0) continue;
      packet.count = count;
      for (int s = pass.first; s < end; ++s) {
        packet.sample_index = static_cast<uint32_t>(s);
        for (int i = 0; i < count; ++i) {
          // One sample goes through the pixel centre (the lecture's view ray); more are
          // spread over the pixel (a box filter) by the pixel's Owen-scrambled Sobol points,
          // which stratify where independent jitter clumps (renderer/sampling/sampler.h). Sample s
          // depends only on (pixel, s).
          const PixelSample2D j =
              spp == 1 ? PixelSample2D{0.5f, 0.5f}
                       : sobol_owen_pixel_sample(pixels[i].key, static_cast<uint32_t>(s));
          packet.rays[i] = context.camera.generate_ray(static_cast<float>(pixels[i].x) + j.x,
                                                       static_cast<float>(pixels[i].y) + j.y);
        }
        context.scene.geometry().intersect_packet(packet.rays, count, packet.hits, packet.found);
        (*counters)[RayKind::camera] += static_cast<uint64_t>(count);
        shade_packet(packet, results, counters);
        for (int i = 0; i < count; ++i) {
          // Before sample 2^k: the sums of samples [0, 2^k), a complete (0,2)-net.
          if (pass.first_half && s > 0 && (s & (s - 1)) == 0)
            pass.first_half[pixels[i].index] = pixels[i].sums;
          add_sample(results[i], &pixels[i].sums, counters);
        }
      }
      for (int i = 0; i < count; ++i) {
        if (pass.sums) pass.sums[pixels[i].index] = pixels[i].sums;
        write_pixel(pixels[i].sums, image->pixel(pixels[i].x, pixels[i].y));
      }
    }
  }
}

// The common case: each camera ray's nearest hit is shaded by `shade(ray, hit, sample,
// counters)`, `sample` its PixelSampleId, one at a time, and a ray that hits nothing sees the
// environment's background (black where the environment is hidden from the camera).
template <typename ShadeFn>
void render_tile_shading_hits(const RenderContext& context, const TileRect& tile, Image* image,
                              RayCounters* counters, ShadeFn&& shade) {
  render_tile_packets(
      context, tile, image, counters,
      [&](const CameraPacket& p, SampleResult* results, RayCounters* c) {
        for (int i = 0; i < p.count; ++i) {
          results[i] =
              p.found[i] ? SampleResult{shade(p.rays[i], p.hits[i], p.id(i), c), true}
                         : SampleResult{context.scene.environment().background(p.rays[i].direction),
                                        false};
        }
      });
}

}  // namespace prism
