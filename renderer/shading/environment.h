// What a ray that leaves the scene sees: the environment's radiance in its direction. Today a
// constant (the command line's --background); an image-based environment, and its sampling
// as a light, would implement the same two calls, and integrators that ask radiance() for
// every escaping ray need not change.
#pragma once

#include <Imath/ImathVec.h>

namespace prism {

class Environment {
 public:
  Environment() = default;
  // Uniform radiance in every direction, in the working colour space.
  explicit Environment(const Imath::V3f& radiance) : radiance_(radiance) {}

  // Radiance arriving along -direction, i.e. seen looking along `direction` (unit).
  const Imath::V3f& radiance(const Imath::V3f& /*direction*/) const { return radiance_; }
  // True when no direction sends any light: integrators may skip asking.
  bool black() const { return radiance_.x <= 0.0f && radiance_.y <= 0.0f && radiance_.z <= 0.0f; }

 private:
  Imath::V3f radiance_{0.0f, 0.0f, 0.0f};
};

}  // namespace prism
