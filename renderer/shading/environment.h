// What a ray that leaves the scene sees, and the environment as a light: the smallest contract
// a path tracer needs of an infinite light (pbrt-v4's base/light.h for infinite lights):
// radiance in a direction, a sampled direction with its solid-angle density, the density of
// a given direction (for multiple importance sampling) and the power, for choosing among
// lights. Integrators without sampled light read it through irradiance(), the light a
// surface receives from it, as their ambient term (integrators/local_shading.h).
//
// An environment is uniform (the command line's --background) or an equirectangular
// (latitude-longitude) map, looked up nearest-texel so that radiance(), sample() and pdf()
// describe one piecewise-constant function exactly. The map's conventions are Blender's world
// mapping with glTF's +Y up: row 0 looks straight up (+Y) and the last row straight down; the
// middle column looks along +X, the column a quarter to its right along +Z, a quarter to its
// left along -Z. Copies share the map.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include <Imath/ImathVec.h>

#include "renderer/image/image.h"

namespace prism {

// Which density the environment is sampled by. `complete` reaches every direction that sends
// light: what a light sample needs when nothing else finds the light. `beside_bsdf` is for a
// light sample weighed by multiple importance sampling against a BSDF sample that can reach
// every direction the light sample can: the map less its mean radiance, clamped at zero, so
// that light samples go to what is brighter than the mean (a sun, a window) and the BSDF's
// samples, which MIS then weighs whole there, find the rest (MIS compensation: Karlik et al.
// 2019, pbrt-v4's allowIncompletePDF). A uniform environment, or a map with no texel above
// its mean, has only the complete density.
enum class EnvironmentDensity : uint8_t { complete, beside_bsdf };

struct EnvironmentSample {
  Imath::V3f wi;        // unit, from the shading point out to the environment
  Imath::V3f radiance;  // arriving along -wi
  float pdf = 0.0f;     // per unit solid angle
};

class Environment {
 public:
  Environment() = default;
  // Uniform radiance in every direction, in the working colour space.
  explicit Environment(const Imath::V3f& radiance);
  // An equirectangular map: the RGB of `map` (alpha is ignored) in the working colour space,
  // times `intensity`, turned by `rotation_radians` about +Y (right-handed: counter-clockwise
  // seen from above, so a feature at +Z moves towards +X). Throws std::invalid_argument for
  // an empty map, a texel that is negative or not finite (naming it), or a scaled texel that
  // is no longer finite.
  Environment(const Image& map, float rotation_radians, float intensity);

  // Radiance arriving along -direction, i.e. seen looking along `direction` (unit).
  Imath::V3f radiance(const Imath::V3f& direction) const {
    return map_ ? map_radiance(direction) : radiance_;
  }
  // What a camera ray that leaves the scene sees: radiance(), or black when the environment
  // is hidden from the camera. Only camera rays ask this; every other ray, and sampling,
  // sees the environment itself.
  Imath::V3f background(const Imath::V3f& direction) const {
    return hidden_ ? Imath::V3f(0.0f) : radiance(direction);
  }
  void set_hidden_from_camera(bool hidden) { hidden_ = hidden; }
  bool hidden_from_camera() const { return hidden_; }

  // True when no direction sends any light: integrators may skip asking.
  bool black() const { return black_; }

  // A direction drawn from `u` in [0,1)^2 with its density; false when the environment is
  // black (nothing to sample). A uniform environment samples the sphere uniformly; a map
  // draws a texel in proportion to its luminance times its solid angle, then a point in it
  // uniformly in (column, row). The radiance and pdf returned are exactly radiance(wi) and
  // pdf(wi).
  // With `density` beside_bsdf the texel is drawn by its luminance above the map's mean
  // instead, and pdf() must be asked for the same density.
  bool sample(const Imath::V2f& u, EnvironmentSample* out,
              EnvironmentDensity density = EnvironmentDensity::complete) const;
  // The density sample() gives direction `wi` (unit).
  float pdf(const Imath::V3f& wi, EnvironmentDensity density = EnvironmentDensity::complete) const;
  // radiance(wi) and pdf(wi) at once, with one lookup of the texel: what a path that escapes
  // after a BSDF sample needs to weigh the light it finds.
  Imath::V3f radiance_and_pdf(const Imath::V3f& wi, float* pdf,
                              EnvironmentDensity density = EnvironmentDensity::complete) const;
  // Power (W per channel) through a sphere of `scene_radius` around the scene: what the
  // environment delivers to the scene, for choosing between it and the scene's lights:
  // pi r^2 times the integral of the radiance over the sphere.
  Imath::V3f power(float scene_radius) const;

  // The irradiance a surface facing `normal` (unit) receives from the whole environment,
  // unoccluded: the integral of radiance(w) max(0, normal . w) over directions. Exact for
  // a uniform environment (pi L); for a map, its projection on the nine spherical harmonics
  // of order <= 2 convolved with the clamped cosine (Ramamoorthi and Hanrahan 2001), clamped
  // at 0. Deterministic: computed once, when the environment is made.
  Imath::V3f irradiance(const Imath::V3f& normal) const;

  // The map's texel a direction falls in (column, row), for tests; (0, 0) when uniform.
  std::array<int, 2> texel_of(const Imath::V3f& direction) const;

 private:
  struct Map;
  Imath::V3f map_radiance(const Imath::V3f& direction) const;
  // The map's density at `wi`, which falls in texel (column, row).
  float map_pdf(const Imath::V3f& wi, int column, int row, EnvironmentDensity density) const;

  Imath::V3f radiance_{0.0f, 0.0f, 0.0f};  // uniform only
  std::shared_ptr<const Map> map_;
  bool black_ = true;
  bool hidden_ = false;
};

// A grey sky whose radiance runs linearly in the height y of the direction, from `nadir`
// (y = -1) to `zenith` (y = 1): a map of one column and 256 rows, each row the mean of that
// linear radiance over its solid angle, so the sky's power and irradiance are the linear
// one's to within the rows' discretisation.
Environment gradient_sky(float zenith, float nadir);

}  // namespace prism
