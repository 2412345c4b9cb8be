// The two layers glTF puts over its metallic-roughness material: KHR_materials_sheen's
// "Charlie" microfibre lobe (Estevez and Kulla, "Production Friendly Microfacet Sheen BRDF",
// 2017) and KHR_materials_clearcoat's second GGX lobe with a fixed F0 of 0.04 (ior 1.5), as
// functions of cosines so that eval, pdf and the sheen albedo table share them. How
// renderer/shading/bsdf.h layers them, and where it departs from the extensions' text to stay
// reciprocal, is in docs/materials.md ("Clearcoat and sheen").
#pragma once

#include <algorithm>
#include <cmath>

#include <Imath/ImathVec.h>

#include "renderer/math.h"
#include "renderer/sampling/warp.h"
#include "renderer/shading/ggx_albedo.h"
#include "renderer/shading/microfacet.h"

namespace prism {

// The clearcoat's reflectance at normal incidence, ((1.5 - 1) / (1.5 + 1))^2.
inline constexpr float kClearcoatF0 = 0.04f;
// The sheen's alpha = roughness^2 is taken no lower than this: below it the lobe is a ring
// of half vectors at the horizon a few float steps wide, and the albedo table cannot follow it.
inline constexpr float kMinSheenAlpha = 1e-2f;

// Schlick's Fresnel of the coat, F0 + (1 - F0)(1 - cos)^5.
inline float clearcoat_fresnel(float cos_theta) {
  return kClearcoatF0 + (1.0f - kClearcoatF0) * schlick_weight(cos_theta);
}

// D_charlie(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), for cos_h = N.H.
inline float charlie_d(float cos_h, float alpha) {
  const float inv_alpha = 1.0f / alpha;
  const float sin2 = std::max(0.0f, 1.0f - cos_h * cos_h);
  return (2.0f + inv_alpha) * std::pow(sin2, 0.5f * inv_alpha) * (0.5f * kInvPi);
}

// Estevez and Kulla's fit of the microfibre Lambda: L(x) = a / (1 + b x^c) + d x + e with the
// coefficients blended between their alpha = 0 and alpha = 1 values by (1 - alpha)^2.
inline float charlie_l(float x, float alpha) {
  const float t = (1.0f - alpha) * (1.0f - alpha);
  const auto blend = [t](float at_one, float at_zero) { return at_one + (at_zero - at_one) * t; };
  const float a = blend(21.5473f, 25.3245f), b = blend(3.82987f, 3.32435f);
  const float c = blend(0.19823f, 0.16801f), d = blend(-1.97760f, -1.27393f);
  const float e = blend(-4.32054f, -4.85967f);
  return a / (1.0f + b * std::pow(x, c)) + d * x + e;
}

inline float charlie_lambda(float cos_theta, float alpha) {
  const float c = std::clamp(cos_theta, 0.0f, 1.0f);
  return c < 0.5f ? std::exp(charlie_l(c, alpha))
                  : std::exp(2.0f * charlie_l(0.5f, alpha) - charlie_l(1.0f - c, alpha));
}

// The Charlie visibility G / (4 N.L N.V) with G = 1 / (1 + Lambda(V) + Lambda(L)): the
// extension's first choice, with which the albedo scaling below conserves energy.
inline float charlie_visibility(float cos_l, float cos_v, float alpha) {
  if (!(cos_l > 0.0f) || !(cos_v > 0.0f)) return 0.0f;
  // Summed in an order symmetric in V and L, so that f(wo, wi) == f(wi, wo) to the bit.
  const float g = 1.0f + (charlie_lambda(cos_v, alpha) + charlie_lambda(cos_l, alpha));
  return 1.0f / (g * 4.0f * cos_l * cos_v);
}

// What the sheen lobe D V (colour 1) reflects of a uniform radiance 1 towards cos_v, E(cos_v),
// by which KHR_materials_sheen scales the layers under it. Bilinear over a 32 x 32 table in
// (sqrt(cos_v), roughness), whose nodes crowd where E turns fastest, at grazing views,
// integrated on first use; `alpha` is the sheen's roughness^2. E exceeds 1 at grazing views
// below roughness 0.3 (the fitted Lambda lets the lobe gain energy there; docs/materials.md).
float sheen_albedo(float cos_v, float alpha);

// The same integral by quadrature (midpoint in cos_l and phi, `strata` x 2 `strata`), as the
// table is built: for the table and the tests.
float integrate_sheen_albedo(float cos_v, float alpha, int strata);

// The layers of one surface point, over the base of BsdfLobes. Every weight zero (the
// default): no layer, and Bsdf never calls into this.
struct SurfaceLayers {
  float clearcoat = 0.0f;        // clearcoatFactor x texture (R)
  float clearcoat_alpha = 0.0f;  // clearcoat roughness^2 (evaluated no lower than kMinGgxAlpha)
  // The coat's shading normal: the hit's, or clearcoatNormalTexture's; on the geometric
  // normal's side, as the base's.
  Imath::V3f clearcoat_normal{0.0f, 0.0f, 1.0f};
  // The Whitted integrators also trace the coat as a mirror (roughness <= kMirrorRoughness).
  bool clearcoat_mirror = false;
  // The coat's mirror carries all of its light: eval() leaves the coat's GGX lobe out
  // (Bsdf::without_traced_mirrors).
  bool clearcoat_mirror_only = false;
  Imath::V3f sheen_colour{0.0f};  // sheenColorFactor x texture, working space
  float sheen_alpha = kMinSheenAlpha;

