// What one random number of the sampler (renderer/sampling/sampler.h) costs, in a form
// callgrind can count: every benchmark runs a fixed number of iterations over the same
// inputs, so its instruction count divided by iterations x calls is instructions per call.
// The inputs (pixel, sample, dimension) are read from an array, so the compiler cannot hoist
// the hashing of one pixel or sample out of the loop as it could for nested loops; BM_Loop
// runs the same loop around a trivial function, the overhead to subtract.
//
//   valgrind --tool=callgrind --toggle-collect='*BM_*' --callgrind-out-file=cg.out
//            build/bench/sampler_cost_bench
//   callgrind_annotate cg.out | grep BM_
//
// It uses only sobol_owen_pixel_sample, sample_dimension and PixelSampler, so the same file
// compiled against an older sampler.h measures that one.
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

#include "renderer/sampling/sampler.h"

namespace prism {
namespace {

constexpr int kIterations = 10;

struct Draw {
  uint64_t pixel;
  uint32_t sample, dimension;
};

// 64 pixels x 64 samples x the dimensions `first`, `first + step`, ... below `end`.
std::vector<Draw> draws(uint32_t first, uint32_t end, uint32_t step) {
  std::vector<Draw> v;
  for (uint64_t pixel = 0; pixel < 64; ++pixel)
    for (uint32_t sample = 0; sample < 64; ++sample)
      for (uint32_t d = first; d < end; d += step) v.push_back({pixel * 7919 + 13, sample, d});
  return v;
}

// Built before main, so no benchmark's count includes them.
const std::vector<Draw> kPairStarts = draws(2, 10, 2);   // 2, 4, 6, 8
const std::vector<Draw> kPairSeconds = draws(3, 10, 2);  // 3, 5, 7, 9
const std::vector<Draw> kSamples = draws(2, 3, 1);       // one per (pixel, sample)

void report(benchmark::State& state, size_t calls, int dimensions_per_call) {
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(calls) * dimensions_per_call);
  state.counters["calls"] = double(calls);
}

void BM_Loop(benchmark::State& state) {
  const std::vector<Draw>& in = kPairStarts;
  for (auto _ : state) {
    float sum = 0.0f;
    for (const Draw& d : in) sum += static_cast<float>(d.sample ^ d.dimension);
    benchmark::DoNotOptimize(sum);
  }
  report(state, in.size(), 1);
}
BENCHMARK(BM_Loop)->Iterations(kIterations);

// The camera ray's position in the pixel: dimensions 0 and 1 together.
void BM_PixelPosition(benchmark::State& state) {
  const std::vector<Draw>& in = kPairStarts;
  for (auto _ : state) {
    float sum = 0.0f;
    for (const Draw& d : in) {
      const PixelSample2D p = sobol_owen_pixel_sample(d.pixel, d.sample ^ d.dimension);
      sum += p.x + p.y;
    }
    benchmark::DoNotOptimize(sum);
  }
  report(state, in.size(), 2);
}
BENCHMARK(BM_PixelPosition)->Iterations(kIterations);

// One padded dimension alone, first (even) or second (odd) of its pair.
template <bool Second>
void BM_SampleDimension(benchmark::State& state) {
  const std::vector<Draw>& in = Second ? kPairSeconds : kPairStarts;
  for (auto _ : state) {
    float sum = 0.0f;
    for (const Draw& d : in) sum += sample_dimension(d.pixel, d.sample, d.dimension);
    benchmark::DoNotOptimize(sum);
  }
  report(state, in.size(), 1);
}
BENCHMARK(BM_SampleDimension<false>)->Name("BM_SampleDimension/first")->Iterations(kIterations);
BENCHMARK(BM_SampleDimension<true>)->Name("BM_SampleDimension/second")->Iterations(kIterations);

// What an integrator does: one PixelSampler per sample, then four 2D draws (dimensions
// 2..9), or eight 1D draws.
template <bool Pairs>
void BM_PixelSampler(benchmark::State& state) {
  const std::vector<Draw>& in = kSamples;
  for (auto _ : state) {
    float sum = 0.0f;
    for (const Draw& d : in) {
      PixelSampler sampler(d.pixel, d.sample);
      for (int k = 0; k < (Pairs ? 4 : 8); ++k) {
        if constexpr (Pairs) {
          const PixelSample2D p = sampler.get2d();
          sum += p.x + p.y;
        } else {
          sum += sampler.get1d();
        }
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  report(state, in.size(), 8);
}
BENCHMARK(BM_PixelSampler<false>)->Name("BM_PixelSampler/get1d")->Iterations(kIterations);
BENCHMARK(BM_PixelSampler<true>)->Name("BM_PixelSampler/get2d")->Iterations(kIterations);

}  // namespace
}  // namespace prism

BENCHMARK_MAIN();
