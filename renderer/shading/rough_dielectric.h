// A rough dielectric interface, GGX microfacets with exact Fresnel reflection and
// transmission (Walter, Marschner, Li and Torrance, "Microfacet Models for Refraction through
// Rough Surfaces", EGSR 2007), sampled by the visible normals (Heitz 2018) as pbrt-v4's
// DielectricBxDF samples it: a microfacet normal m from D_wo(m), then reflection with
// probability F(wo.m) and refraction otherwise. docs/materials.md has the formulas.
//
// Everything is in the local frame whose +z is the shading normal on wo's side (wo.z > 0):
// reflection has wi.z > 0, transmission wi.z < 0. `eta` is the index below over the index
// above (the side wi enters over wo's side): the material's ior entering from outside, 1/ior
// leaving. Transmitted radiance is scaled by 1/eta^2 (pbrt's TransportMode::Radiance: the
// integrator carries radiance from the camera), so f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2.
//
// Thin-walled (KHR_materials_transmission without KHR_materials_volume): the surface is two
// interfaces back to back with nothing between, so light leaves in the direction it came,
// spread by the roughness. Its transmission lobe is the reflection lobe mirrored through the
// tangent plane (glTF's specular_btdf, with H_T = normalize(V + L - 2 (N.L) N)), weighted by
// 1 - F, and has no radiance scaling (the media on both sides are the same).
#pragma once

#include <cmath>

#include <Imath/ImathVec.h>

#include "renderer/math.h"
#include "renderer/shading/microfacet.h"

namespace prism {

struct RoughDielectricSample {
  Imath::V3f wi;  // local frame
  float f = 0.0f;
  float pdf = 0.0f;
  bool transmission = false;
};

struct RoughDielectric {
  float alpha = 1.0f;  // at least kMinGgxAlpha
  float eta = 1.5f;    // n below / n above; not 1 unless thin-walled (the lobe is then a delta)
  bool thin_walled = false;

  // f(wo, wi), both unit, wo.z > 0.
  float eval(const Imath::V3f& wo, const Imath::V3f& wi) const {
    Microfacet m;
    if (!microfacet(wo, wi, &m)) return 0.0f;
    const float cos_o = wo.z, cos_i = std::fabs(wi.z);
    const float dv = ggx_d(m.normal.z, alpha) * ggx_visibility(cos_i, cos_o, alpha);
    const float fresnel = fresnel_dielectric(m.cos_o, eta);
    if (!m.transmission) return dv * fresnel;
    if (thin_walled) return dv * (1.0f - fresnel);
    // 4 D V (1 - F) |wi.m| |wo.m| / (wo.m + eta wi.m)^2: Walter's BTDF, radiance-scaled.
    const float denom = m.cos_o + eta * m.cos_i;
    return 4.0f * dv * (1.0f - fresnel) * std::fabs(m.cos_i) * m.cos_o / (denom * denom);
  }

  // The density sample() draws wi with, per unit solid angle.
  float pdf(const Imath::V3f& wo, const Imath::V3f& wi) const {
    Microfacet m;
    if (!microfacet(wo, wi, &m)) return 0.0f;
    const float fresnel = fresnel_dielectric(m.cos_o, eta);
    const float visible = visible_normal_pdf(wo, m);
    if (!m.transmission) return visible * fresnel / (4.0f * m.cos_o);
    if (thin_walled) return visible * (1.0f - fresnel) / (4.0f * m.cos_o);
    return visible * (1.0f - fresnel) * refraction_jacobian(m);
  }

  // wi from u_choice (reflect or refract) and u (the microfacet normal); false when the
  // direction falls on the wrong side (a microfacet seen but scattering under the horizon).
  bool sample(const Imath::V3f& wo, float u_choice, const Imath::V2f& u,
              RoughDielectricSample* out) const {
    if (!(wo.z > 0.0f)) return false;
    const Imath::V3f normal = sample_ggx_visible_normal(wo, alpha, u);
    const float cos_o = dot(wo, normal);
    if (!(cos_o > 0.0f)) return false;
    const float fresnel = fresnel_dielectric(cos_o, eta);
    Imath::V3f wi;
    const bool transmission = u_choice >= fresnel;
    if (!transmission || thin_walled) {
      wi = normalize(normal * (2.0f * cos_o) - wo);
      if (wi.z <= 0.0f) return false;
      if (transmission) wi.z = -wi.z;
    } else if (!refract(-wo, normal, eta, &wi) || wi.z >= 0.0f) {
      return false;
    }
    out->wi = wi;
    out->transmission = transmission;
    out->f = eval(wo, wi);
    out->pdf = pdf(wo, wi);
    return out->pdf > 0.0f && out->f > 0.0f;
  }

 private:
  struct Microfacet {
    Imath::V3f normal;
    float cos_o = 0.0f, cos_i = 0.0f;  // wo.m, wi.m (for the refracting transmission, < 0)
    bool transmission = false;
  };

  // The microfacet normal that scatters wo into wi: the half vector for reflection and for
  // the thin wall's mirrored transmission, the generalized half vector wo + eta wi (turned
  // to +z) for refraction. False for wi on the horizon, wo at grazing, or a microfacet
  // that faces away from either direction.
  bool microfacet(const Imath::V3f& wo, const Imath::V3f& wi, Microfacet* m) const {
    if (!(wo.z > 0.0f) || wi.z == 0.0f) return false;
    m->transmission = wi.z < 0.0f;
    Imath::V3f h;
    if (!m->transmission || thin_walled) {
      h = wo + Imath::V3f(wi.x, wi.y, std::fabs(wi.z));
    } else {
      h = wo + wi * eta;
      if (h.z < 0.0f) h = -h;
    }
    const float len2 = h.length2();
    if (!(len2 > 0.0f)) return false;
    h /= std::sqrt(len2);
    m->normal = h;
    m->cos_o = dot(wo, h);
    m->cos_i = m->transmission && !thin_walled ? dot(wi, h)
                                               : dot(Imath::V3f(wi.x, wi.y, std::fabs(wi.z)), h);
    if (!(m->cos_o > 0.0f)) return false;
    if (m->transmission && !thin_walled) return m->cos_i < 0.0f;
    return m->cos_i > 0.0f;
  }

  // D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z: the density of m among the visible normals.
  float visible_normal_pdf(const Imath::V3f& wo, const Microfacet& m) const {
    return ggx_g1(wo.z, alpha) * m.cos_o * ggx_d(m.normal.z, alpha) / wo.z;
  }

  // d(omega_m)/d(omega_i) for refraction: |wi.m| / (wi.m + wo.m / eta)^2.
  float refraction_jacobian(const Microfacet& m) const {
    const float denom = m.cos_i + m.cos_o / eta;
    return std::fabs(m.cos_i) / (denom * denom);
  }
};

}  // namespace prism
