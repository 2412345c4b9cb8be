#include "renderer/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "renderer/sampling/adaptive_sampling.h"
#include "renderer/sampling/random.h"

namespace prism {

// Tiles are whole numbers of the tile loop's 4 x 4 packet blocks (integrators/tile_loop.h),
// which then start at multiples of 4 in the image whatever the tile size: which camera rays
// share a packet, and so the image, does not depend on it.
// A region keeps the full frame's tile grid, each tile cut to the region widened to whole
// packet blocks, so that every pixel is traced in the packet it has in the full frame.
std::vector<TileRect> make_tiles(const RenderSettings& s) {
  const int ts = (std::max(1, s.tile_size) + kPacketBlock - 1) / kPacketBlock * kPacketBlock;
  const TileRect r = s.rendered();
  const int rx0 = r.x0 / kPacketBlock * kPacketBlock, ry0 = r.y0 / kPacketBlock * kPacketBlock;
  const int rx1 = std::min(s.width, (r.x1 + kPacketBlock - 1) / kPacketBlock * kPacketBlock);
  const int ry1 = std::min(s.height, (r.y1 + kPacketBlock - 1) / kPacketBlock * kPacketBlock);
  std::vector<TileRect> tiles;
  for (int y = ry0 / ts * ts; y < ry1; y += ts)
    for (int x = rx0 / ts * ts; x < rx1; x += ts)
      tiles.push_back(
          {std::max(x, rx0), std::max(y, ry0), std::min(x + ts, rx1), std::min(y + ts, ry1)});
  // Visited in a fixed shuffled order, not row by row: the tiles done so far are then a fair
  // sample of the image's cost (sky rows are cheap, the ground dear), so the rate the
  // progress bar's ETA extrapolates holds for the tiles left. The order changes no pixel.
  for (size_t i = tiles.size(); i > 1; --i)
    std::swap(tiles[i - 1], tiles[mix64(0x7469'6c65'7300'0000ULL + i) % i]);
  return tiles;
}

namespace {

using Clock = std::chrono::steady_clock;

// Runs passes over tiles in parallel, adding up the rays every tile cast and reporting
// progress; times the whole render without the PassCallback's share.
class PassRunner {
 public:
  PassRunner(const Integrator& integrator, Image* image, const RenderCallbacks& callbacks)
      : integrator_(integrator), image_(image), callbacks_(callbacks), start_(Clock::now()) {}

  // Tiles run on the caller's task arena, so the thread limit is whoever owns that arena
  // (the session: session/session.h), set once rather than here and again in the app.
  //
  // With a claim_tile callback, task i renders whichever tile the claim hands out, not tile i:
  // no process can be handed more than every tile, and once the claims run dry the remaining
  // tasks return without asking again.
  // Each tile counts `weight` towards the progress total: the samples per pixel it takes.
  void run(const RenderContext& context, const std::vector<TileRect>& tiles, int weight = 1) {
    std::atomic<bool> claims_exhausted{false};
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, tiles.size(), 1),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            if (cancelled()) return;
            size_t tile = i;
            if (callbacks_.claim_tile) {
              if (claims_exhausted) return;
              const std::optional<size_t> claimed = callbacks_.claim_tile();
              if (!claimed || *claimed >= tiles.size()) {
                claims_exhausted = true;
                return;
              }
              tile = *claimed;
            }
            RayCounters counters;
            integrator_.render_tile(context, tiles[tile], image_, &counters);
            for (size_t k = 0; k < kRayKindCount; ++k) rays_[k] += counters.rays[k];
            discarded_ += counters.discarded_samples;
            report(done_ += weight);
          }
        },
        tbb::simple_partitioner());
  }

  // Sticky: once the callback has said so, every later tile and round is skipped.
  bool cancelled() {
    if (!cancelled_ && callbacks_.cancel && callbacks_.cancel()) cancelled_ = true;
    return cancelled_;
  }

  void set_total(int total) { total_ = total; }
  // Tiles a round skips (no active pixel) still count towards the bar.
  void skip(int tiles) { report(done_ += tiles); }
  void finish() {
    if (done_ < total_) report(done_ = total_.load());
  }

  void call(const PassCallback& after_pass, int samples, const Image& image) {
    const auto callback_start = Clock::now();
    after_pass(samples, image);
    callback_time_ += Clock::now() - callback_start;
  }
  double seconds() const {
    return std::chrono::duration<double>(Clock::now() - start_ - callback_time_).count();
  }

  RayCounters rays() const {
    RayCounters r;
    for (size_t k = 0; k < kRayKindCount; ++k) r.rays[k] = rays_[k].load();
    r.discarded_samples = discarded_.load();
    return r;
  }

 private:
  void report(int done) {
    if (callbacks_.progress) callbacks_.progress(done, total_);
  }

  const Integrator& integrator_;
  Image* image_;
  const RenderCallbacks& callbacks_;
  const Clock::time_point start_;
  Clock::duration callback_time_{};
  std::atomic<uint64_t> rays_[kRayKindCount] = {}, discarded_{0};
  std::atomic<bool> cancelled_{false};
  std::atomic<int> done_{0}, total_{0};
};

// Between passes: asks the checkpoint callbacks whether to save and whether to stop, and
// keeps the render's clock (over every run) without the time saving takes.
class Checkpoints {
 public:
  Checkpoints(const RenderCallbacks& callbacks, const PassRunner& runner)
      : callbacks_(callbacks), runner_(runner) {
    if (callbacks.resume) {
      resumed_seconds_ = callbacks.resume->seconds;
      resumed_rays_ = callbacks.resume->rays;
    }
  }