  bool present() const {
    return clearcoat > 0.0f || sheen_colour.x > 0.0f || sheen_colour.y > 0.0f ||
           sheen_colour.z > 0.0f;
  }
  float sheen_max() const {
    return fmax_inline(sheen_colour.x, fmax_inline(sheen_colour.y, sheen_colour.z));
  }
  float coat_alpha() const { return fmax_inline(clearcoat_alpha, kMinGgxAlpha); }
  // The coat normal turned as the base's was: `n` is the base normal towards wo, `base` the
  // base's shading normal as stored.
  Imath::V3f coat_normal(const Imath::V3f& n, const Imath::V3f& base) const {
    return dot(n, base) >= 0.0f ? clearcoat_normal : -clearcoat_normal;
  }

  // What the coat lets through to the sheen, and the sheen to the base, for light arriving
  // along wi and leaving along wo: (1 - c max(F(Nc.V), F(Nc.L))) and
  // min(1 - s E(N.V), 1 - s E(N.L)), s = max(sheen colour). Both are the extensions' weights
  // made symmetric in V and L (the sheen's is the extension's own reciprocal form).
  float coat_transmittance(float cos_co, float cos_ci) const {
    if (!(clearcoat > 0.0f)) return 1.0f;
    return 1.0f - clearcoat * fmax_inline(clearcoat_fresnel(fmax_inline(0.0f, cos_co)),
                                          clearcoat_fresnel(fmax_inline(0.0f, cos_ci)));
  }
  float sheen_transmittance(float cos_o, float cos_i) const {
    const float s = sheen_max();
    if (!(s > 0.0f)) return 1.0f;
    return 1.0f - s * fmin_inline(1.0f, sheen_peak_albedo(cos_o, cos_i));
  }
  // max(E(N.V), E(N.L)): where it exceeds 1 the sheen lobe is divided by it, so that it
  // never reflects more than it receives (the extension's lobe elsewhere).
  float sheen_peak_albedo(float cos_o, float cos_i) const {
    return fmax_inline(sheen_albedo(fmax_inline(0.0f, cos_o), sheen_alpha),
                       sheen_albedo(fmax_inline(0.0f, cos_i), sheen_alpha));
  }
  // The same seen from wo alone, for the delta lobes and the albedo: the mirror direction
  // makes the two cosines equal.
  float view_transmittance(const Imath::V3f& wo, const Imath::V3f& n, const Imath::V3f& nc) const {
    const float cos_o = fmax_inline(0.0f, dot(n, wo)), cos_co = fmax_inline(0.0f, dot(nc, wo));
    return coat_transmittance(cos_co, cos_co) * sheen_transmittance(cos_o, cos_o);
  }

  // f of the layered surface, `base` the base's f(wo, wi), for wi on wo's side of `n`.
  Imath::V3f eval(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n,
                  const Imath::V3f& nc, const Imath::V3f& base) const {
    const float cos_o = fmax_inline(0.0f, dot(n, wo)), cos_i = dot(n, wi);
    Imath::V3f under = base;
    if (sheen_max() > 0.0f) {
      Imath::V3f h = wo + wi;
      const float h_len = h.length();
      h = h_len > 0.0f ? h / h_len : n;
      const float peak = sheen_peak_albedo(cos_o, cos_i);
      const float dv = charlie_d(dot(n, h), sheen_alpha) *
                       charlie_visibility(cos_i, cos_o, sheen_alpha) / fmax_inline(1.0f, peak);
      under = sheen_colour * dv + base * (1.0f - sheen_max() * fmin_inline(1.0f, peak));
    }
    if (!(clearcoat > 0.0f)) return under;
    const float cos_co = dot(nc, wo), cos_ci = dot(nc, wi);
    return under * coat_transmittance(cos_co, cos_ci) +
           Imath::V3f(clearcoat_mirror_only ? 0.0f : coat_f(wo, wi, nc));
  }

