#include "renderer/render_state.h"

#include <algorithm>

#include "renderer/sampling/adaptive_sampling.h"

namespace prism {
namespace {

std::string film_text(int width, int height, int spp) {
  return std::to_string(width) + "x" + std::to_string(height) + " at " + std::to_string(spp) +
         " spp";
}

// Rounds that end at or before `samples`: a state is saved at a pass boundary, so this is
// the number of rounds an uninterrupted render had completed there.
int rounds_ended(int samples, int min_spp, int spp) {
  int rounds = 0;
  for (int n = 0; n < spp;) {
    n = next_round_end(n, min_spp, spp);
    if (n > samples) break;
    ++rounds;
  }
  return rounds;
}

}  // namespace

RenderState RenderState::start(const RenderSettings& s) {
  RenderState state;
  state.width = s.width;
  state.height = s.height;
  state.spp = std::max(1, s.spp);
  state.min_spp = s.min_spp;
  state.target_error = s.target_error;
  state.error_goal = s.error_goal;
  state.adaptive = s.adaptive();
  const size_t pixels = static_cast<size_t>(s.width) * s.height;
  state.sums.assign(pixels, PixelSums{});
  if (state.adaptive) {
    state.first_half.assign(pixels, PixelSums{});
    state.active.assign(pixels, 1);
    state.samples_per_pixel.assign(pixels, 0);
    state.error.assign(pixels, 0.0f);
  }
  return state;
}

std::string RenderState::mismatch(const RenderSettings& s) const {
  const int expected_spp = std::max(1, s.spp);
  if (width != s.width || height != s.height || spp != expected_spp)
    return "it is for a " + film_text(width, height, spp) + " film, not " +
           film_text(s.width, s.height, expected_spp);
  if (adaptive != s.adaptive())
    return adaptive ? "it is for an adaptive render, this one is uniform"
                    : "it is for a uniform render, this one is adaptive";
  // Bitwise: a target error that differs in the last bit stops other pixels.
  if (adaptive && (min_spp != s.min_spp || target_error != s.target_error))
    return "it is for --min-spp " + std::to_string(min_spp) + " --target-error " +
           std::to_string(target_error) + ", not " + std::to_string(s.min_spp) + " and " +
           std::to_string(s.target_error);
  if (adaptive && error_goal != s.error_goal)
    return std::string("it is for --error-goal ") + to_string(error_goal) + ", not " +
           to_string(s.error_goal);
  const size_t pixels = static_cast<size_t>(width) * height;
  const size_t adaptive_pixels = adaptive ? pixels : 0;
  if (sums.size() != pixels || first_half.size() != adaptive_pixels ||
      active.size() != adaptive_pixels || samples_per_pixel.size() != adaptive_pixels ||
      error.size() != adaptive_pixels)
    return "its buffers do not match its film";
  if (samples_done < 0 || samples_done > spp)
    return "it has " + std::to_string(samples_done) + " of " + std::to_string(spp) +
           " samples done";
  if (rounds != (adaptive ? rounds_ended(samples_done, min_spp, spp) : 0))
    return "its round count does not match its samples";
  for (size_t i = 0; i < adaptive_pixels; ++i)
    if (active[i] > 1 || (!active[i] && samples_per_pixel[i] > static_cast<uint32_t>(samples_done)))
      return "its per-pixel sample counts are inconsistent";
  return "";
}

}  // namespace prism
