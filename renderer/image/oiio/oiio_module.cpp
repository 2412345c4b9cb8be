// The OpenImageIO module (renderer/image/oiio_module.h): the only code linked against
// OpenImageIO, built as libprism_oiio.so and loaded by the first call that needs it.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/image/oiio_module.h"
#include "renderer/version.h"

namespace prism {
namespace {

std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
  throw std::runtime_error(path + ": " + one_line(reason));
}

int find_channel(const OIIO::ImageSpec& spec, const char* name) {
  for (int c = 0; c < spec.nchannels; ++c)
    if (spec.channelnames[static_cast<size_t>(c)] == name) return c;
  return -1;
}

class OiioCanvas final : public RasterCanvas {
 public:
  OiioCanvas(int width, int height)
      : buffer_(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)) {
    OIIO::ImageBufAlgo::fill(buffer_, {1.0f, 1.0f, 1.0f});
  }
  void line(int x1, int y1, int x2, int y2, const std::array<float, 3>& c) override {
    OIIO::ImageBufAlgo::render_line(buffer_, x1, y1, x2, y2, {c[0], c[1], c[2]});
  }
  void box(int x1, int y1, int x2, int y2, const std::array<float, 3>& c, bool filled) override {
    OIIO::ImageBufAlgo::render_box(buffer_, x1, y1, x2, y2, {c[0], c[1], c[2]}, filled);
  }
  bool text(int x, int y, const std::string& text, int size, TextAlign align,
            const std::array<float, 3>& c) override {
    constexpr OIIO::ImageBufAlgo::TextAlignX kAlign[] = {OIIO::ImageBufAlgo::TextAlignX::Left,
                                                         OIIO::ImageBufAlgo::TextAlignX::Center,
                                                         OIIO::ImageBufAlgo::TextAlignX::Right};
    // DejaVu Sans: Debian's fonts-dejavu-core, which OpenImageIO finds by name.
    const bool drawn = OIIO::ImageBufAlgo::render_text(
        buffer_, x, y, text, size, "DejaVuSans", {c[0], c[1], c[2]},
        kAlign[static_cast<int>(align)], OIIO::ImageBufAlgo::TextAlignY::Center);
    if (!drawn) buffer_.geterror();  // cleared: a missing font is reported by the result
    return drawn;
  }
  void write_png(const std::string& path, int width, int height) const override {
    const OIIO::ImageBuf small =
        OIIO::ImageBufAlgo::resize(buffer_, "", 0.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, 3));
    if (!small.write(path, OIIO::TypeDesc::UINT8, "png")) fail(path, small.geterror());
  }

 private:
  OIIO::ImageBuf buffer_;
};

class Module final : public OiioModule {
 public:
  using OiioModule::read_image;
  Image read_image(const std::string& path, int64_t max_pixels) const override {
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) fail(path, OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.deep) fail(path, "deep images are not supported");
    if (spec.width < 1 || spec.height < 1 || spec.depth != 1 || spec.nchannels < 1)
      fail(path, "not a 2D image with at least one channel");
    if (int64_t(spec.width) * spec.height > max_pixels)
      fail(path, std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                     " pixels is larger than Prism reads here (" + std::to_string(max_pixels) +
                     " pixels)");
    const size_t nch = static_cast<size_t>(spec.nchannels);
    std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * nch);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
      fail(path, in->geterror());
    in->close();

    const int alpha = spec.alpha_channel;
    std::array<int, 3> colour{find_channel(spec, "R"), find_channel(spec, "G"),
                              find_channel(spec, "B")};
    if (colour[0] < 0 || colour[1] < 0 || colour[2] < 0) {
      std::vector<int> others;
      for (int c = 0; c < spec.nchannels; ++c)
        if (c != alpha) others.push_back(c);
      if (others.empty()) fail(path, "has only an alpha channel");
      for (size_t i = 0; i < 3; ++i)
        colour[i] = others.size() == 1 ? others[0] : (i < others.size() ? others[i] : -1);
    }
    Image image(spec.width, spec.height);
    for (size_t p = 0; p < static_cast<size_t>(spec.width) * spec.height; ++p) {
      const float* src = &pixels[p * nch];
      float* dst = &image.rgba[p * 4];
      for (size_t i = 0; i < 3; ++i) dst[i] = colour[i] >= 0 ? src[colour[i]] : 0.0f;
      dst[3] = alpha >= 0 ? src[alpha] : 1.0f;
    }
    return image;
  }

  void write_image(const std::string& path, const Image& image,
                   const std::string& format) const override {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(format);
    if (!out) fail(path, "no " + format + " writer: " + OIIO::geterror());
    const bool eight_bit = format == "jpeg";
    const int channels = format == "tiff" ? 4 : 3;
    OIIO::ImageSpec spec(image.width, image.height, channels,
                         eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (eight_bit) spec.attribute("CompressionQuality", 95);
    spec.attribute("Software", std::string("prism ") + kVersion);
    const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    std::vector<float> data(pixels * static_cast<size_t>(channels));
    for (size_t p = 0; p < pixels; ++p)
      for (size_t c = 0; c < static_cast<size_t>(channels); ++c)
        data[p * static_cast<size_t>(channels) + c] = image.rgba[p * 4 + c];
    if (!out->open(path, spec)) fail(path, out->geterror());
    // Floats in, converted to the file's type by OpenImageIO (rounded for 8 bits).
    if (!out->write_image(OIIO::TypeDesc::FLOAT, data.data())) fail(path, out->geterror());
    if (!out->close()) fail(path, out->geterror());
  }

  std::unique_ptr<RasterCanvas> make_canvas(int width, int height) const override {
    return std::make_unique<OiioCanvas>(width, height);
  }
};

std::string g_build = std::string(kVersion) + " " + kBuildCommit;

}  // namespace
}  // namespace prism

extern "C" {
__attribute__((visibility("default"))) const prism::OiioModule* prism_oiio_module() {
  static const prism::Module module;
  return &module;
}
__attribute__((visibility("default"))) const char* prism_oiio_module_build() {
  return prism::g_build.c_str();
}
}
