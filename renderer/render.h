// Renders an image in tiles, in parallel with TBB. Every pixel's samples depend only on
// (pixel, sample), so the image is bit-identical whatever the thread count or tile order.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "renderer/integrator.h"
#include "renderer/render_state.h"

namespace prism {

struct RenderResult {
  RayCounters rays;      // also counts the non-finite samples discarded
  double seconds = 0.0;  // rendering alone, without the time spent in a PassCallback
  // Adaptive renders (settings.adaptive()) only; a uniform render leaves them empty or 0.
  int rounds = 0;
  bool time_limit_reached = false;
  // RenderCallbacks::cancel said stop: the image holds what the finished tiles wrote.
  bool cancelled = false;
  // RenderCallbacks::stop said stop: the render ended at a pass boundary after handing its
  // state to RenderCallbacks::save; the image is unfinished.
  bool stopped_at_checkpoint = false;
  // With RenderCallbacks::resume: the samples per pixel and the rays it brought in. `rays`
  // and `seconds` count them too, so that they describe the whole image.
  int resumed_samples = 0;
  RayCounters resumed_rays;
  std::vector<uint32_t> samples_per_pixel;  // row-major: the samples each pixel took

  // Samples per pixel taken, over the pixels rendered (one camera ray per sample).
  double mean_spp(const RenderSettings& settings) const {
    return static_cast<double>(rays[RayKind::camera]) /
           static_cast<double>(settings.rendered_pixels());
  }
};

// Called after each finished tile, possibly from several threads at once.
using ProgressCallback = std::function<void(int tiles_done, int tiles_total)>;

// Called on the calling thread after each pass with the samples per pixel taken so far and
// the image of their means.
using PassCallback = std::function<void(int samples_done, const Image& image)>;

// Each pass costs a sweep over every tile and every pixel's stored sums, and a tail where
// threads wait for the pass's last tiles: about 10 ms of wall a pass on a 640 x 480 frame,
// far more than its instructions. At one sample a pass that was 6 % of a checkpointed render,
// at 0.5 s a pass 2.2 %, at 2 s 0.6 % (docs/batch-benchmarks.md). Two seconds still keep a
// stop close: Slurm's --signal warns a minute ahead, Kubernetes grants 30 s.
inline constexpr double kDefaultPassSeconds = 2.0;

struct RenderCallbacks {
  ProgressCallback progress;
  PassCallback after_pass;
  // Polled before each tile, possibly from several threads at once; true stops the render
  // (RenderResult::cancelled).
  std::function<bool()> cancel;
  // Which tiles of make_tiles(settings) this process renders, when several processes share
  // one frame (distributed/): each call hands out a tile no other caller gets, or nothing once
  // none is left, and may come from several threads at once. Unset: every tile. Only for a
  // uniform render without after_pass, whose single pass makes a tile index mean one piece
  // of work.
  std::function<std::optional<size_t>()> claim_tile;

  // Checkpoints (renderer/render_state.h). With any of these set the render runs its samples
  // in passes (of about pass_seconds; adaptive renders in their rounds), keeping each
  // pixel's sums between passes, and between passes (never
  // within one, and not after the last) polls `checkpoint_due` and `stop`: either hands the
  // state to `save`, and `stop` then ends the render (RenderResult::stopped_at_checkpoint).
  // Called on the calling thread; the time they take is not counted as rendering.
  std::function<bool()> checkpoint_due;
  std::function<bool()> stop;
  std::function<void(const RenderState&)> save;
  // Continue from this state instead of sample 0; it must match the film
  // (RenderState::mismatch; std::invalid_argument otherwise).
  const RenderState* resume = nullptr;
  // About how long a uniform render's pass between two polls runs (after a first pass of one
  // sample that measures the rate); 0 takes one sample per pass, so that every sample
  // boundary can be stopped at (the checkpoint tests).
  double pass_seconds = kDefaultPassSeconds;

  bool checkpoints() const { return checkpoint_due || stop || save || resume; }
};

// The tiles render() splits the image into, row by row; RenderCallbacks::claim_tile hands out
// indices into this list.
std::vector<TileRect> make_tiles(const RenderSettings& settings);

// Runs on the calling thread's task arena: the caller sets the thread limit by running it
// inside a tbb::task_arena (session/session.h does).
//
// With `callbacks.after_pass`, the image is rendered in settings.spp passes, pass k taking sample k
// of every pixel, and `callbacks.after_pass` sees each intermediate image (e.g. to measure
// convergence). The final image is bit-identical to a single-pass render: each pixel adds the same
// samples in the same order and divides once at the end.
//
// When settings.adaptive(), samples are taken in rounds (renderer/sampling/adaptive_sampling.h):
// after each, pixels whose neighbourhood has converged below settings.target_error stop, and
// once settings.time_limit_seconds has passed no new round starts. `callbacks.after_pass` then sees
// the image after each round, with the most samples any pixel has taken; `callbacks.progress`
// counts tiles against the rounds a render to settings.spp would need.
//
// With checkpoint callbacks the image is bit-identical too, however often the render was
// stopped and resumed: every pass boundary leaves the sums an uninterrupted render holds
// there, and an adaptive round split into passes decides only at its end.
RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const RenderCallbacks& callbacks = {});

}  // namespace prism
