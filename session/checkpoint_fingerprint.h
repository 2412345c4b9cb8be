// What a checkpoint is tied to: the job's settings, the scene file's bytes and the Prism
// version, hashed. A checkpoint whose fingerprint differs was made for another render and
// must not be continued. Kept in one function so that a shared job fingerprint can replace it.
#pragma once

#include <string>

#include "session/job.h"

namespace prism {

// 32 hex digits of XXH3-128 over a canonical text of `request` and `job` (every field that
// can change the image, floats exactly), the bytes of request.path and kVersion. Throws
// std::runtime_error when the scene file cannot be read. Buffers and images the scene
// names in other files are not hashed.
std::string checkpoint_fingerprint(const SceneRequest& request, const RenderJob& job);

}  // namespace prism
