#include "simulation/clip_preview.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "renderer/temporary_files.h"
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

void write_contact_sheet(const std::vector<fs::path>& frames, const fs::path& output, int tiles,
                         int columns) {
  if (frames.empty()) throw std::runtime_error(output.string() + ": no frames to show");
  const int count = std::min<int>(tiles, static_cast<int>(frames.size()));
  std::vector<OIIO::ImageBuf> images;
  for (int k = 0; k < count; ++k) {
    const size_t frame =
        count == 1 ? 0
                   : static_cast<size_t>(k) * (frames.size() - 1) / static_cast<size_t>(count - 1);
    OIIO::ImageBuf image(frames[frame].string());
    if (!image.read(0, 0, true, OIIO::TypeDesc::UINT8))
      throw std::runtime_error(frames[frame].string() + ": cannot be read: " + image.geterror());
    images.push_back(std::move(image));
  }
  const int w = images[0].spec().width, h = images[0].spec().height;
  const int channels = std::min(images[0].nchannels(), 3);
  const int cols = std::min(columns, count);
  const int rows = (count + cols - 1) / cols;
  constexpr int kGap = 4;
  OIIO::ImageSpec spec(cols * w + (cols - 1) * kGap, rows * h + (rows - 1) * kGap, channels,
                       OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf sheet(spec);
  OIIO::ImageBufAlgo::zero(sheet);
  for (int k = 0; k < count; ++k) {
    if (images[k].spec().width != w || images[k].spec().height != h)
      throw std::runtime_error(frames[static_cast<size_t>(k)].string() +
                               ": not the size of the first frame");
    OIIO::ImageBufAlgo::paste(sheet, (k % cols) * (w + kGap), (k / cols) * (h + kGap), 0, 0,
                              images[k], OIIO::ROI(0, w, 0, h, 0, 1, 0, channels));
  }
  write_atomically(output, [&](const fs::path& temporary) -> std::string {
    return sheet.write(temporary.string(), OIIO::TypeUnknown, "png") ? "" : sheet.geterror();
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
