#include "renderer/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace prism {

RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const ProgressCallback& progress, const PassCallback& after_pass) {
  using Clock = std::chrono::steady_clock;
  const RenderSettings& s = context.settings;
  *image = Image(s.width, s.height);
  const int ts = std::max(1, s.tile_size);
  std::vector<TileRect> tiles;
  for (int y = 0; y < s.height; y += ts)
    for (int x = 0; x < s.width; x += ts)
      tiles.push_back({x, y, std::min(x + ts, s.width), std::min(y + ts, s.height)});

  // Passes keep each pixel's sums between them; a single pass keeps them on the stack.
  const int passes = after_pass ? std::max(1, s.spp) : 1;
  std::vector<PixelSums> sums(after_pass ? static_cast<size_t>(s.width) * s.height : 0);

  std::atomic<uint64_t> camera{0}, shadow{0}, reflection{0}, refraction{0}, discarded{0};
  std::atomic<int> done{0};
  const int total = static_cast<int>(tiles.size()) * passes;
  Clock::duration callback_time{};
  const auto start = Clock::now();
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  for (int pass = 0; pass < passes; ++pass) {
    RenderContext pass_context = context;
    if (after_pass) pass_context.pass = SamplePass{pass, pass + 1, sums.data()};
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<size_t>(0, tiles.size(), 1),
          [&](const tbb::blocked_range<size_t>& range) {
            for (size_t i = range.begin(); i != range.end(); ++i) {
              RayCounters counters;
              integrator.render_tile(pass_context, tiles[i], image, &counters);
              camera += counters.camera;
              shadow += counters.shadow;
              reflection += counters.reflection;
              refraction += counters.refraction;
              discarded += counters.discarded_samples;
              const int n = ++done;
              if (progress) progress(n, total);
            }
          },
          tbb::simple_partitioner());
    });
    if (after_pass) {
      const auto callback_start = Clock::now();
      after_pass(pass + 1, *image);
      callback_time += Clock::now() - callback_start;
    }
  }
  RenderResult result;
  result.seconds = std::chrono::duration<double>(Clock::now() - start - callback_time).count();
  result.rays.camera = camera.load();
  result.rays.shadow = shadow.load();
  result.rays.reflection = reflection.load();
  result.rays.refraction = refraction.load();
  result.rays.discarded_samples = discarded.load();
  return result;
}

}  // namespace prism
