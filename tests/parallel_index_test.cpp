// The parallel loops over one big array (renderer/parallel_index.h): every index visited once,
// and the first failing index the serial loop would report, however the range is split.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include <tbb/task_arena.h>

#include "renderer/parallel_index.h"

namespace prism {
namespace {

constexpr size_t kCount = 10 * kParallelIndexGrain + 123;

TEST(ParallelIndex, VisitsEveryIndexOnce) {
  std::vector<std::atomic<int>> visits(kCount);
  tbb::task_arena(2).execute([&] { for_each_index(kCount, [&](size_t i) { ++visits[i]; }); });
  for (size_t i = 0; i < kCount; ++i) ASSERT_EQ(visits[i].load(), 1) << i;
}

TEST(ParallelIndex, CountsWhatThePredicateSelects) {
  const size_t multiples_of_7 = count_if_index(kCount, [](size_t i) { return i % 7 == 0; });
  EXPECT_EQ(multiples_of_7, (kCount + 6) / 7);
  EXPECT_EQ(count_if_index(0, [](size_t) { return true; }), 0u);
}

// Failing indices in several chunks: the smallest wins, on one thread or two, and none
// gives the count.
TEST(ParallelIndex, FindsTheFirstFailingIndex) {
  const std::vector<size_t> bad = {kCount - 1, 7 * kParallelIndexGrain + 5,
                                   3 * kParallelIndexGrain + 1};
  for (int threads : {1, 2}) {
    tbb::task_arena(threads).execute([&] {
      auto failing = [&](size_t from) {
        return first_index_where(kCount, [&](size_t i) {
          for (size_t b : bad)
            if (b >= from && i == b) return true;
          return false;
        });
      };
      EXPECT_EQ(failing(0), 3 * kParallelIndexGrain + 1) << threads;
      EXPECT_EQ(failing(3 * kParallelIndexGrain + 2), 7 * kParallelIndexGrain + 5) << threads;
      EXPECT_EQ(failing(kCount - 1), kCount - 1) << threads;
      EXPECT_EQ(failing(kCount), kCount) << threads;
    });
  }
}

}  // namespace
}  // namespace prism
