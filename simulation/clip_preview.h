// Previews of a rendered clip for people: a contact sheet of evenly spaced frames and, when
// Debian's ffmpeg is installed, an MP4 of every frame.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace prism {

// The frames (PNG previews) that exist, in frame order.
std::vector<std::filesystem::path> rendered_previews(const std::filesystem::path& png_dir);

// Writes a grid of at most `tiles` frames, evenly spaced over `frames` (first and last
// included), `columns` wide, to `output` (PNG, atomically). Throws std::runtime_error naming
// the file that cannot be read or written.
void write_contact_sheet(const std::vector<std::filesystem::path>& frames,
                         const std::filesystem::path& output, int tiles = 12, int columns = 4);

inline constexpr const char* kFfmpeg = "/usr/bin/ffmpeg";

// Encodes `frames` (consecutive PNGs of one size) to an H.264 MP4 at `fps` through
// kFfmpeg. Returns "" on success, else why not (ffmpeg missing, or its exit status).
std::string write_video(const std::vector<std::filesystem::path>& frames,
                        const std::filesystem::path& output, double fps);

}  // namespace prism
