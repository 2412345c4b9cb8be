// Steps per second of the flock (simulation/flock.h): the shipped clip's box and sphere field
// (scenes/boids/flock.json) with 1 000 and 10 000 boids, on 1 and 2 threads.
//
//   build/bench/boids_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//
// items_per_second is steps per second. 10 000 boids in the same box are ten times as dense,
// so each also has about ten times the neighbours: the second figure is the harder case, not
// a larger copy of the first.
#include <string>

#include <benchmark/benchmark.h>

#include "simulation/flock.h"
#include "simulation/flock_config.h"

namespace prism {
namespace {

void BM_FlockStep(benchmark::State& state) {
  FlockParameters p = read_flock_config(PRISM_SOURCE_DIR "/scenes/boids/flock.json").flock;
  p.boids = static_cast<int>(state.range(0));
  p.spawn = p.bounds;  // the whole box: 10 000 boids have no room in the clip's spawn corner
  Flock flock(p, static_cast<int>(state.range(1)));
  flock.run(60);  // past the start, where every boid still flies alone
  for (auto _ : state) flock.step();
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::to_string(p.boids) + " boids, " + std::to_string(state.range(1)) +
                 " thread(s)");
}
BENCHMARK(BM_FlockStep)
    ->ArgsProduct({{1000, 10000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace prism

BENCHMARK_MAIN();
