// Emissive geometry as light: every triangle and analytic sphere whose material emits
// (EmbreeScene::emitters()) is an area light behind the contract of lights.h (sample, pdf,
// emitted, is_delta, power). Emission is glTF's emissiveFactor x emissiveTexture (with
// KHR_materials_emissive_strength folded into the factor by the loader), a radiance leaving
// both faces alike, as the other integrators show it when a ray meets the surface.
//
// Sampling: a triangle uniformly within the solid angle it subtends at the receiving point
// (Arvo's spherical triangle, renderer/sampling/spherical_triangle.h) when the point is closer
// to its plane than its longest edge and that angle is between 10^-3 sr and 6 sr, else
// uniformly by area; a sphere seen from outside uniformly
// within the cone it subtends (pbrt-v4's Sphere::Sample), from inside uniformly by area.
// Densities are per unit solid angle at the receiving point (docs/lights.md, "Area lights").
#pragma once

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>

#include "renderer/geometry/embree_scene.h"
#include "renderer/sampling/spherical_triangle.h"
#include "renderer/shading/lights.h"
#include "renderer/shading/material.h"

namespace prism {

// Shadow rays towards a point sampled on an area light stop short of it by this fraction of
// the distance: the light's own surface would block them at their very end.
inline constexpr float kAreaLightShadowRayEnd = 0.9999f;

// A triangle light as seen from one point: the spherical triangle and the solid angle it is
// sampled within, or a solid angle of 0 where it is sampled by area. Formed once per shading
// point, it serves both the choice among a few lights (EmitterSampler) and the chosen one's
// sample, which would otherwise build the same spherical triangle twice.
struct TriangleView {
  SphericalTriangle seen;
  double solid_angle = 0.0;
};

class AreaLight {
 public:
  // `material` is the primitive's (it must outlive the light).
  AreaLight(const EmissivePrimitive& primitive, const Material& material);

  bool is_delta() const { return false; }
  // A point on the light drawn from `u` in [0,1)^2 as seen from `point`: the direction, the
  // distance, the radiance the point leaves towards `point` with and the density per unit solid
  // angle. False when nothing can arrive (`point` on the light's plane, a zero density).
  bool sample(const Imath::V3f& point, const Imath::V2f& u, LightSample* out) const;
  // The same for a triangle, given view_from(point).
  bool sample(const Imath::V3f& point, const TriangleView& view, const Imath::V2f& u,
              LightSample* out) const;
  // A triangle as seen from `point` (spheres: a view of solid angle 0, unused).
  TriangleView view_from(const Imath::V3f& point) const;
  // Roughly the light a triangle brings to `point`: the luminance of its emission times the
  // solid angle it subtends there (A |cos| / d^2 at its centroid where it is sampled by area,
  // at most 2 pi). What the choice among a few lights is weighed by; it need not be exact,
  // only computed the same way wherever the choice's probability is.
  float choice_weight(const Imath::V3f& point, const TriangleView& view) const;
  // The density sample() gives direction `wi` (unit) from `point`; 0 when the ray misses.
  float pdf(const Imath::V3f& point, const Imath::V3f& wi) const;
  // The same for a ray from `point` known to reach the light at `on_light` (its hit): no
  // intersection test. A triangle's density is d^2 / (A |cos|), a sphere's the cone's.
  float pdf_towards(const Imath::V3f& point, const Imath::V3f& on_light) const;
  // The emission factor alone (untextured): the radiance a ray meets, textures aside.
  Imath::V3f emitted(const Imath::V3f& /*point*/, const Imath::V3f& /*direction*/) const {
    return factor_;
  }
  // W per channel: pi x area x the factor, from both faces of a triangle. Textures are not
  // integrated: the power only weighs the choice among lights.
  Imath::V3f power() const;
  float area() const { return area_; }
  const EmissivePrimitive& primitive() const { return primitive_; }

 private:
  // The radiance at a sampled point with barycentrics (b1, b2) of corners 1 and 2.
  Imath::V3f radiance_at(float b1, float b2) const;

  EmissivePrimitive primitive_;
  const Material* material_;
  Imath::V3f factor_;
  float brightness_ = 0.0f;  // the factor's luminance
  Imath::V3f normal_;  // triangle: unit, of the counter-clockwise face
  Imath::V3f centroid_{0.0f};  // triangle
  float area_ = 0.0f;
  float longest_edge2_ = 0.0f;  // triangle: its longest edge, squared
};

// The scene's area lights, one per emitter in EmbreeScene::emitters()'s order, so that a
// hit's SurfaceHit::emitter indexes it.
std::vector<AreaLight> make_area_lights(const std::vector<EmissivePrimitive>& emitters,
                                        const std::vector<Material>& materials,
                                        const Material& default_material);

}  // namespace prism