  // True: the render stops here (after `state` was saved, when there is a `save`).
  bool poll(RenderState* state) {
    const bool stop = callbacks_.stop && callbacks_.stop();
    if ((stop || (callbacks_.checkpoint_due && callbacks_.checkpoint_due())) && callbacks_.save) {
      state->rays = rays();
      state->seconds = seconds();
      const auto save_start = Clock::now();
      callbacks_.save(*state);
      save_time_ += Clock::now() - save_start;
    }
    return stop;
  }

  double seconds() const { return resumed_seconds_ + seconds_this_run(); }
  double seconds_this_run() const {
    return runner_.seconds() - std::chrono::duration<double>(save_time_).count();
  }
  RayCounters rays() const {
    RayCounters r = resumed_rays_;
    r += runner_.rays();
    return r;
  }

  void finish(RenderResult* result) const {
    result->seconds = seconds();
    result->rays = rays();
    result->resumed_rays = resumed_rays_;
    if (callbacks_.resume) result->resumed_samples = callbacks_.resume->samples_done;
  }

 private:
  const RenderCallbacks& callbacks_;
  const PassRunner& runner_;
  double resumed_seconds_ = 0.0;
  RayCounters resumed_rays_;
  Clock::duration save_time_{};
};

// The state a render starts from: the resumed one, whose pixels are written into `image` at
// once (an adaptive render never visits its stopped pixels again), or sample 0.
RenderState initial_state(const RenderSettings& s, const RenderState* resume, Image* image) {
  if (!resume) return RenderState::start(s);
  const std::string mismatch = resume->mismatch(s);
  if (!mismatch.empty()) throw std::invalid_argument("cannot resume this render: " + mismatch);
  RenderState state = *resume;
  tbb::parallel_for(0, s.height, [&](int y) {
    for (int x = 0; x < s.width; ++x)
      write_pixel(state.sums[static_cast<size_t>(y) * s.width + x], image->pixel(x, y));
  });
  return state;
}

// The blocks' margins around a region were traced for their neighbours' sake only.
void clear_outside(const TileRect& r, Image* image) {
  for (int y = 0; y < image->height; ++y)
    for (int x = 0; x < image->width; ++x)
      if (x < r.x0 || x >= r.x1 || y < r.y0 || y >= r.y1) std::fill_n(image->pixel(x, y), 4, 0.0f);
}

RenderResult render_uniform(const RenderContext& context, const std::vector<TileRect>& tiles,
                            PassRunner* runner, Image* image, const RenderCallbacks& callbacks) {
  const RenderSettings& s = context.settings;
  const PassCallback& after_pass = callbacks.after_pass;
  const bool checkpoints = callbacks.checkpoints();
  // Passes keep each pixel's sums between them; a single pass keeps them on the stack.
  const bool per_sample = after_pass || checkpoints;
  const int samples = per_sample ? std::max(1, s.spp) : 1;
  RenderState state;
  if (per_sample) state = initial_state(s, callbacks.resume, image);
  Checkpoints clock(callbacks, *runner);
  RenderResult result;
  runner->set_total(static_cast<int>(tiles.size()) * samples);
  runner->skip(static_cast<int>(tiles.size()) * state.samples_done);
  // A render that only needs checkpoints takes its samples in passes of about
  // callbacks.pass_seconds (one sample first, to learn the rate); each pixel still sums its
  // samples in order, so the image is the same however they are grouped. `after_pass` asks
  // for every sample.
  int pass_samples = 1;
  const int first_sample = state.samples_done;
  for (int pass = state.samples_done; pass < samples;) {
    const int end = std::min(samples, pass + pass_samples);
    RenderContext pass_context = context;
    if (per_sample) pass_context.pass = SamplePass{pass, end, state.sums.data()};
    runner->run(pass_context, tiles, end - pass);
    if (runner->cancelled()) break;
    state.samples_done = end;
    if (after_pass) runner->call(after_pass, end, *image);
    if (checkpoints && end < samples && clock.poll(&state)) {
      result.stopped_at_checkpoint = true;
      break;
    }
    pass = end;
    if (!after_pass && callbacks.pass_seconds > 0.0) {
      // The poll's own time (a checkpoint written) is not the render's rate.
      const double per_sample_seconds = clock.seconds_this_run() / (end - first_sample);
      pass_samples = per_sample_seconds > 0.0
                         ? static_cast<int>(std::clamp(callbacks.pass_seconds / per_sample_seconds,
                                                       1.0, static_cast<double>(samples)))
                         : samples;
    }
  }
  result.cancelled = runner->cancelled();
  clock.finish(&result);
  return result;
}

RenderResult render_adaptive(const RenderContext& context, const std::vector<TileRect>& tiles,
                             PassRunner* runner, Image* image, const RenderCallbacks& callbacks) {
  const RenderSettings& s = context.settings;
  const PassCallback& after_pass = callbacks.after_pass;
  const bool checkpoints = callbacks.checkpoints();
  const int spp = std::max(1, s.spp);
  const size_t pixels = static_cast<size_t>(s.width) * s.height;
  RenderState state = initial_state(s, callbacks.resume, image);
  std::vector<PixelSums>& sums = state.sums;
  std::vector<PixelSums>& first_half = state.first_half;
  std::vector<uint8_t>& active = state.active;
  std::vector<uint32_t>& samples = state.samples_per_pixel;
  std::vector<float>& error = state.error;
  std::vector<uint8_t> tile_active;
  // Pixels outside the region take no samples (the blocks' margins around it included).
  if (s.has_region() && !callbacks.resume) {
    const TileRect r = s.region;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x)
        if (x < r.x0 || x >= r.x1 || y < r.y0 || y >= r.y1) {
          active[static_cast<size_t>(y) * s.width + x] = 0;
          samples[static_cast<size_t>(y) * s.width + x] = 0;
        }
  }

