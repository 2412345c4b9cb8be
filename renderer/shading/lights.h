// Lights, behind the contract a path tracer needs (pbrt-v4's base/light.h, Embree's
// tutorials/common/lights/light.h): sample the light arriving at a point, with its pdf;
// the density of a direction; the radiance a ray sees when it meets the light; whether it is
// a delta light; and its power, for choosing among lights (light_sampler.h).
//
// KHR_lights_punctual lights in glTF's units: point and spot intensity in candela, so the
// irradiance at distance d facing the light is I / d^2 (the lecture's I_PL / (4 pi d^2) with
// I_PL = 4 pi I); directional lights in lux, the irradiance itself. All three are delta
// lights: a ray never meets one, and sample() is exact (pdf 1, the irradiance as radiance).
#pragma once

#include <limits>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"

namespace prism {

class ColourPipeline;

// Light arriving at a point from one light.
struct LightSample {
  Imath::V3f wi;  // unit, from the point towards the light
  float distance = std::numeric_limits<float>::infinity();  // to the light; inf: directional
  // Arriving along -wi. For a delta light, the irradiance on a surface facing it (pbrt's
  // convention: a delta light's radiance and pdf are both deltas, which cancel).
  Imath::V3f radiance;
  float pdf = 1.0f;  // per unit solid angle; 1 for a delta light
};

class LightSource {
 public:
  LightSource(const Light& light, const ColourPipeline& colour);

  LightType type() const { return type_; }
  // A delta light cannot be hit by a ray or sampled by a BSDF: multiple importance sampling
  // gives its sample() the whole weight.
  bool is_delta() const { return true; }
  // Light arriving at `point` (`u`: two sample dimensions, unused by delta lights). False when
  // nothing arrives: outside the spot cone or the range, at the light itself, or a light
  // whose irradiance would not be finite.
  bool sample(const Imath::V3f& point, const Imath::V2f& u, LightSample* out) const;
  // The density sample() gives direction wi from `point`: 0 for a delta light.
  float pdf(const Imath::V3f& /*point*/, const Imath::V3f& /*wi*/) const { return 0.0f; }
  // Radiance a ray leaving `point` along `direction` sees on the light itself: 0 for a delta
  // light, which no ray can meet.
  Imath::V3f emitted(const Imath::V3f& /*point*/, const Imath::V3f& /*direction*/) const {
    return Imath::V3f(0.0f);
  }
  // Total emitted power in W (per colour channel), given the radius of a sphere around the
  // scene (a directional light's power is its irradiance over the disc the scene shows it).
  Imath::V3f power(float scene_radius) const;

  // In the frame of the geometry (renderer/geometry/embree_scene.h, world_origin).
  const Imath::V3f& position() const { return position_; }
  const Imath::V3f& direction() const { return direction_; }  // unit, the way light travels
  const Imath::V3f& intensity() const { return intensity_; }  // W/sr, or W/m^2 directional
  float range() const { return range_; }                      // m; 0 = unlimited
  float cos_outer() const { return cos_outer_; }              // spot: the cone's edge
  // Delivers nothing anywhere (a zero colour or intensity): sample() always says no.
  bool dark() const { return intensity_.x == 0.0f && intensity_.y == 0.0f && intensity_.z == 0.0f; }

 private:
  LightType type_ = LightType::point;
  Imath::V3f intensity_;  // colour x intensity, working space
  Imath::V3f position_;
  Imath::V3f direction_;
  float range_ = 0.0f;  // 0 = unlimited
  float cos_inner_ = 1.0f, cos_outer_ = 0.0f;
};

}  // namespace prism
