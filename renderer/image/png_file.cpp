#include "renderer/image/png_file.h"

#include <png.h>

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

namespace prism {
namespace {

// libpng reports errors by longjmp: what it writes to is plain data, and the function that
// calls setjmp holds nothing with a destructor, which a longjmp would skip.
struct PngSink {
  std::FILE* file;
  char message[160];
};

extern "C" void record_write_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof sink->message, "%s", message);
  png_longjmp(png, 1);
}

extern "C" void ignore_write_warning(png_structp, png_const_charp) {}

bool write_rows(png_structp png, png_infop info, int width, int height, png_bytepp rows,
                png_textp software) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (software) png_set_text(png, info, software, 1);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

void write_png_file(const std::string& path, int width, int height, const uint8_t* rgb,
                    const std::string& software) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw std::runtime_error(path + ": cannot be created");
  PngSink sink{file.get(), {}};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, record_write_error,
                                            ignore_write_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    throw std::runtime_error(path + ": cannot start the PNG encoder");
  }
  png_init_io(png, file.get());
  const std::size_t row_bytes = std::size_t(width) * 3;
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (std::size_t y = 0; y < rows.size(); ++y)
    rows[y] = const_cast<png_bytep>(rgb + y * row_bytes);
  std::string key = "Software", text = software;
  png_text chunk{};
  chunk.compression = PNG_TEXT_COMPRESSION_NONE;
  chunk.key = key.data();
  chunk.text = text.data();
  chunk.text_length = text.size();
  const bool written =
      write_rows(png, info, width, height, rows.data(), software.empty() ? nullptr : &chunk);
  png_destroy_write_struct(&png, &info);
  if (!written) throw std::runtime_error(path + ": " + sink.message);
  if (std::fflush(file.get()) != 0 || std::ferror(file.get()))
    throw std::runtime_error(path + ": cannot be written (disk full?)");
}

}  // namespace prism
