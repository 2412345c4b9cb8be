// The two image formats glTF allows, decoded by their reference libraries (libpng and
// libjpeg-turbo) from bytes in memory: a scene pays for no other image code, and no other
// decoder ever sees a glTF image (docs/images.md).
//
// Each call returns an empty string on success, else a short reason (no file or element
// name: the caller adds them). Headers are read before anything is allocated, so the
// caller can check sizes against its limits first.
#pragma once

#include <cstddef>
#include <string>

namespace prism::gltf_detail {

struct ImageHeader {
  int width = 0;
  int height = 0;
  int channels = 0;  // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA, after expanding palettes
  int bits = 8;      // per channel as decoded: 8, or 16 for 16-bit PNGs
};

std::string read_png_header(const unsigned char* bytes, std::size_t size, ImageHeader* header);
// Fills width x height x channels samples of header.bits each, as stored: bytes for 8-bit
// images, native-order uint16_t for 16-bit ones; straight (not premultiplied) alpha as glTF
// defines it. The caller says what the codes mean (gltf_images.h).
std::string decode_png(const unsigned char* bytes, std::size_t size, const ImageHeader& header,
                       unsigned char* samples);

std::string read_jpeg_header(const unsigned char* bytes, std::size_t size, ImageHeader* header);
// Fills width x height x channels 8-bit codes.
std::string decode_jpeg(const unsigned char* bytes, std::size_t size, const ImageHeader& header,
                        unsigned char* codes);

}  // namespace prism::gltf_detail
