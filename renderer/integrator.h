// The small interface between the tile loop and the integrators (integrators/ implements
// it, one file each). An integrator is called once per tile, not per ray, so its per-ray
// code is free to inline and specialise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>

#include <Imath/ImathVec.h>

#include "renderer/camera.h"
#include "renderer/enum_names.h"
#include "renderer/image/image.h"
#include "renderer/render_scene.h"

namespace prism {

// The kinds of ray an integrator casts, counted per render and reported by name (summary,
// EXR metadata, compare's tables). An integrator that casts a new kind adds a row here.
// `bounce`: a path tracer's rays after the camera ray, sampled from the BSDF.
enum class RayKind : uint8_t { camera, shadow, reflection, refraction, bounce };
inline constexpr EnumName<RayKind> kRayKindNames[] = {{RayKind::camera, "camera"},
                                                      {RayKind::shadow, "shadow"},
                                                      {RayKind::reflection, "reflection"},
                                                      {RayKind::refraction, "refraction"},
                                                      {RayKind::bounce, "bounce"}};
constexpr std::span<const EnumName<RayKind>> enum_names(RayKind) {
  return kRayKindNames;
}
inline constexpr size_t kRayKindCount = std::size(kRayKindNames);

// What adaptive sampling's --target-error bounds (renderer/sampling/adaptive_sampling.h):
// `pixel`, every pixel's estimated relative error (a pixel stops once it is below, as Cycles'
// noise threshold); `image`, the image's, the root of the mean over pixels of their squared
// relative errors (relMSE's root), with each pixel given the samples that lower it most.
enum class ErrorGoal : uint8_t { pixel, image };
inline constexpr EnumName<ErrorGoal> kErrorGoalNames[] = {{ErrorGoal::pixel, "pixel"},
                                                          {ErrorGoal::image, "image"}};
constexpr std::span<const EnumName<ErrorGoal>> enum_names(ErrorGoal) {
  return kErrorGoalNames;
}

struct RayCounters {
  uint64_t rays[kRayKindCount] = {};
  // Not rays: samples whose radiance was NaN or infinite, left out of their pixel.
  uint64_t discarded_samples = 0;

  uint64_t& operator[](RayKind kind) { return rays[static_cast<size_t>(kind)]; }
  uint64_t operator[](RayKind kind) const { return rays[static_cast<size_t>(kind)]; }
  uint64_t total() const {
    uint64_t sum = 0;
    for (uint64_t n : rays) sum += n;
    return sum;
  }
  RayCounters& operator+=(const RayCounters& o) {
    for (size_t k = 0; k < kRayKindCount; ++k) rays[k] += o.rays[k];
    discarded_samples += o.discarded_samples;
    return *this;
  }
};

// The film and how it is sampled: what every integrator shares. An integrator's own
// parameters (a depth limit, an ambient term) belong to the integrator (integrators/
// registry.h), the background to the scene (RenderScene::environment).
struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 1;  // spp = 1 samples pixel centres, as the lecture's view rays do
  int tile_size = 16;
  // false: the integrators' general code, whatever the scene's features allow them to skip
  // (integrators/shading_flags.h); the image is the same, only slower.
  bool specialise = true;
  // Adaptive sampling (renderer/sampling/adaptive_sampling.h, docs/sampling.md). With neither set,
  // every pixel takes exactly `spp` samples, as it always did; with either, `spp` is the
  // most a pixel takes and samples are taken in rounds.
  float target_error = 0.0f;        // a pixel stops once its relative error is below; 0 = off
  double time_limit_seconds = 0.0;  // stop after the round in progress once passed; 0 = none
  int min_spp = 8;                  // samples every pixel takes before the first decision
  ErrorGoal error_goal = ErrorGoal::pixel;  // what target_error bounds
  // The part of the frame rendered (pbrt's pixel bounds): pixels outside it are not traced
  // and stay 0 with alpha 0, and an EXR records it as its data window. Every pixel inside is
  // the full frame's, bit for bit (with adaptive sampling, pixels at its edge may take other
  // sample counts: their neighbourhood is cut). Empty (x1 == 0): the whole frame.
  TileRect region{0, 0, 0, 0};
  // Which of the independent sample streams the render draws (renderer/sampling/sampler.h,
  // pixel_sample_key). 0, the default, is every render's; another seed gives the same image
  // in expectation with noise independent of seed 0's: what a reference must be to measure a
  // render's error (its first samples would otherwise be the render's own).
  uint32_t seed = 0;
  // The largest seed a user may ask for: the command line's and Python's whole numbers are
  // ints, so every front end accepts the same range.
  static constexpr int kMaxSeed = 2147483647;
  bool adaptive() const { return target_error > 0.0f || time_limit_seconds > 0.0; }
  bool has_region() const { return region.x1 > 0; }
  TileRect rendered() const { return has_region() ? region : TileRect{0, 0, width, height}; }
  int64_t rendered_pixels() const {
    const TileRect r = rendered();
    return int64_t{r.x1 - r.x0} * (r.y1 - r.y0);
  }
};

// The tile loop traces camera rays in packets of kPacketBlock x kPacketBlock pixels
// (integrators/tile_loop.h); tiles are whole numbers of them (renderer/render.cpp).
inline constexpr int kPacketBlock = 4;

// A pixel's running totals over the samples taken so far, kept between passes.
struct PixelSums {
  Imath::V3f radiance{0.0f, 0.0f, 0.0f};
  uint32_t hits = 0;                              // kept samples whose camera ray found geometry
  uint32_t kept = 0;                              // samples with finite radiance
  Imath::V3f radiance_squared{0.0f, 0.0f, 0.0f};  // for adaptive sampling's error model
};

// A pixel's RGBA from its sums: the mean of its kept samples, alpha the fraction that hit;
// 0 with alpha 0 when none was kept. Here rather than in the tile loop because a resumed
// render (renderer/render_state.h) writes its stopped pixels from their sums the same way.
inline void write_pixel(const PixelSums& sums, float* out) {
  if (sums.kept == 0) {
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    return;
  }
  const float inv_kept = 1.0f / static_cast<float>(sums.kept);
  out[0] = sums.radiance.x * inv_kept;
  out[1] = sums.radiance.y * inv_kept;
  out[2] = sums.radiance.z * inv_kept;
  out[3] = static_cast<float>(sums.hits) * inv_kept;
}

// Which samples of each pixel a render_tile call takes. The default is all of them in one
// go; renderer/render.cpp takes one sample per pass when it is asked for the image after
// every pass, keeping the sums in `sums` (one per pixel, row-major) between calls.
// Adaptive rounds also pass `active` (pixels outside it are left alone: their sums and image
// pixels keep what earlier rounds wrote) and `first_half`, where each pixel keeps the sums of
// its first 2^k samples, 2^k the largest power of two below the samples it has taken: the
// error estimate compares those with the rest (renderer/sampling/adaptive_sampling.h).
struct SamplePass {
  int first = 0;
  int end = -1;                     // exclusive; -1 = settings.spp
  PixelSums* sums = nullptr;        // null: a single pass, sums live on the stack
  const uint8_t* active = nullptr;  // per pixel, row-major; null = every pixel
  PixelSums* first_half = nullptr;  // per pixel, row-major; null = not kept
};

struct RenderContext {
  const RenderScene& scene;
  const Camera& camera;
  const RenderSettings& settings;
  SamplePass pass{};
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Takes context.pass's samples of every pixel in `tile` and writes the mean so far as its
  // RGBA; adds the rays it cast (and the samples it discarded) to `counters`.
  virtual void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                           RayCounters* counters) const = 0;
};

}  // namespace prism
