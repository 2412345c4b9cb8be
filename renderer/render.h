// Renders an image in tiles, in parallel with TBB. Every pixel's samples depend only on
// (pixel, sample), so the image is bit-identical whatever the thread count or tile order.
#pragma once

#include <functional>

#include "renderer/integrator.h"

namespace prism {

struct RenderResult {
  RayCounters rays;      // also counts the non-finite samples discarded
  double seconds = 0.0;  // rendering alone, without the time spent in a PassCallback
};

// Called after each finished tile, possibly from several threads at once.
using ProgressCallback = std::function<void(int tiles_done, int tiles_total)>;

// Called on the calling thread after each pass with the samples per pixel taken so far and
// the image of their means.
using PassCallback = std::function<void(int samples_done, const Image& image)>;

// With `after_pass`, the image is rendered in settings.spp passes, pass k taking sample k of
// every pixel, and `after_pass` sees each intermediate image (e.g. to measure convergence).
// The final image is bit-identical to a single-pass render: each pixel adds the same samples
// in the same order and divides once at the end.
RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const ProgressCallback& progress = {}, const PassCallback& after_pass = {});

}  // namespace prism
