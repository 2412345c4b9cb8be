#include "renderer/image/exr_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfThreading.h>

#include <Imath/half.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace prism {
namespace {

// A render is at most 32768 wide (session.cpp); anything this large is not an image we
// made or a reference anyone renders against, and reading it would need tens of GiB.

[[noreturn]] void fail(const std::string& path, std::string reason) {
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  std::replace(reason.begin(), reason.end(), '\r', ' ');
  while (!reason.empty() && reason.back() == ' ') reason.pop_back();
  throw std::runtime_error(path + ": " + reason);
}

Imf::Compression to_imf(ExrCompression c) {
  switch (c) {
    case ExrCompression::none:
      return Imf::NO_COMPRESSION;
    case ExrCompression::rle:
      return Imf::RLE_COMPRESSION;
    case ExrCompression::zips:
      return Imf::ZIPS_COMPRESSION;
    case ExrCompression::zip:
      return Imf::ZIP_COMPRESSION;
    case ExrCompression::piz:
      return Imf::PIZ_COMPRESSION;
  }
  return Imf::ZIP_COMPRESSION;
}

Imath::M44f to_matrix(const std::array<float, 16>& m) {
  return Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11],
                     m[12], m[13], m[14], m[15]);
}

// OpenEXR compresses blocks of scan lines on one process-wide pool; its size is changed only
// between writes, under this lock, so a batch's writes never race on it.
std::mutex g_pool_mutex;

// OpenEXR's pool size for `threads` compressing: with a pool of 0 the calling thread
// compresses alone; with n, n pool threads do while the caller waits.
int pool_size(int threads) {
  if (threads == 1) return 0;
  if (threads > 1) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace

void write_exr_file(const std::string& path, const Image& image, const ExrHeader& fields,
                    const ExrWriteOptions& options) {
  const TileRect window = fields.data_window.value_or(TileRect{0, 0, image.width, image.height});
  const Imath::Box2i display({0, 0}, {image.width - 1, image.height - 1});
  Imf::Header header(display, Imath::Box2i({window.x0, window.y0}, {window.x1 - 1, window.y1 - 1}));
  header.compression() = to_imf(options.compression);
  header.zipCompressionLevel() = std::clamp(options.zip_level, 1, 9);
  if (fields.chromaticities) {
    const std::array<float, 8>& c = *fields.chromaticities;
    Imf::addChromaticities(
        header, Imf::Chromaticities({c[0], c[1]}, {c[2], c[3]}, {c[4], c[5]}, {c[6], c[7]}));
  }
  if (fields.world_to_camera) Imf::addWorldToCamera(header, to_matrix(*fields.world_to_camera));
  if (fields.world_to_ndc) Imf::addWorldToNDC(header, to_matrix(*fields.world_to_ndc));
  for (const auto& [name, value] : fields.strings) header.insert(name, Imf::StringAttribute(value));
  for (const auto& [name, value] : fields.ints) header.insert(name, Imf::IntAttribute(value));
  for (const auto& [name, value] : fields.floats) header.insert(name, Imf::FloatAttribute(value));

  const char* names[] = {"R", "G", "B", "A"};
  Imf::FrameBuffer frame;
  // OpenEXR writes a channel only from a slice of its own type: half pixels are rounded
  // here, by Imath's float-to-half (round to nearest even), as OpenImageIO rounded them.
  std::vector<half> halves;
  char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgba.data()));
  size_t value_size = sizeof(float);
  Imf::PixelType type = Imf::FLOAT;
  if (options.pixel_type == ExrPixelType::half) {
    halves.assign(image.rgba.begin(), image.rgba.end());
    base = reinterpret_cast<char*>(halves.data());
    value_size = sizeof(half);
    type = Imf::HALF;
  }
  const size_t x_stride = 4 * value_size;
  const size_t y_stride = x_stride * static_cast<size_t>(image.width);
  // Slices address pixel (x, y) in display-window coordinates, which are the image's own:
  // a data window's pixels are read from where they sit in the whole image.
  for (int c = 0; c < 4; ++c) {
    header.channels().insert(names[c], Imf::Channel(type));
    frame.insert(names[c], Imf::Slice(type, base + c * value_size, x_stride, y_stride));
  }
  try {
    std::lock_guard<std::mutex> lock(g_pool_mutex);
    const int threads = pool_size(options.threads);
    if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
    Imf::OutputFile file(path.c_str(), header, threads);
    file.setFrameBuffer(frame);
    file.writePixels(window.y1 - window.y0);
  } catch (const std::exception& e) {
    fail(path, e.what());
  }
}

