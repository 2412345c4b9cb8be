// OpenImageIO, in a module loaded the first time something needs it.
//
// Debian's OpenImageIO links about 260 shared libraries (OpenCV, GDAL, FFmpeg, DCMTK, ...):
// a process linked against it spends some 0.2 s in the dynamic loader before main. Every
// image a render must touch (EXR, glTF's PNG and JPEG, PNG previews) goes through OpenEXR,
// libpng and libjpeg-turbo instead, so only what OpenImageIO alone does pays for it: reading
// images of any other format, and drawing text into plots (docs/images.md).
//
// The module (libprism_oiio.so) is found in ../lib/prism beside the executable, where the
// build and `cmake --install` put it, and must come from the same build: a module from
// another build is refused rather than called through a mismatched interface.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "renderer/image/image.h"

namespace prism {

enum class TextAlign { left, centre, right };

// A raster to draw a figure into: pixels, y down, display RGB in [0, 1]; it starts white.
class RasterCanvas {
 public:
  virtual ~RasterCanvas() = default;
  virtual void line(int x1, int y1, int x2, int y2, const std::array<float, 3>& rgb) = 0;
  virtual void box(int x1, int y1, int x2, int y2, const std::array<float, 3>& rgb,
                   bool filled) = 0;
  // Text vertically centred on y. False when no font could be found (nothing is drawn).
  virtual bool text(int x, int y, const std::string& text, int size, TextAlign align,
                    const std::array<float, 3>& rgb) = 0;
  // Shrinks the raster to width x height (a filtered resize) and writes it as an 8-bit PNG to
  // `path`. Throws std::runtime_error "<path>: <reason>".
  virtual void write_png(const std::string& path, int width, int height) const = 0;
};

class OiioModule {
 public:
  virtual ~OiioModule() = default;
  // Any image OpenImageIO reads, as RGBA floats: channels R, G, B by name, else the first
  // non-alpha ones (one is grey), alpha or 1. Throws std::runtime_error "<path>: <reason>",
  // also for an image of more than `max_pixels`, before its pixels are allocated.
  virtual Image read_image(const std::string& path, int64_t max_pixels) const = 0;
  Image read_image(const std::string& path) const { return read_image(path, int64_t{1} << 30); }
  virtual std::unique_ptr<RasterCanvas> make_canvas(int width, int height) const = 0;
  // Writes `image` to `path` itself in OpenImageIO's format `format` ("tiff", "hdr",
  // "jpeg"): RGBA float for tiff, RGB float for hdr, RGB 8-bit for jpeg (its values then
  // display-referred in [0, 1]). Throws std::runtime_error "<path>: <reason>".
  virtual void write_image(const std::string& path, const Image& image,
                           const std::string& format) const = 0;
};

// The module, loaded on the first call. Throws std::runtime_error "<for_path>: <reason>"
// when it cannot be loaded, naming the file that needed it.
const OiioModule& oiio_module(const std::string& for_path);

// What the module exports, in C so that dlsym finds it by name: a function returning the
// module's one OiioModule, and one returning its build (renderer/loadable_module.h).
inline constexpr const char* kOiioModuleEntry = "prism_oiio_module";
inline constexpr const char* kOiioModuleBuild = "prism_oiio_module_build";

}  // namespace prism
