#include "renderer/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace prism {

RenderResult render(const Integrator& integrator, const RenderContext& context, Image* image,
                    const ProgressCallback& progress) {
  const RenderSettings& s = context.settings;
  *image = Image(s.width, s.height);
  const int ts = std::max(1, s.tile_size);
  std::vector<TileRect> tiles;
  for (int y = 0; y < s.height; y += ts)
    for (int x = 0; x < s.width; x += ts)
      tiles.push_back({x, y, std::min(x + ts, s.width), std::min(y + ts, s.height)});

  std::atomic<uint64_t> camera{0}, shadow{0}, reflection{0}, refraction{0};
  std::atomic<int> done{0};
  const int total = static_cast<int>(tiles.size());
  const auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, tiles.size(), 1),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            RayCounters counters;
            integrator.render_tile(context, tiles[i], image, &counters);
            camera += counters.camera;
            shadow += counters.shadow;
            reflection += counters.reflection;
            refraction += counters.refraction;
            const int n = ++done;
            if (progress) progress(n, total);
          }
        },
        tbb::simple_partitioner());
  });
  RenderResult result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.rays = {camera.load(), shadow.load(), reflection.load(), refraction.load()};
  return result;
}

}  // namespace prism
