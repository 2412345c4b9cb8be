#include <turbojpeg.h>

#include <memory>

#include "scene_io/image_decoders.h"

namespace prism::gltf_detail {
namespace {

struct HandleCloser {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using Decompressor = std::unique_ptr<void, HandleCloser>;

std::string why(tjhandle handle) {
  const char* message = tjGetErrorStr2(handle);
  return std::string("the JPEG image cannot be read") +
         (message && *message ? std::string(": ") + message : std::string());
}

}  // namespace

std::string read_jpeg_header(const unsigned char* bytes, std::size_t size, ImageHeader* header) {
  const Decompressor handle(tjInitDecompress());
  if (!handle) return "cannot start the JPEG decoder";
  int width = 0, height = 0, subsampling = 0, colour_space = 0;
  if (tjDecompressHeader3(handle.get(), bytes, static_cast<unsigned long>(size), &width, &height,
                          &subsampling, &colour_space) != 0)
    return why(handle.get());
  // TurboJPEG reports a file that ends before its frame header as a warning, with no size.
  if (width <= 0 || height <= 0) return why(handle.get());
  // glTF's JPEG images are colour or grey; CMYK ones have no colour meaning it defines.
  if (colour_space == TJCS_CMYK || colour_space == TJCS_YCCK)
    return "a CMYK JPEG image; glTF images are RGB or grey";
  header->width = width;
  header->height = height;
  header->channels = colour_space == TJCS_GRAY ? 1 : 3;
  header->bits = 8;
  return {};
}

std::string decode_jpeg(const unsigned char* bytes, std::size_t size, const ImageHeader& header,
                        unsigned char* codes) {
  const Decompressor handle(tjInitDecompress());
  if (!handle) return "cannot start the JPEG decoder";
  // Default flags: the accurate integer DCT and smooth chroma upsampling, libjpeg's own
  // defaults. A warning (e.g. data ending early, filled with grey) leaves a whole image,
  // as every JPEG viewer shows it; only errors refuse the file.
  const int pixel_format = header.channels == 1 ? TJPF_GRAY : TJPF_RGB;
  if (tjDecompress2(handle.get(), bytes, static_cast<unsigned long>(size), codes, header.width, 0,
                    header.height, pixel_format, 0) != 0 &&
      tjGetErrorCode(handle.get()) != TJERR_WARNING)
    return why(handle.get());
  return {};
}

}  // namespace prism::gltf_detail