bool is_exr_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  return Imf::isOpenExrFile(path.c_str());
}

Image read_exr_file(const std::string& path, int64_t max_pixels) {
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1;
    const int64_t height = int64_t(window.max.y) - window.min.y + 1;
    if (width < 1 || height < 1) fail(path, "has an empty data window");
    if (width * height > max_pixels)
      fail(path, "data window of " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels is larger than Prism reads here (" + std::to_string(max_pixels) +
                     " pixels)");

    const Imf::ChannelList& channels = header.channels();
    std::vector<std::string> colour_names;
    for (const char* name : {"R", "G", "B"})
      if (channels.findChannel(name)) colour_names.push_back(name);
    if (colour_names.size() != 3) {
      // No R, G, B: the first non-alpha channels in the file's (alphabetical) order.
      colour_names.clear();
      for (auto it = channels.begin(); it != channels.end(); ++it)
        if (std::string(it.name()) != "A" && colour_names.size() < 3)
          colour_names.push_back(it.name());
      if (colour_names.empty()) fail(path, "has only an alpha channel");
      // One channel is grey; with two, blue stays zero.
      if (colour_names.size() == 1) colour_names.assign(3, colour_names[0]);
    }

    Image image(static_cast<int>(width), static_cast<int>(height));
    // Slices address pixel (x, y) of the data window at base + x * xs + y * ys, with x and y
    // in the file's coordinates: the base is moved back by the window's corner.
    const size_t xs = 4 * sizeof(float), ys = xs * static_cast<size_t>(width);
    char* origin = reinterpret_cast<char*>(image.rgba.data()) -
                   static_cast<ptrdiff_t>(window.min.x) * static_cast<ptrdiff_t>(xs) -
                   static_cast<ptrdiff_t>(window.min.y) * static_cast<ptrdiff_t>(ys);
    Imf::FrameBuffer frame;
    // A grey channel is read once, into red, and copied below.
    for (size_t i = 0; i < colour_names.size(); ++i) {
      if (i > 0 && colour_names[i] == colour_names[0]) continue;
      frame.insert(colour_names[i],
                   Imf::Slice(Imf::FLOAT, origin + i * sizeof(float), xs, ys, 1, 1, 0.0));
    }
    // Missing alpha reads as the fill value 1.
    frame.insert("A", Imf::Slice(Imf::FLOAT, origin + 3 * sizeof(float), xs, ys, 1, 1, 1.0));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (colour_names.size() == 3 && colour_names[1] == colour_names[0]) {
      for (size_t p = 0; p < image.rgba.size(); p += 4)
        image.rgba[p + 1] = image.rgba[p + 2] = image.rgba[p];
    }
    return image;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    if (what.rfind(path + ": ", 0) == 0) throw;
    fail(path, what);
  } catch (const std::exception& e) {
    fail(path, e.what());
  }
}

std::optional<ExrHeader> read_exr_header(const std::string& path) {
  if (!is_exr_file(path)) return std::nullopt;
  try {
    Imf::InputFile file(path.c_str());
    ExrHeader out;
    const Imf::Header& header = file.header();
    for (auto it = header.begin(); it != header.end(); ++it) {
      const Imf::Attribute& a = it.attribute();
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a))
        out.strings.emplace_back(it.name(), s->value());
      else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a))
        out.ints.emplace_back(it.name(), i->value());
      else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a))
        out.floats.emplace_back(it.name(), f->value());
    }
    return out;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<std::string> read_exr_string(const std::string& path, const std::string& name) {
  const std::optional<ExrHeader> header = read_exr_header(path);
  if (!header) return std::nullopt;
  return header->string_value(name);
}

}  // namespace prism
