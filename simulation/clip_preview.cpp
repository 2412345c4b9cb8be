#include "simulation/clip_preview.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <cmath>
#include <iterator>

#include "renderer/image/png_file.h"
#include "renderer/temporary_files.h"
#include "scene_io/image_decoders.h"
#include "simulation/atomic_write.h"

extern char** environ;

namespace prism {

namespace fs = std::filesystem;

std::vector<fs::path> rendered_previews(const fs::path& png_dir) {
  std::vector<fs::path> frames;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(png_dir, error)) {
    const std::string name = entry.path().filename().string();
    // Only finished previews: the batch's temporaries are hidden (".frame_...").
    if (entry.is_regular_file() && name.rfind("frame_", 0) == 0 &&
        entry.path().extension() == ".png")
      frames.push_back(entry.path());
  }
  // Frame names are zero-padded to one width, so name order is frame order.
  std::sort(frames.begin(), frames.end());
  return frames;
}

namespace {

// A rendered preview (an 8-bit PNG Prism wrote) as 8-bit RGB, through the same libpng decoder
// that reads glTF textures.
struct Frame {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

Frame read_frame(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in),
                                         std::istreambuf_iterator<char>()};
  gltf_detail::ImageHeader header;
  std::string why = gltf_detail::read_png_header(bytes.data(), bytes.size(), &header);
  std::vector<uint16_t> samples;  // as wide as a 16-bit image needs; an 8-bit one uses bytes
  if (why.empty()) {
    samples.resize(size_t(header.width) * size_t(header.height) * size_t(header.channels));
    why = gltf_detail::decode_png(bytes.data(), bytes.size(), header,
                                  reinterpret_cast<unsigned char*>(samples.data()));
  }
  if (!why.empty()) throw std::runtime_error(path.string() + ": cannot be read: " + why);
  Frame frame{header.width, header.height, {}};
  frame.rgb.resize(size_t(header.width) * size_t(header.height) * 3);
  const size_t channels = size_t(header.channels);
  const auto* codes = reinterpret_cast<const uint8_t*>(samples.data());
  for (size_t p = 0; p < size_t(header.width) * size_t(header.height); ++p)
    for (size_t c = 0; c < 3; ++c) {
      // Grey (1 or 2 channels) fills all three; alpha is left out.
      const size_t i = p * channels + (channels < 3 ? 0 : c);
      frame.rgb[p * 3 + c] =
          header.bits == 8 ? codes[i]
                           : static_cast<uint8_t>(std::lround(samples[i] * (255.0 / 65535.0)));
    }
  return frame;
}

}  // namespace

void write_contact_sheet(const std::vector<fs::path>& frames, const fs::path& output, int tiles,
                         int columns) {
  if (frames.empty()) throw std::runtime_error(output.string() + ": no frames to show");
  const int count = std::min<int>(tiles, static_cast<int>(frames.size()));
  std::vector<Frame> images;
  for (int k = 0; k < count; ++k) {
    const size_t frame =
        count == 1 ? 0
                   : static_cast<size_t>(k) * (frames.size() - 1) / static_cast<size_t>(count - 1);
    images.push_back(read_frame(frames[frame]));
    if (images.back().width != images[0].width || images.back().height != images[0].height)
      throw std::runtime_error(frames[frame].string() + ": not the size of the first frame");
  }
  const int w = images[0].width, h = images[0].height;
  const int cols = std::min(columns, count);
  const int rows = (count + cols - 1) / cols;
  constexpr int kGap = 4;
  const int sheet_w = cols * w + (cols - 1) * kGap, sheet_h = rows * h + (rows - 1) * kGap;
  std::vector<uint8_t> sheet(size_t(sheet_w) * size_t(sheet_h) * 3, 0);
  for (int k = 0; k < count; ++k) {
    const int x0 = (k % cols) * (w + kGap), y0 = (k / cols) * (h + kGap);
    for (int y = 0; y < h; ++y)
      std::copy_n(images[size_t(k)].rgb.begin() + ptrdiff_t(size_t(y) * size_t(w) * 3),
                  size_t(w) * 3,
                  sheet.begin() + ptrdiff_t((size_t(y0 + y) * size_t(sheet_w) + size_t(x0)) * 3));
  }
  write_atomically(output, [&](const fs::path& temporary) -> std::string {
    try {
      write_png_file(temporary.string(), sheet_w, sheet_h, sheet.data(), "prism boids");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  });
}

std::string write_video(const std::vector<fs::path>& frames, const fs::path& output, double fps) {
  if (access(kFfmpeg, X_OK) != 0) return std::string(kFfmpeg) + " is not installed";
  if (frames.empty()) return "no frames";
  // ffmpeg's concat demuxer takes the exact list, so a missing frame in the middle never
  // shifts the numbering of a %04d pattern.
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const fs::path list = dir / temporary_name("frames.txt");
  {
    std::ofstream out(list);
    for (const fs::path& f : frames) {
      out << "file '" << fs::absolute(f).string() << "'\n";
      out << "duration " << 1.0 / fps << "\n";
    }
  }
  const auto encode = [&](const fs::path& temporary) -> std::string {
    const std::string rate = std::to_string(fps);
    std::vector<std::string> args = {kFfmpeg, "-nostdin", "-loglevel", "error", "-y", "-f",
                                     "concat", "-safe", "0", "-i", list.string(), "-r", rate,
                                     "-c:v", "libx264", "-pix_fmt", "yuv420p",
                                     // H.264 in 4:2:0 needs even sizes.
                                     "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-movflags",
                                     "+faststart", "-f", "mp4", temporary.string()};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    int status = 0;
    if (posix_spawn(&pid, kFfmpeg, nullptr, nullptr, argv.data(), environ) != 0)
      return "ffmpeg could not be started";
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      return "ffmpeg failed (status " + std::to_string(status) + ")";
    return "";
  };
  std::string why;
  try {
    write_atomically(output, encode);
  } catch (const std::runtime_error& e) {
    why = e.what();
  }
  std::error_code error;
  fs::remove(list, error);
  return why;
}

}  // namespace prism
