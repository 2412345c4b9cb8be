// Renders an image in tiles, in parallel with TBB. Every pixel's samples depend only on
// (pixel, sample), so the image is bit-identical whatever the thread count or tile order.
#pragma once

#include <functional>

#include "renderer/integrator.h"

namespace prism {

struct RenderResult {
  RayCounters rays;
  double seconds = 0.0;
};

// Called after each finished tile, possibly from several threads at once.
using ProgressCallback = std::function<void(int tiles_done, int tiles_total)>;

RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const ProgressCallback& progress = {});

}  // namespace prism
