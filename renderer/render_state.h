// What a render has accumulated at a pass boundary, enough to continue it later (a
// checkpoint: session/checkpoint_file.h stores one) with the same result bit for bit as if
// it had never stopped: each pixel's sums are exactly the floats an uninterrupted render
// holds after the same samples, so continuing adds the remaining samples in the same order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/integrator.h"

namespace prism {

struct RenderState {
  // The film the state belongs to: a state only continues a render of the same size,
  // samples and adaptive choices (RenderState::mismatch). The time limit may differ: it
  // decides when to stop, not which samples a pixel takes.
  int width = 0, height = 0, spp = 0, min_spp = 0;
  float target_error = 0.0f;
  ErrorGoal error_goal = ErrorGoal::pixel;
  bool adaptive = false;

  // Samples every pixel has taken (uniform), or every still active pixel (adaptive). In an
  // adaptive render a state that ends a round was saved after that round's decision.
  int samples_done = 0;
  int rounds = 0;  // adaptive rounds completed
  RayCounters rays;
  double seconds = 0.0;  // rendering so far, over every run

  std::vector<PixelSums> sums;  // per pixel, row-major
  // Adaptive only (empty otherwise), per pixel: the sums of the first 2^k samples, whether
  // the pixel still samples, the samples a stopped pixel took, and each pixel's last error
  // estimate. A stopped pixel's estimate is read in its neighbours' decisions; with
  // kNeighbourWeight <= 1 it cannot change one (it stopped below the target), but the
  // state keeps it so that a resumed decision reads exactly what an uninterrupted one does.
  std::vector<PixelSums> first_half;
  std::vector<uint8_t> active;
  std::vector<uint32_t> samples_per_pixel;
  std::vector<float> error;

  // A state at sample 0 of a render of `settings`, with its buffers sized.
  static RenderState start(const RenderSettings& settings);

  // Empty when this state can continue a render of `settings`; otherwise why not, as one
  // phrase ("it is for a 64x64 film, not 32x32").
  std::string mismatch(const RenderSettings& settings) const;
};

}  // namespace prism
