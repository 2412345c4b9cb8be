#include "renderer/shading/lights.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "renderer/image/colour.h"
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
  // A light that delivers nothing costs no shadow ray.
  if (light.intensity.x == 0.0f && light.intensity.y == 0.0f && light.intensity.z == 0.0f)
    return false;
  if (light.type == LightType::directional) {
    out->to_light = -light.direction;
    out->distance = std::numeric_limits<float>::infinity();
    out->irradiance = light.intensity;
    return true;
  }
  const V3f offset = light.position - point;
  const float d2 = offset.length2();
  // A point at the light itself, or so close (d < 1.1e-19 m) that d^2 is subnormal and 1/d^2
  // overflows float, receives nothing: the inverse-square law has no finite value there, and
  // infinity times a zero intensity or cosine would be NaN.
  if (!(d2 >= FLT_MIN) || !std::isfinite(d2)) return false;
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
  // An irradiance beyond float's range (a bright light within a hair's breadth) cannot be
  // shaded finitely; the light is left out rather than poisoning the pixel.
  if (!std::isfinite(out->irradiance.x + out->irradiance.y + out->irradiance.z)) return false;
  return true;
}

}  // namespace prism
