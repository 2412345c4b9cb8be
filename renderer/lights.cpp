#include "renderer/lights.h"

#include <algorithm>
#include <cmath>

#include "renderer/colour.h"
#include "renderer/math.h"

namespace prism {

LightSource make_light_source(const Light& light, const ColourPipeline& colour) {
  LightSource s;
  s.type = light.type;
  const C3f c = colour.from_linear_rec709(light.colour);
  s.intensity = V3f(c.x, c.y, c.z) * light.intensity;
  s.position = V3f(light.position);
  s.direction = normalize(V3f(light.direction));
  s.range = static_cast<float>(light.range);
  s.cos_inner = static_cast<float>(std::cos(light.inner_cone_angle));
  s.cos_outer = static_cast<float>(std::cos(light.outer_cone_angle));
  return s;
}

bool light_arrival(const LightSource& light, const V3f& point, LightArrival* out) {
  if (light.type == LightType::directional) {
    out->to_light = -light.direction;
    out->distance = std::numeric_limits<float>::infinity();
    out->irradiance = light.intensity;
    return true;
  }
  const V3f offset = light.position - point;
  const float d2 = offset.length2();
  if (!(d2 > 0.0f)) return false;
  const float d = std::sqrt(d2);
  out->to_light = offset / d;
  out->distance = d;
  float attenuation = 1.0f / d2;
  if (light.range > 0.0f) {
    // glTF's recommended smooth window: reaches zero at `range`, leaves 1/d^2 alone near.
    const float ratio = d / light.range;
    const float window = std::clamp(1.0f - ratio * ratio * ratio * ratio, 0.0f, 1.0f);
    attenuation *= window * window;
  }
  if (light.type == LightType::spot) {
    const float cos_angle = dot(light.direction, -out->to_light);
    const float span = std::max(light.cos_inner - light.cos_outer, 1e-4f);
    const float t = std::clamp((cos_angle - light.cos_outer) / span, 0.0f, 1.0f);
    attenuation *= t * t;
  }
  if (attenuation <= 0.0f) return false;
  out->irradiance = light.intensity * attenuation;
  return true;
}

}  // namespace prism
