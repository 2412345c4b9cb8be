// Steps per second of the flock (simulation/flock.h) in the shipped clip's box and sphere
// field (scenes/boids/flock.json), boids spread through the whole box:
//   - "same box": 1 000 and 10 000 boids in the clip's box. 10 000 there are ten times as
//     dense, with about ten times the neighbours each: the hard case.
//   - "same density": 10 000 boids in the box and field scaled by 10^(1/3) on every axis (the
//     spheres' radii too), so each boid has as many neighbours as with 1 000 in the clip's box.
// on 1 and 2 threads.
//
//   build/bench/boids_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//
// items_per_second is steps per second.
#include <cmath>
#include <string>

#include <benchmark/benchmark.h>

#include "simulation/flock.h"
#include "simulation/flock_config.h"

namespace prism {
namespace {

FlockParameters bench_flock(int boids, bool same_density) {
  FlockParameters p = read_flock_config(PRISM_SOURCE_DIR "/scenes/boids/flock.json").flock;
  p.boids = boids;
  if (same_density) {
    const float k = std::cbrt(static_cast<float>(boids) / 1000.0f);
    p.bounds.min *= k;
    p.bounds.max *= k;
    for (SphereObstacle& s : p.obstacles) {
      s.centre *= k;
      s.radius *= k;
    }
  }
  p.spawn = p.bounds;  // the whole box: 10 000 boids have no room in the clip's spawn corner
  return p;
}

void BM_FlockStep(benchmark::State& state) {
  const int boids = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const bool same_density = state.range(2) != 0;
  Flock flock(bench_flock(boids, same_density), threads);
  flock.run(60);  // past the start, where every boid still flies alone
  for (auto _ : state) flock.step();
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::to_string(boids) + " boids, " + std::to_string(threads) + " thread(s), " +
                 (same_density ? "same density" : "same box"));
}
BENCHMARK(BM_FlockStep)
    ->Args({1000, 1, 0})
    ->Args({10000, 1, 0})
    ->Args({10000, 1, 1})
    ->Args({1000, 2, 0})
    ->Args({10000, 2, 0})
    ->Args({10000, 2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace prism

BENCHMARK_MAIN();
