// Writes a clip's file (a frame scene, the job file, a preview) the way the renderer writes
// its images: to a hidden temporary beside the target (renderer/temporary_files.h), renamed
// into place once complete, so a killed run leaves each file absent, old or whole.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace prism {

// `write(temporary)` fills the temporary and returns "" or why it failed; then the rename.
// Throws std::runtime_error "TARGET: cannot be written: WHY", leaving no temporary behind.
void write_atomically(const std::filesystem::path& target,
                      const std::function<std::string(const std::filesystem::path&)>& write);

// The same for text.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace prism
