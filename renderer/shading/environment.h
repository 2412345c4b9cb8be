// What a ray that leaves the scene sees, and the environment as a light: the smallest contract
// a path tracer needs of an infinite light (pbrt-v4's base/light.h for infinite lights):
// radiance in a direction, a sampled direction with its solid-angle density, the density of
// a given direction (for multiple importance sampling) and the power, for choosing among
// lights. Today a constant (the command line's --background); an image-based environment
// implements the same calls, and integrators written against them need not change.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Imath/ImathVec.h>

namespace prism {

struct EnvironmentSample {
  Imath::V3f wi;        // unit, from the shading point out to the environment
  Imath::V3f radiance;  // arriving along -wi
  float pdf = 0.0f;     // per unit solid angle
};

class Environment {
 public:
  Environment() = default;
  // Uniform radiance in every direction, in the working colour space.
  explicit Environment(const Imath::V3f& radiance) : radiance_(radiance) {}

  // Radiance arriving along -direction, i.e. seen looking along `direction` (unit).
  Imath::V3f radiance(const Imath::V3f& /*direction*/) const { return radiance_; }
  // True when no direction sends any light: integrators may skip asking.
  bool black() const { return radiance_.x <= 0.0f && radiance_.y <= 0.0f && radiance_.z <= 0.0f; }

  // A direction drawn from `u` in [0,1)^2 with its density; false when the environment is
  // black (nothing to sample). A uniform environment samples the sphere uniformly.
  bool sample(const Imath::V2f& u, EnvironmentSample* out) const {
    if (black()) return false;
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
    out->wi = Imath::V3f(r * std::cos(phi), r * std::sin(phi), z);
    out->radiance = radiance_;
    out->pdf = 1.0f / (4.0f * std::numbers::pi_v<float>);
    return true;
  }
  // The density sample() gives direction `wi` (unit).
  float pdf(const Imath::V3f& /*wi*/) const {
    return black() ? 0.0f : 1.0f / (4.0f * std::numbers::pi_v<float>);
  }
  // Power (W per channel) through a sphere of `scene_radius` around the scene: what the
  // environment delivers to the scene, for choosing between it and the scene's lights.
  Imath::V3f power(float scene_radius) const {
    const float pi = std::numbers::pi_v<float>;
    return radiance_ * (4.0f * pi * pi * scene_radius * scene_radius);
  }

 private:
  Imath::V3f radiance_{0.0f, 0.0f, 0.0f};
};

}  // namespace prism
