// The BSDF at a surface point: what a material does with light, as an integrator asks it
// (pbrt-v4's base/bxdf.h contract): eval, sample, pdf and lobe flags, all in world space with
// directions pointing away from the surface (wo towards the viewer, wi towards the light).
//
// Today's lobes are the lecture's local model mapped from glTF (docs/materials.md):
//   Lambert diffuse rho_d / pi + normalised Phong k_s (n + 2) / (2 pi) (R.V)^n
// and two delta lobes the Whitted integrator traces deterministically: a mirror weighted by
// Schlick's Fresnel with F0 = k_s (roughness <= kMirrorRoughness), and a smooth dielectric
// that reflects F and refracts 1 - F (exact Fresnel, the material's ior), tinted by the base
// colour on entry. A path tracer samples all of them through sample(); the Whitted
// integrators ask eval() per light and specular_lobes() for their recursive rays.
//
// Every method computes exactly what the integrators computed inline before it existed, in
// the same order, so images are bit for bit those of the hand-written code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Imath/ImathVec.h>

#include "renderer/math.h"
#include "renderer/sampling/warp.h"

namespace prism {

// Which kinds of scattering a BSDF has, as bits (pbrt's BxDFFlags).
enum BsdfLobe : uint8_t {
  kDiffuseReflection = 1u << 0,
  kGlossyReflection = 1u << 1,
  kSpecularReflection = 1u << 2,    // a delta lobe: the mirror, or the dielectric's reflection
  kSpecularTransmission = 1u << 3,  // a delta lobe: the dielectric's refraction
};
inline constexpr uint8_t kSpecularLobes = kSpecularReflection | kSpecularTransmission;

// The lobes' parameters at one point, in the working colour space.
struct BsdfLobes {
  Imath::V3f diffuse_albedo{0.0f};   // rho_d; the BRDF is rho_d / pi
  Imath::V3f specular_colour{0.0f};  // k_s: reflectance at normal incidence (F0)
  float phong_exponent = 0.0f;       // n of the normalised lobe (n + 2) / (2 pi) (R.V)^n
  bool mirror = false;               // the specular reflection lobe is present
  float transmission = 0.0f;         // weight of the smooth dielectric part
  float ior = 1.5f;
  Imath::V3f transmission_tint{1.0f};  // colour of light passing in (the base colour)
};

// One direction a delta lobe scatters into, with its weight (f cos / pdf): the radiance L
// arriving along wi contributes hadamard(colour, L) * scale. Colour and scale are kept apart
// so that the product rounds as the Whitted integrator has always rounded it.
struct SpecularLobe {
  Imath::V3f wi;
  Imath::V3f colour;
  float scale = 1.0f;
  bool transmission = false;  // wi is on the far side of the surface
  Imath::V3f weight() const { return colour * scale; }
};

struct BsdfSample {
  Imath::V3f wi;
  Imath::V3f f;      // the BSDF's value (for a delta lobe: the weight times pdf / |cos|)
  float pdf = 0.0f;  // per unit solid angle; for a delta lobe, the probability of choosing it
  uint8_t lobe = 0;  // the one BsdfLobe bit sampled
  bool specular() const { return (lobe & kSpecularLobes) != 0; }
};

class Bsdf {
 public:
  Bsdf() = default;
  // `shading_normal` unit, on the geometric normal's side.
  Bsdf(const Imath::V3f& shading_normal, const BsdfLobes& lobes)
      : normal_(shading_normal), lobes_(lobes) {}

  const BsdfLobes& lobes() const { return lobes_; }
  const Imath::V3f& shading_normal() const { return normal_; }
  // The shading normal on wo's side: the hemisphere the reflection lobes live in.
  Imath::V3f normal_towards(const Imath::V3f& wo) const { return face_forward(normal_, wo); }

