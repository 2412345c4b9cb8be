// OpenEXR files read and written through the OpenEXR library itself, not OpenImageIO: EXR
// is the master every render writes and every comparison reads, and OpenEXR is a small
// library, where OpenImageIO brings some 260 shared libraries into the process at start-up
// (docs/images.md). Writing compresses in parallel on OpenEXR's own thread pool.
//
// Both directions treat the file as untrusted: a reader checks the data window before it
// allocates, and every failure is one std::runtime_error "<path>: <reason>" on one line.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "renderer/enum_names.h"
#include "renderer/image/image.h"

namespace prism {

enum class ExrPixelType : uint8_t { half, float32 };

// Lossless compressions only: an EXR master keeps every bit of the render. The default is
// chosen by measurement (docs/benchmarks.md, "EXR writing").
enum class ExrCompression : uint8_t { none, rle, zips, zip, piz };
inline constexpr EnumName<ExrCompression> kExrCompressionNames[] = {{ExrCompression::none, "none"},
                                                                    {ExrCompression::rle, "rle"},
                                                                    {ExrCompression::zips, "zips"},
                                                                    {ExrCompression::zip, "zip"},
                                                                    {ExrCompression::piz, "piz"}};
constexpr std::span<const EnumName<ExrCompression>> enum_names(ExrCompression) {
  return kExrCompressionNames;
}

// Measured on this machine (docs/benchmarks.md, "EXR writing").
inline constexpr ExrCompression kDefaultExrCompression = ExrCompression::piz;
inline constexpr int kDefaultZipLevel = 4;

// What an EXR's header carries besides the pixels.
struct ExrHeader {
  // The pixels stored, inside the display window (the whole image): a render of a region
  // (RenderSettings::region) stores only it. Empty: the whole image.
  std::optional<TileRect> data_window;
  std::optional<std::array<float, 8>> chromaticities;  // red, green, blue, white (x, y)
  std::optional<std::array<float, 16>> world_to_camera, world_to_ndc;  // row-major
  std::vector<std::pair<std::string, std::string>> strings;
  std::vector<std::pair<std::string, int>> ints;
  std::vector<std::pair<std::string, float>> floats;

  std::optional<std::string> string_value(const std::string& name) const {
    return find(strings, name);
  }
  std::optional<int> int_value(const std::string& name) const { return find(ints, name); }
  std::optional<float> float_value(const std::string& name) const { return find(floats, name); }

 private:
  template <typename T>
  static std::optional<T> find(const std::vector<std::pair<std::string, T>>& list,
                               const std::string& name) {
    for (const auto& [key, value] : list)
      if (key == name) return value;
    return std::nullopt;
  }
};

struct ExrWriteOptions {
  ExrPixelType pixel_type = ExrPixelType::float32;
  ExrCompression compression = kDefaultExrCompression;
  int threads = 0;  // threads compressing: 1 = the calling thread alone, 0 = one per core
  // zlib's level for zip and zips, 1 (fastest) to 9 (smallest).
  int zip_level = kDefaultZipLevel;
};

// Writes RGBA `image` to `path` itself (callers that need atomic replacement write to a
// temporary name and rename it: image_output.h).
void write_exr_file(const std::string& path, const Image& image, const ExrHeader& header,
                    const ExrWriteOptions& options);

// True when the file starts with OpenEXR's magic number.
bool is_exr_file(const std::string& path);

// The data window of part 0 as RGBA floats: channels R, G, B by name, else the first
// non-alpha channels (one channel is grey); A, or 1 without it. A data window of more than
// `max_pixels` is refused before anything is allocated for it.
inline constexpr int64_t kMaxReadPixels = int64_t{1} << 30;
Image read_exr_file(const std::string& path, int64_t max_pixels = kMaxReadPixels);

// The header's string, int and float attributes (chromaticities and matrices are not read
// back), or std::nullopt when the file cannot be read as an EXR. Reads the header only.
std::optional<ExrHeader> read_exr_header(const std::string& path);
// The string attribute `name`, or std::nullopt when the file cannot be read or lacks it.
std::optional<std::string> read_exr_string(const std::string& path, const std::string& name);

}  // namespace prism
