// The small interface between the tile loop and the integrators (integrators/ implements
// it, one file each). An integrator is called once per tile, not per ray, so its per-ray
// code is free to inline and specialise.
#pragma once

#include <cstdint>

#include <Imath/ImathVec.h>

#include "renderer/camera.h"
#include "renderer/image.h"
#include "renderer/render_scene.h"

namespace prism {

struct RayCounters {
  uint64_t camera = 0;
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;

  uint64_t total() const { return camera + shadow + reflection + refraction; }
  RayCounters& operator+=(const RayCounters& o) {
    camera += o.camera;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    return *this;
  }
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 1;        // spp = 1 samples pixel centres, as the lecture's view rays do
  int max_depth = 5;  // whitted: longest chain of reflection/refraction rays
  int threads = 0;    // 0 = every core
  int tile_size = 16;
  Imath::V3f ambient{0.0f, 0.0f, 0.0f};     // I_a: uniform ambient radiance
  Imath::V3f background{0.0f, 0.0f, 0.0f};  // radiance of rays that leave the scene
};

struct TileRect {
  int x0, y0, x1, y1;  // [x0, x1) x [y0, y1)
};

struct RenderContext {
  const RenderScene& scene;
  const Camera& camera;
  const RenderSettings& settings;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual const char* name() const = 0;
  // Writes the final RGBA of every pixel in `tile`; adds the rays it cast to `counters`.
  virtual void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                           RayCounters* counters) const = 0;
};

}  // namespace prism
