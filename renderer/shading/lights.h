// KHR_lights_punctual lights in glTF's units: point and spot intensity in candela, so the
// irradiance at distance d facing the light is I / d^2 (the lecture's I_PL / (4 pi d^2) with
// I_PL = 4 pi I); directional lights in lux, the irradiance itself.
#pragma once

#include <limits>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"

namespace prism {

class ColourPipeline;

struct LightSource {
  LightType type = LightType::point;
  Imath::V3f intensity;  // colour x intensity, working space (W/sr, or W/m^2 directional)
  Imath::V3f position;
  Imath::V3f direction;  // unit, the way the light travels
  float range = 0.0f;    // 0 = unlimited
  float cos_inner = 1.0f, cos_outer = 0.0f;
};

// What arrives from one light at a point.
struct LightArrival {
  Imath::V3f to_light;  // unit
  float distance = std::numeric_limits<float>::infinity();
  Imath::V3f irradiance;  // on a surface facing the light (before the cosine law)
};

LightSource make_light_source(const Light& light, const ColourPipeline& colour);

// False when nothing arrives (outside the spot cone or the range, or at the light itself).
bool light_arrival(const LightSource& light, const Imath::V3f& point, LightArrival* out);

}  // namespace prism
