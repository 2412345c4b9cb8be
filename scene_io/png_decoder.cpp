#include <png.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "scene_io/gltf_limits.h"
#include "scene_io/image_decoders.h"

namespace prism::gltf_detail {
namespace {

// libpng reports errors by longjmp: the state it reaches is plain data, and the functions
// that call setjmp hold nothing with a destructor, which a longjmp would skip.
struct PngSource {
  const unsigned char* bytes;
  std::size_t size;
  std::size_t offset;
  char message[160];
};

extern "C" void read_from_memory(png_structp png, png_bytep out, png_size_t count) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (count > source->size - source->offset) png_error(png, "the data ends early");
  std::memcpy(out, source->bytes + source->offset, count);
  source->offset += count;
}

extern "C" void record_error(png_structp png, png_const_charp message) {
  auto* source = static_cast<PngSource*>(png_get_error_ptr(png));
  std::snprintf(source->message, sizeof source->message, "%s", message);
  png_longjmp(png, 1);
}

// Warnings (a damaged ancillary chunk, say) leave the pixels intact.
extern "C" void ignore_warning(png_structp, png_const_charp) {}

class PngReader {
 public:
  PngReader(const unsigned char* bytes, std::size_t size) : source_{bytes, size, 0, {}} {
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &source_, record_error, ignore_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (png_ && info_) png_set_read_fn(png_, &source_, read_from_memory);
  }
  ~PngReader() { png_destroy_read_struct(&png_, info_ ? &info_ : nullptr, nullptr); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  bool ready() const { return png_ && info_; }
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }
  std::string why() const {
    return std::string("the PNG image cannot be read") +
           (source_.message[0] ? std::string(": ") + source_.message : std::string());
  }

 private:
  PngSource source_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

// Reads the header and sets the transforms every caller decodes with: palettes to RGB, grey
// below 8 bits to 8, a tRNS chunk to an alpha channel, 16-bit samples in native order; no
// gamma change (glTF says what the values mean, not the file's gAMA chunk).
bool read_info(png_structp png, png_infop info, ImageHeader* header) {
  if (setjmp(png_jmpbuf(png))) return false;
  // libpng's own guards on top of ours: sides, and the memory one ancillary chunk may take.
  png_set_user_limits(png, gltf_limits::kMaxImageSide, gltf_limits::kMaxImageSide);
  png_set_chunk_malloc_max(png, 8u << 20);
  png_read_info(png, info);
  const int colour_type = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colour_type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_swap(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  header->width = static_cast<int>(png_get_image_width(png, info));
  header->height = static_cast<int>(png_get_image_height(png, info));
  header->channels = png_get_channels(png, info);
  header->bits = png_get_bit_depth(png, info);
  return true;
}

bool read_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

}  // namespace

std::string read_png_header(const unsigned char* bytes, std::size_t size, ImageHeader* header) {
  PngReader reader(bytes, size);
  if (!reader.ready()) return "cannot start the PNG decoder";
  if (!read_info(reader.png(), reader.info(), header)) return reader.why();
  if (header->channels < 1 || header->channels > 4 || (header->bits != 8 && header->bits != 16))
    return "a PNG layout Prism does not read (" + std::to_string(header->channels) +
           " channels of " + std::to_string(header->bits) + " bits)";
  return {};
}

std::string decode_png(const unsigned char* bytes, std::size_t size, const ImageHeader& header,
                       unsigned char* samples) {
  PngReader reader(bytes, size);
  ImageHeader found;
  if (!reader.ready()) return "cannot start the PNG decoder";
  if (!read_info(reader.png(), reader.info(), &found)) return reader.why();
  if (found.width != header.width || found.height != header.height ||
      found.channels != header.channels || found.bits != header.bits)
    return "the PNG header changed between reads";
  // libpng writes the rows straight into the caller's texels: no second copy of the image.
  const std::size_t row_bytes =
      std::size_t(header.width) * std::size_t(header.channels) * std::size_t(header.bits / 8);
  std::vector<png_bytep> rows(std::size_t(header.height));
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = samples + y * row_bytes;
  if (!read_rows(reader.png(), reader.info(), rows.data())) return reader.why();
  return {};
}

}  // namespace prism::gltf_detail
