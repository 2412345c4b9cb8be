// A scene-linear RGBA float image in the working colour space, row 0 at the top.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace prism {

// A rectangle of pixels: a tile, or the region of a frame that is rendered.
struct TileRect {
  int x0, y0, x1, y1;  // [x0, x1) x [y0, y1)
};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // width * height * 4

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0.0f) {}

  float* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const float* pixel(int x, int y) const {
    return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  }
};

// The pixels of `r` (inside the image) as an image of their own.
inline Image crop(const Image& image, const TileRect& r) {
  Image out(r.x1 - r.x0, r.y1 - r.y0);
  for (int y = r.y0; y < r.y1; ++y)
    std::copy_n(image.pixel(r.x0, y), std::size_t{4} * out.width, out.pixel(0, y - r.y0));
  return out;
}

}  // namespace prism
