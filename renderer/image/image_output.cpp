#include "renderer/image/image_output.h"

#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iterator>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "renderer/image/oiio_module.h"
#include "renderer/image/png_file.h"
#include "renderer/temporary_files.h"
#include "renderer/version.h"

namespace fs = std::filesystem;

namespace prism {

namespace {

std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
  throw std::runtime_error(one_line(path + ": " + reason));
}

// A zero-sized image is a caller bug (a 0-pixel resolution should have been rejected on the
// command line); refusing it before touching the file system keeps any old output intact.
void check_image(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) {
    fail(path, "cannot write an empty image (" + std::to_string(image.width) + " x " +
                   std::to_string(image.height) + ")");
  }
  const std::size_t expected = static_cast<std::size_t>(image.width) * image.height * 4;
  if (image.rgba.size() != expected) {
    fail(path, "image has " + std::to_string(image.rgba.size()) + " floats, expected " +
                   std::to_string(expected));
  }
}

// Temporary files being written, for the signal handler: fixed storage, because a handler
// may only call async-signal-safe functions (no allocation, no locks); unlink(2) is one.
constexpr int kTempSlots = 8;
char g_temp_paths[kTempSlots][PATH_MAX];
std::atomic<bool> g_temp_in_use[kTempSlots];
constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
struct sigaction g_previous[std::size(kCleanupSignals)];

extern "C" void remove_temp_files_and_reraise(int sig) {
  const int saved_errno = errno;
  for (int i = 0; i < kTempSlots; ++i)
    if (g_temp_in_use[i].load()) ::unlink(g_temp_paths[i]);
  for (std::size_t i = 0; i < std::size(kCleanupSignals); ++i) {
    if (kCleanupSignals[i] != sig) continue;
    const struct sigaction& previous = g_previous[i];
    if (!(previous.sa_flags & SA_SIGINFO) && previous.sa_handler != SIG_DFL &&
        previous.sa_handler != SIG_IGN) {
      errno = saved_errno;
      previous.sa_handler(sig);  // the program's own handler decides what happens next
      return;
    }
  }
  // The default action (termination), as if the handler had never been installed.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
  errno = saved_errno;
}

// Installed once, on the first write; signals the process ignores stay ignored.
void install_signal_cleanup() {
  static const bool installed = [] {
    for (std::size_t i = 0; i < std::size(kCleanupSignals); ++i) {
      struct sigaction action {};
      action.sa_handler = remove_temp_files_and_reraise;
      sigemptyset(&action.sa_mask);
      if (::sigaction(kCleanupSignals[i], nullptr, &g_previous[i]) != 0) continue;
      if (!(g_previous[i].sa_flags & SA_SIGINFO) && g_previous[i].sa_handler == SIG_IGN) continue;
      ::sigaction(kCleanupSignals[i], &action, nullptr);
    }
    return true;
  }();
  (void)installed;
}

// The temporary file lives beside the target so the final rename stays on one file system
// (and is therefore atomic). It is hidden, unique per process and call, and removed when the
// write fails, when a termination signal arrives, or by the next write after a crash.
class TempFile {
 public:
  explicit TempFile(const std::string& target) {
    const fs::path target_path(target);
    fs::path dir = target_path.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail(target, "directory '" + dir.string() + "' does not exist");
    remove_stale_temporaries(dir, target_path);
    path_ = (dir / temporary_name(target_path)).string();
    install_signal_cleanup();
    if (path_.size() < PATH_MAX) {
      for (int i = 0; i < kTempSlots && slot_ < 0; ++i) {
        bool expected = false;
        if (!claimed_[i].compare_exchange_strong(expected, true)) continue;
        std::memcpy(g_temp_paths[i], path_.c_str(), path_.size() + 1);
        g_temp_in_use[i].store(true);  // after the copy: the handler sees a whole path
        slot_ = i;
      }
    }
  }
  ~TempFile() {
    release();
    if (!committed_) {
      std::error_code ec;
      fs::remove(path_, ec);
    }
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::string& path() const { return path_; }

  void commit(const std::string& target) {
    std::error_code ec;
    fs::rename(path_, target, ec);
    if (ec) fail(target, "cannot move the finished file into place: " + ec.message());
    committed_ = true;
    release();
  }

 private:
  void release() {
    if (slot_ < 0) return;
    g_temp_in_use[slot_].store(false);
    claimed_[slot_].store(false);
    slot_ = -1;
  }

  static inline std::atomic<bool> claimed_[kTempSlots];
  std::string path_;
  int slot_ = -1;
  bool committed_ = false;
};

// Writes `path` through a temporary beside it, renamed into place; a failure is reported
// under the target's name, the temporary being an implementation detail.
template <typename Write>
void write_atomically(const std::string& path, const Write& write) {
  TempFile temp(path);
  try {
    write(temp.path());
  } catch (const std::runtime_error& e) {
    std::string reason = e.what();
    if (reason.rfind(temp.path() + ": ", 0) == 0) reason.erase(0, temp.path().size() + 2);
    fail(path, reason);
  }
  temp.commit(path);
}

std::string capture_date() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char text[32];
  std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &local);
  return text;
}

