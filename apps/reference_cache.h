// The on-disk cache of `prism compare`'s reference renders. A reference at 256 spp costs far
// more than the renders it judges, and it depends only on the scene and the settings that
// change its pixels, so it is rendered once and found again by a hash of those.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "apps/command_line.h"
#include "integrators/parameters.h"
#include "renderer/image/image.h"
#include "renderer/integrator.h"
#include "renderer/scene_description.h"

namespace prism {

struct ReferenceKey {
  nlohmann::json settings;  // everything hashed, kept in the EXR to check a hit against
  std::string hash;         // 32 hex digits
};

// The hash of the scene file's bytes (and of the external buffers and images it names), the
// program version and every setting that changes the image: integrator and its parameters,
// spp, resolution, the camera used, working space, background, sphere mode. Not the thread
// count: the image is bit-identical whatever it is.
ReferenceKey reference_key(const std::string& scene_path, const RenderJob& job,
                           const RenderSettings& film, const ParameterValues& parameters,
                           const CameraDescription& camera, int camera_index);

// $XDG_CACHE_HOME/prism/references, or ~/.cache/prism/references. Throws UsageError when
// neither XDG_CACHE_HOME nor HOME is set.
std::string reference_cache_dir();

// An image with what prism recorded in it when it rendered it (zero when it did not).
struct RecordedRender {
  Image image;
  int spp = 0;
  double seconds = 0.0;  // how long the render took when it was made
  RayCounters rays;
};

// Reads an EXR and its prism:spp, prism:renderSeconds and prism:rays* attributes. Throws
// std::runtime_error("<path>: <reason>") when it cannot be read.
RecordedRender read_recorded_render(const std::string& path);

// The render stored under `key` in `dir`, or nothing when there is none (or a file whose
// recorded settings differ, which is then rendered again and replaced).
std::optional<RecordedRender> find_cached_reference(const std::string& dir,
                                                    const ReferenceKey& key);

// The path a reference with `key` is stored at; write it with write_exr and
// reference_metadata_entry so find_cached_reference recognises it.
std::string cached_reference_path(const std::string& dir, const ReferenceKey& key);
std::pair<std::string, std::string> reference_metadata_entry(const ReferenceKey& key);

// What a pass over the cache removed and left.
struct CacheSweep {
  int removed = 0;
  uint64_t removed_bytes = 0;
  int kept = 0;
  uint64_t kept_bytes = 0;
};

// The cache is bounded (a reference of a large frame is tens of MiB and every new setting
// adds one): removes the least recently used references (by modification time, which a
// cache hit renews) until those left hold at most `max_bytes`, never `keep` (the one just
// written). Only files named as the cache names them (32 hex digits + ".exr") are touched.
CacheSweep bound_reference_cache(const std::string& dir, uint64_t max_bytes,
                                 const std::string& keep = {});
// Removes every cached reference (`prism compare --clear-cache`).
inline CacheSweep clear_reference_cache(const std::string& dir) {
  return bound_reference_cache(dir, 0);
}
// The bound used when --cache-limit is not given.
inline constexpr double kDefaultCacheLimitGib = 2.0;

}  // namespace prism
