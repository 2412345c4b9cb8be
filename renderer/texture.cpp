#include "renderer/texture.h"

#include <algorithm>
#include <cmath>

#include "renderer/colour.h"

namespace prism {
namespace {

// Texel index for an integer coordinate outside [0, size) under a wrap mode.
int wrap_index(long long i, int size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp_to_edge:
      return static_cast<int>(std::clamp<long long>(i, 0, size - 1));
    case TextureWrap::mirrored_repeat: {
      const long long period = 2LL * size;
      long long m = i % period;
      if (m < 0) m += period;
      return static_cast<int>(m < size ? m : period - 1 - m);
    }
    case TextureWrap::repeat:
    default: {
      long long m = i % size;
      return static_cast<int>(m < 0 ? m + size : m);
    }
  }
}

}  // namespace

Texture::Texture(const TextureImage& image, const ColourPipeline& colour)
    : width_(image.width), height_(image.height), wrap_s_(image.wrap_s), wrap_t_(image.wrap_t) {
  const size_t count = static_cast<size_t>(width_) * height_;
  std::vector<float> rgb(count * 3);
  texels_.resize(count);
  const int c = image.channels;
  for (size_t i = 0; i < count; ++i) {
    const float* t = &image.texels[i * c];
    // Grey and grey-alpha images broadcast their grey value; alpha defaults to opaque.
    const float r = t[0];
    const float g = c >= 3 ? t[1] : t[0];
    const float b = c >= 3 ? t[2] : t[0];
    const float a = c == 4 ? t[3] : (c == 2 ? t[1] : 1.0f);
    rgb[i * 3 + 0] = r;
    rgb[i * 3 + 1] = g;
    rgb[i * 3 + 2] = b;
    texels_[i].w = a;
  }
  if (image.encoding == TextureEncoding::srgb) colour.srgb_texture_to_working(rgb.data(), count, 3);
  for (size_t i = 0; i < count; ++i) {
    texels_[i].x = rgb[i * 3 + 0];
    texels_[i].y = rgb[i * 3 + 1];
    texels_[i].z = rgb[i * 3 + 2];
  }
}

Imath::V4f Texture::sample(const Imath::V2f& uv) const {
  // Texel centres sit at half-integer coordinates.
  const float x = uv.x * static_cast<float>(width_) - 0.5f;
  const float y = uv.y * static_cast<float>(height_) - 0.5f;
  // Beyond 2^40 texels a float UV has no fractional texel left; clamping there keeps the
  // integer conversion defined without changing any representable lookup.
  constexpr float kLimit = 1099511627776.0f;
  if (!(std::fabs(x) < kLimit) || !(std::fabs(y) < kLimit)) return texel(0, 0);
  const float fx = std::floor(x), fy = std::floor(y);
  const float wx = x - fx, wy = y - fy;
  const auto ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
  const int x0 = wrap_index(ix, width_, wrap_s_), x1 = wrap_index(ix + 1, width_, wrap_s_);
  const int y0 = wrap_index(iy, height_, wrap_t_), y1 = wrap_index(iy + 1, height_, wrap_t_);
  return (texel(x0, y0) * (1.0f - wx) + texel(x1, y0) * wx) * (1.0f - wy) +
         (texel(x0, y1) * (1.0f - wx) + texel(x1, y1) * wx) * wy;
}

}  // namespace prism