  // Checkpoints split rounds into passes of one sample, and progress then counts tiles per
  // sample rather than per round.
  int planned = 0;
  for (int n = 0; n < spp; n = next_round_end(n, s.min_spp, spp)) ++planned;
  runner->set_total(static_cast<int>(tiles.size()) * (checkpoints ? spp : planned));

  // Where the resumed state stands: inside the round that started at `done`, or at its end
  // with the decision made. Only tiles with an active pixel take part, as in the round that
  // was interrupted (a pixel never becomes active again).
  int done = 0;
  while (done < spp && next_round_end(done, s.min_spp, spp) <= state.samples_done)
    done = next_round_end(done, s.min_spp, spp);
  std::vector<TileRect> round_tiles;
  for (const TileRect& t : tiles) {
    bool any = !callbacks.resume;
    for (int y = t.y0; y < t.y1 && !any; ++y)
      for (int x = t.x0; x < t.x1 && !any; ++x) any = active[static_cast<size_t>(y) * s.width + x];
    if (any) round_tiles.push_back(t);
  }
  if (checkpoints) runner->skip(static_cast<int>(tiles.size()) * state.samples_done);

  Checkpoints clock(callbacks, *runner);
  RenderResult result;
  result.rounds = state.rounds;
  while (done < spp && !result.stopped_at_checkpoint) {
    const int end = next_round_end(done, s.min_spp, spp);
    RenderContext round_context = context;
    while (state.samples_done < end) {
      const int first = state.samples_done;
      const int pass_end = checkpoints ? first + 1 : end;
      round_context.pass =
          SamplePass{first, pass_end, sums.data(), active.data(), first_half.data()};
      runner->skip(static_cast<int>(tiles.size() - round_tiles.size()));
      runner->run(round_context, round_tiles);
      if (runner->cancelled()) break;
      state.samples_done = pass_end;
      // Within the round only: its end is polled after the decision below.
      if (checkpoints && pass_end < end && clock.poll(&state)) {
        result.stopped_at_checkpoint = true;
        break;
      }
    }
    if (runner->cancelled() || result.stopped_at_checkpoint) break;
    done = end;
    state.rounds = ++result.rounds;
    if (after_pass) runner->call(after_pass, done, *image);
    if (done >= spp) break;
    if (s.time_limit_seconds > 0.0 && clock.seconds() >= s.time_limit_seconds) {
      result.time_limit_reached = true;
      break;
    }
    if (s.target_error > 0.0f) {
      size_t still_active = 0;
      // Pixels that stop record their count here; the rest get theirs after the last round,
      // so no round walks the whole image for it.
      {
        still_active = update_active_pixels(
            s.width, s.height, sums.data(), first_half.data(), s.target_error, s.error_goal,
            static_cast<uint32_t>(done), &error, active.data(), samples.data());
        // Only tiles that were in this round can still have active pixels.
        tile_active.assign(round_tiles.size(), 0);
        tbb::parallel_for(size_t{0}, round_tiles.size(), [&](size_t k) {
          const TileRect& t = round_tiles[k];
          for (int y = t.y0; y < t.y1 && !tile_active[k]; ++y)
            for (int x = t.x0; x < t.x1 && !tile_active[k]; ++x)
              tile_active[k] = active[static_cast<size_t>(y) * s.width + x];
        });
      }
      if (still_active == 0) break;
      size_t kept = 0;
      for (size_t k = 0; k < round_tiles.size(); ++k)
        if (tile_active[k]) round_tiles[kept++] = round_tiles[k];
      round_tiles.resize(kept);
    }
    if (checkpoints && clock.poll(&state)) result.stopped_at_checkpoint = true;
  }
  for (size_t i = 0; i < pixels; ++i)
    if (active[i]) samples[i] = static_cast<uint32_t>(done);
  result.cancelled = runner->cancelled();
  if (!result.cancelled && !result.stopped_at_checkpoint) runner->finish();
  clock.finish(&result);
  result.samples_per_pixel = std::move(samples);
  return result;
}

}  // namespace

RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const RenderCallbacks& callbacks) {
  const RenderSettings& s = context.settings;
  if (callbacks.claim_tile && (s.adaptive() || callbacks.after_pass))
    throw std::logic_error("render: claim_tile needs a uniform single-pass render");
  *image = Image(s.width, s.height);
  const std::vector<TileRect> tiles = make_tiles(s);
  PassRunner runner(integrator, image, callbacks);
  RenderResult result = s.adaptive() ? render_adaptive(context, tiles, &runner, image, callbacks)
                                     : render_uniform(context, tiles, &runner, image, callbacks);
  if (s.has_region()) clear_outside(s.region, image);
  return result;
}

}  // namespace prism
