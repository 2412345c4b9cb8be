#include "renderer/shading/lights.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "renderer/image/colour.h"
#include "renderer/math.h"

namespace prism {

LightSource::LightSource(const Light& light, const ColourPipeline& colour) {
  type_ = light.type;
  const C3f c = colour.from_linear_rec709(light.colour);
  intensity_ = V3f(c.x, c.y, c.z) * light.intensity;
  position_ = V3f(light.position);
  direction_ = normalize(V3f(light.direction));
  range_ = static_cast<float>(light.range);
  cos_inner_ = static_cast<float>(std::cos(light.inner_cone_angle));
  cos_outer_ = static_cast<float>(std::cos(light.outer_cone_angle));
}

V3f LightSource::power(float scene_radius) const {
  switch (type_) {
    case LightType::point:
      return intensity_ * (4.0f * kPi);
    case LightType::spot:
      // pbrt-v4's SpotLight::Phi: the full cone plus half the smooth falloff band.
      return intensity_ * (2.0f * kPi * (1.0f - 0.5f * (cos_inner_ + cos_outer_)));
    case LightType::directional:
      break;
  }
  return intensity_ * (kPi * scene_radius * scene_radius);
}

bool LightSource::sample(const V3f& point, const Imath::V2f& /*u*/, LightSample* out) const {
  // A light that delivers nothing costs no shadow ray.
  if (dark()) return false;
  if (type_ == LightType::directional) {
    out->wi = -direction_;
    out->distance = std::numeric_limits<float>::infinity();
    out->pdf = 1.0f;
    out->radiance = intensity_;
    return true;
  }
  const V3f offset = position_ - point;
  const float d2 = offset.length2();
  // A point at the light itself, or so close (d < 1.1e-19 m) that d^2 is subnormal and 1/d^2
  // overflows float, receives nothing: the inverse-square law has no finite value there, and
  // infinity times a zero intensity or cosine would be NaN.
  if (!(d2 >= FLT_MIN) || !std::isfinite(d2)) return false;
  const float d = std::sqrt(d2);
  out->wi = offset / d;
  out->distance = d;
  float attenuation = 1.0f / d2;
  if (range_ > 0.0f) {
    // glTF's recommended smooth window: reaches zero at `range`, leaves 1/d^2 alone near.
    const float ratio = d / range_;
    const float window = std::clamp(1.0f - ratio * ratio * ratio * ratio, 0.0f, 1.0f);
    attenuation *= window * window;
  }
  if (type_ == LightType::spot) {
    const float cos_angle = dot(direction_, -out->wi);
    const float span = std::max(cos_inner_ - cos_outer_, 1e-4f);
    const float t = std::clamp((cos_angle - cos_outer_) / span, 0.0f, 1.0f);
    attenuation *= t * t;
  }
  if (attenuation <= 0.0f) return false;
  out->radiance = intensity_ * attenuation;
  out->pdf = 1.0f;
  // An irradiance beyond float's range (a bright light within a hair's breadth) cannot be
  // shaded finitely; the light is left out rather than poisoning the pixel.
  if (!std::isfinite(out->radiance.x + out->radiance.y + out->radiance.z)) return false;
  return true;
}

}  // namespace prism