  uint8_t flags() const {
    uint8_t f = 0;
    if (has(lobes_.diffuse_albedo)) f |= kDiffuseReflection;
    if (has(lobes_.specular_colour)) f |= kGlossyReflection;
    if (lobes_.mirror && lobes_.transmission < 1.0f) f |= kSpecularReflection;
    if (lobes_.transmission > 0.0f) f |= kSpecularReflection | kSpecularTransmission;
    return f;
  }

  // f(wo, wi) of the non-delta lobes, for wi on wo's side of the shading normal `n`
  // (normal_towards(wo)); zero below it. The Phong term uses R = reflect(-wi, n).
  Imath::V3f eval(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    if (dot(n, wi) <= 0.0f) return Imath::V3f(0.0f);
    const float lobe_norm = (lobes_.phong_exponent + 2.0f) * (0.5f * kInvPi);
    const Imath::V3f reflected = reflect(-wi, n);
    const float cos_view = std::fmax(0.0f, dot(reflected, wo));
    const float specular = lobes_.phong_exponent > 0.0f
                               ? lobe_norm * std::pow(cos_view, lobes_.phong_exponent)
                               : lobe_norm;
    return lobes_.diffuse_albedo * kInvPi + lobes_.specular_colour * specular;
  }
  Imath::V3f eval(const Imath::V3f& wo, const Imath::V3f& wi) const {
    return eval(wo, wi, normal_towards(wo));
  }

  // The density sample() picks wi with among its non-delta lobes (the delta lobes' share
  // of the choice excluded, as pbrt's pdf does).
  float pdf(const Imath::V3f& wo, const Imath::V3f& wi) const {
    const Imath::V3f n = normal_towards(wo);
    const float cos_wi = dot(n, wi);
    if (cos_wi <= 0.0f) return 0.0f;
    const LobeChoice c = choice(wo, n);
    float density = c.diffuse * cos_wi * kInvPi;
    if (c.glossy > 0.0f) density += c.glossy * phong_pdf(wo, wi, n);
    return density;
  }

  // Picks a lobe with `u_lobe` (in proportion to its albedo estimate) and a direction with
  // `u`; false when nothing scatters or the direction falls below the surface.
  bool sample(const Imath::V3f& wo, float u_lobe, const Imath::V2f& u, bool back_face,
              BsdfSample* out) const {
    const Imath::V3f n = normal_towards(wo);
    const LobeChoice c = choice(wo, n);
    if (u_lobe < c.specular) {
      SpecularLobe lobes[2];
      const int count = specular_lobes<true, true>(wo, n, back_face, lobes);
      float total = 0.0f;
      for (int i = 0; i < count; ++i) total += luminance(lobes[i].weight());
      if (!(total > 0.0f)) return false;
      // Among the delta lobes in proportion to their weights: unbiased for any choice.
      float pick = (u_lobe / c.specular) * total;
      int k = 0;
      while (k + 1 < count && pick >= luminance(lobes[k].weight()))
        pick -= luminance(lobes[k++].weight());
      const float p = c.specular * luminance(lobes[k].weight()) / total;
      const float cos_wi = std::fabs(dot(n, lobes[k].wi));
      out->wi = lobes[k].wi;
      out->pdf = p;
      out->f = cos_wi > 0.0f ? lobes[k].weight() * (p / cos_wi) : Imath::V3f(0.0f);
      out->lobe = lobes[k].transmission ? kSpecularTransmission : kSpecularReflection;
      return cos_wi > 0.0f;
    }
    const float u_rest = (u_lobe - c.specular) / std::max(1e-30f, 1.0f - c.specular);
    Imath::V3f wi;
    if (u_rest * (c.diffuse + c.glossy) < c.diffuse || c.glossy <= 0.0f) {
      wi = from_local(square_to_cosine_hemisphere(u), n);
      out->lobe = kDiffuseReflection;
    } else {
      const Imath::V3f r = reflect(-wo, n);
      wi = from_local(square_to_cosine_power(u, lobes_.phong_exponent), r);
      out->lobe = kGlossyReflection;
    }
    if (dot(n, wi) <= 0.0f) return false;
    out->wi = wi;
    out->f = eval(wo, wi, n);
    out->pdf = pdf(wo, wi);
    return out->pdf > 0.0f;
  }

