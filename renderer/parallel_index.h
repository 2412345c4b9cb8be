// Loops over the indices 0..count-1 of one big array, split over the calling arena's threads.
// The body of each must depend on its own index only (or sum integer counts), so the result is
// the serial loop's bit for bit: a big mesh is usually one primitive, which would otherwise be
// read, checked and prepared on one thread while the others wait.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace prism {

// Below this many elements a loop is not worth splitting.
inline constexpr size_t kParallelIndexGrain = size_t(1) << 16;

template <typename Body>
void for_each_index(size_t count, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kParallelIndexGrain),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) body(i);
                    });
}

// How many indices `counted` is true for; it is called once for each index.
template <typename Predicate>
size_t count_if_index(size_t count, const Predicate& counted) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, count, kParallelIndexGrain), size_t(0),
      [&](const tbb::blocked_range<size_t>& r, size_t n) {
        for (size_t i = r.begin(); i != r.end(); ++i) n += counted(i) ? 1 : 0;
        return n;
      },
      std::plus<size_t>());
}

// The smallest index `bad` is true for, or `count` when there is none: the error a serial
// check would report first, whichever thread finds it.
template <typename Predicate>
size_t first_index_where(size_t count, const Predicate& bad) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, count, kParallelIndexGrain), count,
      [&](const tbb::blocked_range<size_t>& r, size_t first) {
        for (size_t i = r.begin(); i != r.end() && i < first; ++i)
          if (bad(i)) return i;
        return first;
      },
      [](size_t a, size_t b) { return std::min(a, b); });
}

}  // namespace prism
