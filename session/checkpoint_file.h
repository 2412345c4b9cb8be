// A render's checkpoint on disk: a RenderState (renderer/render_state.h) and the fingerprint
// of the job it belongs to, written atomically and read back as untrusted input.
//
// The format (version 1), little-endian throughout:
//   "PRISMCKP"                       8 bytes of magic
//   u32 format version               1
//   u32 fingerprint length, bytes    at most kMaxCheckpointFingerprint
//   i32 width, height, spp, min_spp; f32 target error; u8 adaptive: 0 uniform, else 1 + the
//   error goal (1 pixel, 2 image)
//   i32 samples done, rounds; f64 seconds
//   u32 ray kinds (kRayKindCount), then a u64 per kind and u64 discarded samples
//   u64 pixels (width x height)
//   per pixel: the sums (f32 x 3 radiance, u32 hits, u32 kept, f32 x 3 radiance squared)
//   adaptive only, per pixel each: the first-half sums (as above), u8 active, u32 samples,
//   f32 error
//   16 bytes: XXH3-128 of everything before them (low 64 bits first)
// Every count is checked against the film the caller expects and the file's exact size
// before anything is allocated, and the hash catches any damage the checks cannot, so a
// file that reads back is the state that was written.
#pragma once

#include <optional>
#include <string>

#include "renderer/integrator.h"
#include "renderer/render_state.h"

namespace prism {

inline constexpr size_t kMaxCheckpointFingerprint = 1024;

// Writes `state` and `fingerprint` to `path` through a temporary in the same folder, flushed
// to disk (fsync) before it is renamed into place: `path` holds the old checkpoint or the
// new one, never a mixture. Throws std::runtime_error("<path>: <reason>").
void write_checkpoint(const std::string& path, const RenderState& state,
                      const std::string& fingerprint);

struct CheckpointRead {
  std::optional<RenderState> state;
  std::string reason;  // when there is no state: why, one line ("written for another job")
};

// The state in `path` if it was written for `fingerprint` and continues a render of `film`
// (RenderState::mismatch); otherwise none and the reason. Never throws for the file's
// content; a caller that gets no state renders from the start.
CheckpointRead read_checkpoint(const std::string& path, const RenderSettings& film,
                               const std::string& fingerprint);

// Where `prism render -o OUTPUT` keeps its checkpoint: OUTPUT.checkpoint.
inline std::string checkpoint_path(const std::string& output) {
  return output + ".checkpoint";
}

}  // namespace prism
