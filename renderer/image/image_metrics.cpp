#include "renderer/image/image_metrics.h"

#include "renderer/image/exr_file.h"
#include "renderer/image/oiio_module.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <vector>

namespace prism {
namespace {

bool pixel_is_finite(const float* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) && std::isfinite(p[3]);
}

double psnr_from_mse(double mse) {
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(kPsnrPeak * kPsnrPeak / mse);
}

// Keeps the first location in scan order on ties, as idiff does, so the two can be compared.
void track_max(double abs_error, int x, int y, ChannelError* e) {
  if (e->max_x < 0 || abs_error > e->max_abs) {
    e->max_abs = abs_error;
    e->max_x = x;
    e->max_y = y;
  }
}

[[noreturn]] void fail(const std::string& path, std::string reason) {
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  while (!reason.empty() && reason.back() == ' ') reason.pop_back();
  throw std::runtime_error(path + ": " + reason);
}

}  // namespace

ImageError compare_images(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
                                std::to_string(b.height));
  ImageError e;
  // Sums in double: a 4K image has 25 million terms, far past float's 24-bit mantissa.
  std::array<double, 3> squared{}, relative{};
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const float* pa = a.pixel(x, y);
      const float* pb = b.pixel(x, y);
      const bool finite_a = pixel_is_finite(pa);
      const bool finite_b = pixel_is_finite(pb);
      e.non_finite_a += finite_a ? 0 : 1;
      e.non_finite_b += finite_b ? 0 : 1;
      if (!finite_a || !finite_b) continue;
      ++e.compared_pixels;
      for (int c = 0; c < 3; ++c) {
        const double ref = pb[c];
        const double d = static_cast<double>(pa[c]) - ref;
        squared[static_cast<size_t>(c)] += d * d;
        relative[static_cast<size_t>(c)] += d * d / (ref * ref + kRelMseEpsilon);
        const double abs_error = std::fabs(d);
        track_max(abs_error, x, y, &e.channel[static_cast<size_t>(c)]);
        if (e.overall.max_x < 0 || abs_error > e.overall.max_abs) {
          track_max(abs_error, x, y, &e.overall);
          e.max_channel = c;
        }
      }
    }
  }
  const double n = static_cast<double>(e.compared_pixels);
  if (e.compared_pixels == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (ChannelError* c : {&e.channel[0], &e.channel[1], &e.channel[2], &e.overall})
      *c = ChannelError{nan, nan, nan, nan, -1, -1};
    return e;
  }
  double squared_all = 0.0, relative_all = 0.0;
  for (size_t c = 0; c < 3; ++c) {
    const double mse = squared[c] / n;
    e.channel[c].rmse = std::sqrt(mse);
    e.channel[c].relmse = relative[c] / n;
    e.channel[c].psnr = psnr_from_mse(mse);
    squared_all += squared[c];
    relative_all += relative[c];
  }
  const double mse = squared_all / (3.0 * n);
  e.overall.rmse = std::sqrt(mse);
  e.overall.relmse = relative_all / (3.0 * n);
  e.overall.psnr = psnr_from_mse(mse);
  return e;
}

std::optional<std::string> read_exr_attribute(const std::string& path, const std::string& key) {
  return read_exr_string(path, "prism:" + key);
}

Image read_exr(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory");
  if (is_exr_file(path)) return read_exr_file(path);
  // Another format (a PNG or TIFF reference, say): OpenImageIO, loaded only now.
  return oiio_module(path).read_image(path);
}

Image difference_image(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("difference_image: the images differ in size");
  Image out(a.width, a.height);
  for (size_t i = 0; i < a.rgba.size(); i += 4) {
    bool finite = true;
    for (size_t c = 0; c < 3; ++c)
      finite = finite && std::isfinite(a.rgba[i + c]) && std::isfinite(b.rgba[i + c]);
    for (size_t c = 0; c < 3; ++c)
      out.rgba[i + c] = finite ? std::abs(a.rgba[i + c] - b.rgba[i + c])
                               : std::numeric_limits<float>::quiet_NaN();
    out.rgba[i + 3] = 1.0f;
  }
  return out;
}

Image error_heatmap(const Image& difference, float peak) {
  // Stops of the ramp, evenly spaced from 0 to `peak`.
  static constexpr float kRamp[][3] = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1},
                                       {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
  constexpr int kSegments = static_cast<int>(std::size(kRamp)) - 1;
  Image out(difference.width, difference.height);
  for (size_t i = 0; i < difference.rgba.size(); i += 4) {
    const float e = std::max({difference.rgba[i], difference.rgba[i + 1], difference.rgba[i + 2]});
    float* p = &out.rgba[i];
    p[3] = 1.0f;
    if (!std::isfinite(difference.rgba[i]) || !std::isfinite(difference.rgba[i + 1]) ||
        !std::isfinite(difference.rgba[i + 2])) {
      p[0] = 0.0f, p[1] = 1.0f, p[2] = 0.0f;
      continue;
    }
    const float t = peak > 0.0f ? std::clamp(e / peak, 0.0f, 1.0f) * kSegments : 0.0f;
    const int k = std::min(static_cast<int>(t), kSegments - 1);
    const float f = t - static_cast<float>(k);
    for (int c = 0; c < 3; ++c) p[c] = kRamp[k][c] + f * (kRamp[k + 1][c] - kRamp[k][c]);
  }
  return out;
}

}  // namespace prism
