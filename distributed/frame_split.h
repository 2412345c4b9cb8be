// One frame's tiles shared by the ranks of a world: every rank renders the tiles it claims
// from a shared counter (dynamic balancing: a rank that finishes early claims more), then
// sends their pixels to rank 0 once, which places them into its image. Each pixel's samples
// depend only on (pixel, sample), so rank 0's image is bit-identical to a single process's
// whatever the number of ranks and whoever rendered which tile (renderer/render.cpp).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "distributed/world.h"
#include "renderer/image/image.h"
#include "renderer/integrator.h"
#include "renderer/render.h"

namespace prism::distributed {

// What splitting a frame cost, for --verbose and docs/batch.md. Rank 0 has every figure,
// the other ranks the first three.
struct FrameSplitStats {
  int rank = 0, ranks = 1;
  uint64_t tiles_here = 0;               // tiles this rank rendered
  std::vector<uint64_t> tiles_per_rank;  // rank 0: tiles each rank rendered
  uint64_t tiles_received = 0;           // rank 0: tiles the other ranks sent
  uint64_t bytes_received = 0;           // rank 0: their bytes, tile indices included
  // Rank 0: from its own last tile until every rank had finished theirs.
  double wait_seconds = 0.0;
  // Rank 0: moving the other ranks' tiles to it and placing them into its image.
  double gather_seconds = 0.0;
  // What carries the ranks' messages (World::transport).
  std::string transport;
};

class FrameSplit {
 public:
  // Collective: every rank makes one per frame, with the same film.
  FrameSplit(const World& world, const RenderSettings& film);
  FrameSplit(const FrameSplit&) = delete;
  FrameSplit& operator=(const FrameSplit&) = delete;

  // For RenderCallbacks::claim_tile; thread-safe.
  std::optional<size_t> claim();
  // Tiles handed out so far to every rank, as far as this rank has seen (a progress bar's).
  size_t claimed_anywhere() const { return claimed_anywhere_; }
  size_t tiles() const { return tiles_.size(); }

  // Collective, once, after this rank's render into `image` with `result`: rank 0's image
  // receives every other rank's tiles and its result becomes the frame's (rays summed over
  // ranks, cancelled if any rank was, seconds its own wall until the image was whole).
  FrameSplitStats gather(Image* image, RenderResult* result);

 private:
  const World& world_;
  std::vector<TileRect> tiles_;
  std::unique_ptr<SharedCounter> counter_;
  std::mutex claimed_mutex_;
  std::vector<uint32_t> claimed_;  // by this rank, in claim order
  std::atomic<size_t> claimed_anywhere_{0};
};

}  // namespace prism::distributed
