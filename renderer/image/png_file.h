// 8-bit PNG files written through libpng: previews and plots, without OpenImageIO.
#pragma once

#include <cstdint>
#include <string>

namespace prism {

// Writes `rgb` (width x height x 3 bytes, row 0 at the top) to `path` itself, with a
// "Software" text chunk when `software` is not empty. Throws std::runtime_error
// "<path>: <reason>" on failure.
void write_png_file(const std::string& path, int width, int height, const uint8_t* rgb,
                    const std::string& software);

}  // namespace prism
