// A scene-linear RGBA float image in the working colour space, row 0 at the top.
#pragma once

#include <cstddef>
#include <vector>

namespace prism {

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

}  // namespace prism