  // The delta lobes' directions and weights at the shading normal `n` (normal_towards(wo)),
  // transmission first: the refracted ray (unless total internal reflection) and one
  // reflection ray carrying both the mirror's and the dielectric's reflection. `back_face`:
  // wo is inside the dielectric. Mirror and Transmission say which lobes to consider, so a
  // caller specialised on the scene leaves out what no surface has. Returns the count.
  template <bool Mirror, bool Transmission>
  int specular_lobes(const Imath::V3f& wo, const Imath::V3f& n, bool back_face,
                     SpecularLobe* out) const {
    const float cos_i = std::fmin(1.0f, std::fmax(0.0f, dot(wo, n)));
    Imath::V3f reflect_weight(0.0f);
    int count = 0;
    if constexpr (Mirror) {
      if (lobes_.mirror && lobes_.transmission < 1.0f) {
        const Imath::V3f f0 = lobes_.specular_colour;
        reflect_weight +=
            (f0 + (Imath::V3f(1.0f) - f0) * schlick_weight(cos_i)) * (1.0f - lobes_.transmission);
      }
    }
    if constexpr (Transmission) {
      if (lobes_.transmission > 0.0f) {
        // eta = n_transmitted / n_incident: entering from the front, or leaving from inside.
        const float eta = back_face ? 1.0f / lobes_.ior : lobes_.ior;
        const float fresnel = fresnel_dielectric(cos_i, eta);
        reflect_weight += Imath::V3f(lobes_.transmission * fresnel);
        Imath::V3f refracted;
        if (fresnel < 1.0f && refract(-wo, n, eta, &refracted)) {
          const Imath::V3f tint = back_face ? Imath::V3f(1.0f) : lobes_.transmission_tint;
          out[count++] = {refracted, tint, lobes_.transmission * (1.0f - fresnel), true};
        }
      }
    }
    if (reflect_weight.x > 0.0f || reflect_weight.y > 0.0f || reflect_weight.z > 0.0f)
      out[count++] = {normalize(reflect(-wo, n)), reflect_weight, 1.0f, false};
    return count;
  }

 private:
  // How sample() splits its choice: the delta lobes' share first, then diffuse and glossy in
  // proportion to their albedos.
  struct LobeChoice {
    float specular = 0.0f, diffuse = 0.0f, glossy = 0.0f;
  };
  LobeChoice choice(const Imath::V3f& wo, const Imath::V3f& n) const {
    SpecularLobe lobes[2];
    float specular = 0.0f;
    const int count = specular_lobes<true, true>(wo, n, false, lobes);
    for (int i = 0; i < count; ++i) specular += luminance(lobes[i].weight());
    const float diffuse = luminance(lobes_.diffuse_albedo);
    const float glossy = luminance(lobes_.specular_colour);
    const float total = specular + diffuse + glossy;
    if (!(total > 0.0f)) return {};
    const float rest = 1.0f - specular / total;
    const float reflect_total = diffuse + glossy;
    if (!(reflect_total > 0.0f)) return {specular / total, 0.0f, 0.0f};
    return {specular / total, rest * diffuse / reflect_total, rest * glossy / reflect_total};
  }
  // Density of the Phong lobe's sampling: cos^n about the mirror direction R of wo.
  float phong_pdf(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    const float cos_alpha = dot(reflect(-wo, n), wi);
    if (cos_alpha <= 0.0f) return 0.0f;
    return cosine_power_pdf(cos_alpha, lobes_.phong_exponent);
  }
  static float schlick_weight(float cos_theta) {
    const float m = std::fmax(0.0f, 1.0f - cos_theta);
    return (m * m) * (m * m) * m;
  }
  static bool has(const Imath::V3f& c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }
  static float luminance(const Imath::V3f& c) {
    return std::fmax(0.0f, 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
  }

  Imath::V3f normal_{0.0f, 0.0f, 1.0f};
  BsdfLobes lobes_;
};

}  // namespace prism
