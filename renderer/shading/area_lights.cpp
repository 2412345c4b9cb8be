#include "renderer/shading/area_lights.h"

#include <algorithm>
#include <cmath>

#include "renderer/math.h"
#include "renderer/sampling/spherical_triangle.h"
#include "renderer/sampling/warp.h"

namespace prism {
namespace {

// Below sin^2 of 1.5 degrees the cone's cosines lose their digits in 1 - cos: pbrt-v4's
// small-angle form takes over there.
constexpr float kSmallCone = 0.00068523f;

// A triangle subtending a solid angle in this range is sampled uniformly within it; below it
// (small or far away) area sampling is as good and cheaper, above it (a point almost on a vast
// triangle) the spherical construction runs out of digits. pbrt-v4 draws the line in the
// same places for the same reasons.
constexpr double kMinSphericalSolidAngle = 1e-3;
constexpr double kMaxSphericalSolidAngle = 6.0;

float safe_sqrt(float x) {
  return std::sqrt(std::max(0.0f, x));
}

// The solid angle the triangle subtends at `point` when it is sampled within it, with the
// triangle as seen from there; 0 when it is sampled by area instead.
// Area sampling's 1/d^2 varies little over a triangle far from `point` compared with its size
// (Cycles draws the line at the longest edge), and costs a tenth as much.
double spherical_sampling_area(const V3f& point, const V3f* corners, const V3f& normal,
                               float longest_edge2, SphericalTriangle* seen) {
  const float plane_distance = dot(point - corners[0], normal);
  if (plane_distance * plane_distance >= longest_edge2) return 0.0;
  if (!spherical_triangle_from(point, corners, seen)) return 0.0;
  const double area = spherical_triangle_area(*seen);
  return area >= kMinSphericalSolidAngle && area <= kMaxSphericalSolidAngle ? area : 0.0;
}

// The ray (point, wi) against the triangle, both faces (Moller-Trumbore): the distance and
// the barycentrics of corners 1 and 2, unclamped; false when the ray is parallel to it.
bool ray_triangle(const V3f& point, const V3f& wi, const V3f* c, float* t, float* b1, float* b2) {
  const V3f e1 = c[1] - c[0], e2 = c[2] - c[0];
  const V3f p = cross(wi, e2);
  const float det = dot(e1, p);
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const V3f s = point - c[0];
  const V3f q = cross(s, e1);
  *b1 = dot(s, p) * inv;
  *b2 = dot(wi, q) * inv;
  *t = dot(e2, q) * inv;
  return true;
}

}  // namespace

AreaLight::AreaLight(const EmissivePrimitive& primitive, const Material& material)
    : primitive_(primitive),
      material_(&material),
      factor_(material.emissive),
      brightness_(luminance(factor_)) {
  if (primitive_.shape == EmissivePrimitive::Shape::triangle) {
    const V3f n = cross(primitive_.corners[1] - primitive_.corners[0],
                        primitive_.corners[2] - primitive_.corners[0]);
    const float len = n.length();
    area_ = 0.5f * len;
    normal_ = len > 0.0f ? n / len : V3f(0.0f, 0.0f, 1.0f);
    centroid_ = (primitive_.corners[0] + primitive_.corners[1] + primitive_.corners[2]) / 3.0f;
    for (int i = 0; i < 3; ++i)
      longest_edge2_ = std::max(
          longest_edge2_, (primitive_.corners[(i + 1) % 3] - primitive_.corners[i]).length2());
  } else {
    area_ = 4.0f * kPi * primitive_.radius * primitive_.radius;
  }
}

V3f AreaLight::power() const {
  const float sides = primitive_.shape == EmissivePrimitive::Shape::triangle ? 2.0f : 1.0f;
  return factor_ * (kPi * area_ * sides);
}

V3f AreaLight::radiance_at(float b1, float b2) const {
  if (!material_->emissive_texture.texture) return factor_;
  SurfaceHit hit;
  hit.attributes = primitive_.attributes;
  hit.vertices[0] = primitive_.vertices[0];
  hit.vertices[1] = primitive_.vertices[1];
  hit.vertices[2] = primitive_.vertices[2];
  hit.barycentric_u = b1;
  hit.barycentric_v = b2;
  return emitted_radiance(*material_, hit);
}

TriangleView AreaLight::view_from(const V3f& point) const {
  TriangleView view;
  if (primitive_.shape == EmissivePrimitive::Shape::triangle)
    view.solid_angle =
        spherical_sampling_area(point, primitive_.corners, normal_, longest_edge2_, &view.seen);
  return view;
}

float AreaLight::choice_weight(const V3f& point, const TriangleView& view) const {
  if (view.solid_angle > 0.0) return brightness_ * static_cast<float>(view.solid_angle);
  const V3f offset = centroid_ - point;
  const float d2 = offset.length2();
  if (!(d2 > 0.0f)) return 0.0f;
  const float projected = area_ * std::fabs(dot(normal_, offset)) / (d2 * std::sqrt(d2));
  return brightness_ * std::min(projected, 2.0f * kPi);
}

bool AreaLight::sample(const V3f& point, const Imath::V2f& u, LightSample* out) const {
  return sample(point, view_from(point), u, out);
}

bool AreaLight::sample(const V3f& point, const TriangleView& view, const Imath::V2f& u,
                       LightSample* out) const {
  const V3f* c = primitive_.corners;
  V3f on_light;
  float b1 = 0.0f, b2 = 0.0f;
  if (primitive_.shape == EmissivePrimitive::Shape::triangle) {
    const SphericalTriangle& seen = view.seen;
    const double solid_angle = view.solid_angle;
    if (solid_angle > 0.0) {
      const Imath::V3d direction = sample_spherical_triangle(seen, solid_angle, u.x, u.y);
      const V3f wi(static_cast<float>(direction.x), static_cast<float>(direction.y),
                   static_cast<float>(direction.z));
      float t = 0.0f;
      if (material_->emissive_texture.texture) {
        if (!ray_triangle(point, wi, c, &t, &b1, &b2)) return false;
        // Rounding can put the direction a hair outside an edge: the point stays on the light.
        b1 = std::clamp(b1, 0.0f, 1.0f);
        b2 = std::clamp(b2, 0.0f, 1.0f - b1);
      } else {
        t = dot(c[0] - point, normal_) / dot(wi, normal_);
      }
      if (!(t > 0.0f) || !std::isfinite(t)) return false;
      out->wi = wi;
      out->distance = t;
      out->pdf = static_cast<float>(1.0 / solid_angle);
      out->radiance = radiance_at(b1, b2);
      return std::isfinite(out->pdf);
    }
    const float s = std::sqrt(u.x);
    const float b0 = 1.0f - s;
    b1 = u.y * s;
    b2 = 1.0f - b0 - b1;
    on_light = c[0] * b0 + c[1] * b1 + c[2] * b2;
  } else {
    const V3f to_centre = c[0] - point;
    const float dc2 = to_centre.length2();
    const float r = primitive_.radius;
    if (dc2 <= r * r) {
      // Inside: uniformly by area, every point of the sphere being visible.
      const float z = 1.0f - 2.0f * u.x;
      const float rr = safe_sqrt(1.0f - z * z);
      const float phi = 2.0f * kPi * u.y;
      on_light = c[0] + V3f(rr * std::cos(phi), rr * std::sin(phi), z) * r;
    } else {
      const float sin2_max = r * r / dc2;
      const float sin_max = std::sqrt(sin2_max);
      const float cos_max = safe_sqrt(1.0f - sin2_max);
      float one_minus_cos_max = 1.0f - cos_max;
      float cos_theta = (cos_max - 1.0f) * u.x + 1.0f;
      float sin2_theta = 1.0f - cos_theta * cos_theta;
      if (sin2_max < kSmallCone) {
        sin2_theta = sin2_max * u.x;
        cos_theta = std::sqrt(1.0f - sin2_theta);
        one_minus_cos_max = 0.5f * sin2_max;
      }
      // The angle at the centre between the direction to `point` and the sampled point.
      const float cos_alpha =
          sin2_theta / sin_max + cos_theta * safe_sqrt(1.0f - sin2_theta / (sin_max * sin_max));
      const float sin_alpha = safe_sqrt(1.0f - cos_alpha * cos_alpha);
      const float phi = 2.0f * kPi * u.y;
      const V3f axis = normalize(point - c[0]);
      const V3f n =
          from_local(V3f(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha), axis);
      on_light = c[0] + n * r;
      const V3f offset = on_light - point;
      const float d = offset.length();
      if (!(d > 0.0f)) return false;
      out->wi = offset / d;
      out->distance = d;
      out->pdf = 1.0f / (2.0f * kPi * one_minus_cos_max);
      out->radiance = factor_;
      return std::isfinite(out->pdf);
    }
  }
  const V3f offset = on_light - point;
  const float d2 = offset.length2();
  if (!(d2 > 0.0f)) return false;
  const float d = std::sqrt(d2);
  out->wi = offset / d;
  out->distance = d;
  const V3f n =
      primitive_.shape == EmissivePrimitive::Shape::triangle ? normal_ : normalize(on_light - c[0]);
  const float cos_light = std::fabs(dot(n, out->wi));
  if (!(cos_light > 0.0f) || !(area_ > 0.0f)) return false;
  out->pdf = d2 / (area_ * cos_light);
  out->radiance = radiance_at(b1, b2);
  return std::isfinite(out->pdf);
}

float AreaLight::pdf_towards(const V3f& point, const V3f& on_light) const {
  const V3f* c = primitive_.corners;
  if (primitive_.shape == EmissivePrimitive::Shape::sphere) {
    const float dc2 = (c[0] - point).length2();
    const float r = primitive_.radius;
    if (dc2 > r * r) {
      const float sin2_max = r * r / dc2;
      const float one_minus_cos_max =
          sin2_max < kSmallCone ? 0.5f * sin2_max : 1.0f - safe_sqrt(1.0f - sin2_max);
      return 1.0f / (2.0f * kPi * one_minus_cos_max);
    }
  }
  if (primitive_.shape == EmissivePrimitive::Shape::triangle) {
    SphericalTriangle seen;
    const double solid_angle = spherical_sampling_area(point, c, normal_, longest_edge2_, &seen);
    if (solid_angle > 0.0) return static_cast<float>(1.0 / solid_angle);
  }
  const V3f offset = on_light - point;
  const float d2 = offset.length2();
  if (!(d2 > 0.0f) || !(area_ > 0.0f)) return 0.0f;
  const V3f n =
      primitive_.shape == EmissivePrimitive::Shape::triangle ? normal_ : normalize(on_light - c[0]);
  const float cos_light = std::fabs(dot(n, offset)) / std::sqrt(d2);
  return cos_light > 0.0f ? d2 / (area_ * cos_light) : 0.0f;
}

float AreaLight::pdf(const V3f& point, const V3f& wi) const {
  const V3f* c = primitive_.corners;
  if (primitive_.shape == EmissivePrimitive::Shape::triangle) {
    float t = 0.0f, b1 = 0.0f, b2 = 0.0f;
    if (!ray_triangle(point, wi, c, &t, &b1, &b2)) return 0.0f;
    if (b1 < 0.0f || b1 > 1.0f || b2 < 0.0f || b1 + b2 > 1.0f || !(t > 0.0f)) return 0.0f;
    return pdf_towards(point, point + wi * t);
  }
  const V3f oc = point - c[0];
  const float r = primitive_.radius;
  const float b = dot(oc, wi);
  const float disc = b * b - (oc.length2() - r * r);
  if (disc < 0.0f) return 0.0f;
  const float root = std::sqrt(disc);
  const float t = oc.length2() > r * r ? -b - root : -b + root;
  if (!(t > 0.0f)) return 0.0f;
  return pdf_towards(point, point + wi * t);
}

std::vector<AreaLight> make_area_lights(const std::vector<EmissivePrimitive>& emitters,
                                        const std::vector<Material>& materials,
                                        const Material& default_material) {
  std::vector<AreaLight> lights;
  lights.reserve(emitters.size());
  for (const EmissivePrimitive& e : emitters) {
    const bool known = e.material >= 0 && static_cast<size_t>(e.material) < materials.size();
    lights.emplace_back(e, known ? materials[static_cast<size_t>(e.material)] : default_material);
  }
  return lights;
}

}  // namespace prism