  // The coat lobe alone, c F(V.H) D Vis about the coat normal: F at V.H rather than the
  // extension's Nc.V keeps it reciprocal (the two agree where the lobe has its light).
  float coat_f(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& nc) const {
    const float cos_co = dot(nc, wo), cos_ci = dot(nc, wi);
    if (!(cos_co > 0.0f) || !(cos_ci > 0.0f)) return 0.0f;
    const Imath::V3f h = normalize(wo + wi);
    const float alpha = coat_alpha();
    // V.H and L.H are equal but round differently: their mean is the same either way round.
    const float cos_h = 0.5f * (dot(wo, h) + dot(wi, h));
    return clearcoat * clearcoat_fresnel(fmax_inline(0.0f, cos_h)) * ggx_d(dot(nc, h), alpha) *
           ggx_visibility(cos_ci, cos_co, alpha);
  }

  // The density of sample_coat: the coat's visible normals, G1(Nc.V) D(H) / (4 Nc.V).
  float coat_pdf(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& nc) const {
    const float cos_co = dot(nc, wo);
    if (!(cos_co > 0.0f)) return 0.0f;
    const Imath::V3f h = normalize(wo + wi);
    const float alpha = coat_alpha();
    return ggx_g1(cos_co, alpha) * ggx_d(dot(nc, h), alpha) / (4.0f * cos_co);
  }
  // A direction reflected about a visible normal of the coat; false when wo is below it.
  bool sample_coat(const Imath::V3f& wo, const Imath::V3f& nc, const Imath::V2f& u,
                   Imath::V3f* wi) const {
    const Imath::V3f wo_local = to_local(wo, nc);
    if (!(wo_local.z > 0.0f)) return false;
    const Imath::V3f h = sample_ggx_visible_normal(wo_local, coat_alpha(), u);
    *wi = from_local(h * (2.0f * wo_local.dot(h)) - wo_local, nc);
    return true;
  }

  // The coat's directional albedo towards wo: c (F0 E + (1 - F0) E_S) of the GGX table, or
  // the mirror's c F(Nc.V) where the Whitted integrators trace it as one.
  float coat_albedo(const Imath::V3f& wo, const Imath::V3f& nc) const {
    if (!(clearcoat > 0.0f)) return 0.0f;
    const float cos_co = std::clamp(dot(nc, wo), 0.0f, 1.0f);
    if (clearcoat_mirror) return clearcoat * clearcoat_fresnel(cos_co);
    const GgxAlbedo a = ggx_albedo(cos_co, coat_alpha());
    return clearcoat * (kClearcoatF0 * a.e + (1.0f - kClearcoatF0) * a.e_schlick);
  }

  // The albedo of the whole stack for a base albedo `base` (the base's own, delta lobes as
  // the caller's scope has them); `with_coat`: the coat is counted (a coat traced as a
  // mirror belongs to the delta lobes).
  Imath::V3f albedo(const Imath::V3f& wo, const Imath::V3f& n, const Imath::V3f& nc,
                    const Imath::V3f& base, bool with_coat) const {
    const float cos_o = std::clamp(dot(n, wo), 0.0f, 1.0f);
    const Imath::V3f under = sheen_colour * fmin_inline(1.0f, sheen_albedo(cos_o, sheen_alpha)) +
                             base * sheen_transmittance(cos_o, cos_o);
    const float cos_co = fmax_inline(0.0f, dot(nc, wo));
    const bool coat = with_coat || !clearcoat_mirror;
    return under * coat_transmittance(cos_co, cos_co) +
           Imath::V3f(coat ? coat_albedo(wo, nc) : 0.0f);
  }

  // How sample() shares its choice between the coat, the sheen and the base, in proportion
  // to their albedo estimates (`base`: the base's, before the layers over it take their part).
  struct Shares {
    float coat = 0.0f, sheen = 0.0f;
  };
  Shares shares(const Imath::V3f& wo, const Imath::V3f& n, const Imath::V3f& nc, float base) const {
    const float cos_o = std::clamp(dot(n, wo), 0.0f, 1.0f);
    const float cos_co = fmax_inline(0.0f, dot(nc, wo));
    const float through_coat = coat_transmittance(cos_co, cos_co);
    const float coat = clearcoat_mirror ? 0.0f : coat_albedo(wo, nc);
    const float sheen =
        through_coat * sheen_max() * fmin_inline(1.0f, sheen_albedo(cos_o, sheen_alpha));
    const float rest = through_coat * sheen_transmittance(cos_o, cos_o) * fmax_inline(0.0f, base);
    const float total = coat + sheen + rest;
    if (!(total > 0.0f)) return {};
    return {coat / total, sheen / total};
  }
};

}  // namespace prism