std::array<float, 16> to_float_matrix(const M44d& m) {
  std::array<float, 16> out{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = static_cast<float>(m[r][c]);
  }
  return out;
}

}  // namespace

void write_exr(const std::string& path, const Image& image, const ColourPipeline& colour,
               const RenderMetadata& metadata, const ExrWriteOptions& options) {
  check_image(path, image);
  ExrHeader header;
  header.data_window = metadata.region;
  header.chromaticities = colour.chromaticities();
  header.world_to_camera = to_float_matrix(metadata.world_to_camera);
  header.world_to_ndc = to_float_matrix(metadata.world_to_ndc);
  // Named as OpenImageIO and earlier Prism wrote them: "Software", and the standard capDate
  // (local time, "YYYY:MM:DD hh:mm:ss"), which OpenImageIO shows as DateTime.
  header.strings = {{"Software", std::string("prism ") + kVersion},
                    {"capDate", capture_date()},
                    {"prism:integrator", metadata.integrator},
                    {"prism:scene", metadata.scene_path},
                    {"prism:workingSpace", to_string(colour.working_space())},
                    {"prism:ocioConfig", colour.config_source()}};
  for (const auto& [key, value] : metadata.extra)
    header.strings.emplace_back("prism:" + key, value);
  header.ints = {{"prism:spp", metadata.spp}};
  header.floats = {{"prism:renderSeconds", static_cast<float>(metadata.render_seconds)}};

  write_atomically(path, [&](const std::string& temporary) {
    write_exr_file(temporary, image, header, options);
  });
}

void write_png_preview(const std::string& path, const Image& image, const ColourPipeline& colour,
                       const DisplayOptions& options) {
  check_image(path, image);
  write_display_png(path, colour.working_to_display(image, options));
}

void write_display_png(const std::string& path, const Image& display) {
  check_image(path, display);
  const Image& image = display;

  // RGB only: the render's colour is premultiplied by alpha, i.e. already "over black", and a
  // preview that viewers draw over a checkerboard would misrepresent it.
  const std::size_t pixel_count = static_cast<std::size_t>(image.width) * image.height;
  std::vector<std::uint8_t> bytes(pixel_count * 3);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    for (int c = 0; c < 3; ++c) {
      bytes[i * 3 + c] = static_cast<std::uint8_t>(std::lround(display.rgba[i * 4 + c] * 255.0f));
    }
  }
  write_atomically(path, [&](const std::string& temporary) {
    write_png_file(temporary, image.width, image.height, bytes.data(),
                   std::string("prism ") + kVersion);
  });
}

bool image_format_for_path(const std::string& path, ImageFormat* format) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static const std::pair<const char*, ImageFormat> kExtensions[] = {
      {".exr", ImageFormat::exr},  {".tif", ImageFormat::tiff}, {".tiff", ImageFormat::tiff},
      {".hdr", ImageFormat::hdr},  {".png", ImageFormat::png},  {".jpg", ImageFormat::jpeg},
      {".jpeg", ImageFormat::jpeg}};
  for (const auto& [extension, f] : kExtensions)
    if (ext == extension) {
      *format = f;
      return true;
    }
  return false;
}

void write_image(const std::string& path, ImageFormat format, const Image& image,
                 const ColourPipeline& colour, const DisplayOptions& display) {
  if (format == ImageFormat::png) return write_png_preview(path, image, colour, display);
  if (format == ImageFormat::exr) throw std::logic_error("write_image: EXR goes through write_exr");
  check_image(path, image);
  // Loaded before the temporary exists, so that a missing module leaves nothing behind.
  const OiioModule& oiio = oiio_module(path);
  const Image pixels = display_referred(format) ? colour.working_to_display(image, display) : image;
  const char* name = format == ImageFormat::tiff  ? "tiff"
                     : format == ImageFormat::hdr ? "hdr"
                                                  : "jpeg";
  write_atomically(
      path, [&](const std::string& temporary) { oiio.write_image(temporary, pixels, name); });
}

}  // namespace prism
