// What identifies a render's result, so that a batch can tell an output that is up to date
// from one that must be rendered again: the job's settings (as canonical text), the contents
// of every file the scene was read from, and the build of Prism. Hashed with XXH3-128, stable
// across processes and machines (std::hash is neither).
#pragma once

#include <string>
#include <vector>

#include "renderer/image/image_output.h"
#include "session/job.h"

namespace prism {

struct InputFile {
  std::string path;
  std::string content_hash;  // content_hash(path) when fingerprinted
};

// Every setting of a render that can change its output file, one "key=value" per line in a
// fixed order: the scene (its absolute path and selection), the job and the pixel type.
// Thread counts, tile sizes, budgets and output names are left out: they never change a
// pixel.
std::string canonical_settings(const SceneRequest& scene, const RenderJob& job,
                               ExrPixelType pixel_type);

// The environment a job asks for as one line of canonical text: the map's absolute path and
// the hash of its contents (or "unreadable": the render then reports why), its rotation,
// intensity and whether it is hidden. A map's contents are part of what a render depends on.
std::string environment_settings(const EnvironmentRequest& environment);

// XXH3-128 of `bytes`, as 32 lowercase hex digits.
std::string hash_text(const std::string& bytes);

// XXH3-128 of the file's contents, read in blocks; throws std::runtime_error naming the file
// when it cannot be read.
std::string content_hash(const std::string& path);

// The inputs of a scene: each of `files` (SceneDescription::source_files) with its hash.
std::vector<InputFile> hash_inputs(const std::vector<std::string>& files);

// The fingerprint of a job: its settings, its inputs (in order) and this build.
std::string job_fingerprint(const std::string& settings, const std::vector<InputFile>& inputs);

// The inputs as one line of text, "HASH PATH" separated by newlines, and back (false for
// anything else); an output records them so a later run can re-hash just those files.
std::string format_inputs(const std::vector<InputFile>& inputs);
bool parse_inputs(const std::string& text, std::vector<InputFile>* inputs);

}  // namespace prism
