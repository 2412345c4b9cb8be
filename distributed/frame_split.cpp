#include "distributed/frame_split.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

namespace prism::distributed {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

size_t tile_floats(const TileRect& t) {
  return static_cast<size_t>(t.x1 - t.x0) * static_cast<size_t>(t.y1 - t.y0) * 4;
}

// A tile on the wire: its index (uint32) then its RGBA floats, row by row.
void append_tile(const Image& image, const TileRect& t, uint32_t index,
                 std::vector<std::byte>* out) {
  const size_t row_bytes = static_cast<size_t>(t.x1 - t.x0) * 4 * sizeof(float);
  size_t at = out->size();
  out->resize(at + sizeof index + static_cast<size_t>(t.y1 - t.y0) * row_bytes);
  std::memcpy(out->data() + at, &index, sizeof index);
  at += sizeof index;
  for (int y = t.y0; y < t.y1; ++y, at += row_bytes)
    std::memcpy(out->data() + at, image.pixel(t.x0, y), row_bytes);
}

// Places every tile of `bytes` into `image`; returns how many there were.
uint64_t place_tiles(const std::vector<TileRect>& tiles, const std::vector<std::byte>& bytes,
                     Image* image) {
  uint64_t count = 0;
  size_t at = 0;
  while (at < bytes.size()) {
    uint32_t index = 0;
    if (bytes.size() - at < sizeof index) throw std::runtime_error("gather: truncated tile");
    std::memcpy(&index, bytes.data() + at, sizeof index);
    at += sizeof index;
    if (index >= tiles.size()) throw std::runtime_error("gather: no tile " + std::to_string(index));
    const TileRect& t = tiles[index];
    const size_t row_bytes = static_cast<size_t>(t.x1 - t.x0) * 4 * sizeof(float);
    if (bytes.size() - at < tile_floats(t) * sizeof(float))
      throw std::runtime_error("gather: truncated tile");
    for (int y = t.y0; y < t.y1; ++y, at += row_bytes)
      std::memcpy(image->pixel(t.x0, y), bytes.data() + at, row_bytes);
    ++count;
  }
  return count;
}

}  // namespace

FrameSplit::FrameSplit(const World& world, const RenderSettings& film)
    : world_(world), tiles_(make_tiles(film)), counter_(std::make_unique<SharedCounter>(world)) {}

std::optional<size_t> FrameSplit::claim() {
  const uint64_t n = counter_->next();
  size_t seen = claimed_anywhere_;
  const size_t now = static_cast<size_t>(std::min<uint64_t>(n + 1, tiles_.size()));
  while (seen < now && !claimed_anywhere_.compare_exchange_weak(seen, now)) {
  }
  if (n >= tiles_.size()) return std::nullopt;
  const std::lock_guard<std::mutex> lock(claimed_mutex_);
  claimed_.push_back(static_cast<uint32_t>(n));
  return static_cast<size_t>(n);
}

FrameSplitStats FrameSplit::gather(Image* image, RenderResult* result) {
  FrameSplitStats stats;
  stats.rank = world_.rank();
  stats.ranks = world_.size();
  stats.transport = world_.transport();
  stats.tiles_here = claimed_.size();
  const auto wait_start = Clock::now();
  // Every rank has stopped claiming once all are here, so the window can go.
  world_.barrier();
  counter_.reset();
  stats.wait_seconds = seconds_since(wait_start);

  const auto gather_start = Clock::now();
  std::vector<std::byte> mine;
  if (!world_.root()) {
    size_t bytes = 0;
    for (uint32_t index : claimed_)
      bytes += sizeof index + tile_floats(tiles_[index]) * sizeof(float);
    mine.reserve(bytes);
    for (uint32_t index : claimed_) append_tile(*image, tiles_[index], index, &mine);
  }
  const std::vector<std::vector<std::byte>> received = gather_at_root(world_, mine);
  enum : size_t { kRays = 0, kDiscarded = kRayKindCount, kCancelled, kCount };
  uint64_t sums[kCount] = {};
  for (size_t k = 0; k < kRayKindCount; ++k) sums[kRays + k] = result->rays.rays[k];
  sums[kDiscarded] = result->rays.discarded_samples;
  sums[kCancelled] = result->cancelled ? 1 : 0;
  sum_at_root(world_, sums);
  if (world_.root()) {
    stats.tiles_per_rank.assign(received.size(), 0);
    stats.tiles_per_rank[0] = claimed_.size();
    for (size_t r = 1; r < received.size(); ++r) {
      stats.tiles_per_rank[r] = place_tiles(tiles_, received[r], image);
      stats.tiles_received += stats.tiles_per_rank[r];
      stats.bytes_received += received[r].size();
    }
    for (size_t k = 0; k < kRayKindCount; ++k) result->rays.rays[k] = sums[kRays + k];
    result->rays.discarded_samples = sums[kDiscarded];
    result->cancelled = sums[kCancelled] > 0;
  }
  stats.gather_seconds = seconds_since(gather_start);
  result->seconds += stats.wait_seconds + stats.gather_seconds;
  return stats;
}

}  // namespace prism::distributed
