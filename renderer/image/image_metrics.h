// Error metrics between a test image and a reference, and a reader for the images they
// compare. docs/metrics.md has the formulas and how they agree with OpenImageIO's idiff.
//
// Only the colour channels (R, G, B) are compared; alpha is coverage, not radiance. A pixel
// with any non-finite channel (NaN or infinity) in either image is left out of every metric
// and counted instead, so one stray NaN cannot turn the whole comparison into NaN.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "renderer/image/image.h"

namespace prism {

// relMSE's epsilon: keeps dark reference pixels from dominating (pbrt and Mitsuba use 1e-2).
inline constexpr double kRelMseEpsilon = 1e-2;
// PSNR's peak signal: scene-linear images have no natural white, so we take 1 (as idiff).
inline constexpr double kPsnrPeak = 1.0;

struct ChannelError {
  double rmse = 0.0;
  double relmse = 0.0;  // mean of (a - b)^2 / (b^2 + kRelMseEpsilon), b the reference
  double psnr = 0.0;    // 10 log10(peak^2 / MSE) dB; +infinity when the channels are equal
  double max_abs = 0.0;
  int max_x = -1, max_y = -1;  // where max_abs is (first in scan order); -1 if nothing compared
};

struct ImageError {
  std::array<ChannelError, 3> channel;  // R, G, B
  ChannelError overall;                 // over all three channels together
  int max_channel = -1;                 // 0, 1, 2: the channel of overall.max_abs
  uint64_t compared_pixels = 0;         // finite in both images
  uint64_t non_finite_a = 0;            // pixels with a NaN or infinite channel, per image
  uint64_t non_finite_b = 0;
};

// `b` is the reference. Both must have the same size (std::invalid_argument otherwise).
// With no pixel finite in both, every metric is NaN.
ImageError compare_images(const Image& a, const Image& b);

// |a - b| per colour channel, alpha 1; a pixel with a NaN or infinity in either image is NaN
// (as idiff -o writes it). The images must have the same size.
Image difference_image(const Image& a, const Image& b);
// A false-colour map of the largest channel error per pixel, display RGB in [0, 1]: black
// for none through blue, magenta, red and yellow to white at `peak`; non-finite pixels green.
Image error_heatmap(const Image& difference, float peak);

// Reads an image file (any format OpenImageIO reads; meant for EXR) as scene-linear RGBA.
// One channel is grey (R = G = B), a missing alpha is 1. Throws std::runtime_error
// "<path>: <reason>" on one line when the file cannot be read.
Image read_exr(const std::string& path);

// The string attribute `prism:<key>` of an EXR's header (written from RenderMetadata::extra),
// or std::nullopt when the file is missing, unreadable, not an EXR or lacks it. Reads the
// header only.
std::optional<std::string> read_exr_attribute(const std::string& path, const std::string& key);

}  // namespace prism
