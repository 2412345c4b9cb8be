// The BSDF at a surface point: what a material does with light, as an integrator asks it
// (pbrt-v4's base/bxdf.h contract): eval, sample, pdf and lobe flags, all in world space with
// directions pointing away from the surface (wo towards the viewer, wi towards the light).
//
// The lobes are glTF 2.0's (specification Appendix B, docs/materials.md): a specular layer
// (GGX, height-correlated Smith visibility, Schlick's Fresnel; conductor_fresnel for the
// metal part, fresnel_mix for the dielectric part with KHR_materials_specular's F0 and F90)
// over a Lambert base. With BrdfModel::lecture the layer's glossy lobe is the lecture's
// normalised Phong lobe k_s (n + 2) / (2 pi) (R.V)^n instead, and the diffuse base is
// rho_d (1 - max F0) / pi: the model Prism started from, kept for comparison.
//
// Two delta lobes are traced by integrators that follow mirror rays: the layer's mirror
// reflection where the surface is smooth (roughness <= kMirrorRoughness), weighted by the
// layer's own Schlick Fresnel at the viewing angle, and the transmissive part, a smooth
// dielectric that reflects F and refracts 1 - F (exact Fresnel with the material's ior),
// tinted by the base colour on entry. eval() keeps the layer's GGX lobe on smooth surfaces
// too: it is how a punctual light, which no mirror ray can find, shows its highlight.
//
// Under the path tracer (path_traced()) a rough transmissive part is instead the rough
// dielectric of rough_dielectric.h: glossy reflection and transmission with exact Fresnel,
// refracting for KHR_materials_volume materials, passing straight through for thin walls.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Imath/ImathVec.h>

#include "renderer/enum_names.h"
#include "renderer/math.h"
#include "renderer/sampling/warp.h"
#include "renderer/shading/clearcoat_sheen.h"
#include "renderer/shading/ggx_albedo.h"
#include "renderer/shading/microfacet.h"
#include "renderer/shading/rough_dielectric.h"

namespace prism {

// Which kinds of scattering a BSDF has, as bits (pbrt's BxDFFlags).
enum BsdfLobe : uint8_t {
  kDiffuseReflection = 1u << 0,
  kGlossyReflection = 1u << 1,
  kSpecularReflection = 1u << 2,    // a delta lobe: the mirror, or the dielectric's reflection
  kSpecularTransmission = 1u << 3,  // a delta lobe: the dielectric's refraction
  kGlossyTransmission = 1u << 4,    // the rough dielectric's (rough_dielectric.h), path only
};
inline constexpr uint8_t kSpecularLobes = kSpecularReflection | kSpecularTransmission;

// Which glossy lobe eval() evaluates: glTF's GGX (the default), or the lecture's Phong lobe.
enum class BrdfModel : uint8_t { gltf, lecture };
inline constexpr EnumName<BrdfModel> kBrdfModelNames[] = {{BrdfModel::gltf, "gltf"},
                                                          {BrdfModel::lecture, "lecture"}};
constexpr std::span<const EnumName<BrdfModel>> enum_names(BrdfModel) {
  return kBrdfModelNames;
}

// The lobes' parameters at one point, in the working colour space. With metallic m,
// transmission T and base colour rho (renderer/shading/material.cpp fills them):
struct BsdfLobes {
  BrdfModel model = BrdfModel::gltf;
  Imath::V3f diffuse_albedo{0.0f};  // rho (1 - m)(1 - T): the base under the dielectric layer
  // The dielectric's layer, F = F0 + (F90 - F0)(1 - v.h)^5: the diffuse base receives
  // 1 - max(F) of the light (glTF's fresnel_mix with KHR_materials_specular).
  Imath::V3f dielectric_f0{0.0f};
  float dielectric_f90 = 0.0f;
  // The whole specular layer, (1 - m) dielectric + m (rho, 1): conductor_fresnel and
  // fresnel_mix blended by m, as glTF's mix(dielectric_brdf, metal_brdf, metallic).
  Imath::V3f specular_f0{0.0f};
  Imath::V3f specular_f90{0.0f};
  float alpha = 1.0f;           // GGX alpha = roughness^2
  float phong_exponent = 0.0f;  // the lecture model's n
  bool mirror = false;          // the layer's delta reflection is present
  // The mirror carries all of the layer's light: eval() leaves the GGX lobe out (path_traced()).
  bool mirror_only = false;
  float transmission = 0.0f;  // (1 - m) T: weight of the smooth dielectric part
  float ior = 1.5f;
  Imath::V3f transmission_tint{1.0f};  // colour of light passing in (the base colour)
  // KHR_materials_sheen and _clearcoat over all of the above (clearcoat_sheen.h).
  SurfaceLayers layers;
  // No KHR_materials_volume (or thicknessFactor 0): the rough lobe passes light straight
  // through instead of refracting it (rough_dielectric.h).
  bool thin_walled = true;
  // Set by Bsdf::path_traced: the transmissive part is the rough dielectric, not the delta
  // lobes, and wo is inside it (back_face).
  bool rough_transmission = false;
  bool back_face = false;
  // Set by Bsdf::path_traced for transmissive materials: the layer's GGX lobe covers the opaque
  // part only, the dielectric (rough, or delta at ior 1) reflecting for itself.
  bool opaque_layer = false;
};

// Which lobes an albedo covers: an integrator that traces the delta lobes itself asks for
// the rest only, so that each lobe's light is counted once.
enum class AlbedoScope : uint8_t { all_lobes, without_delta_lobes };

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
  Imath::V3f f;      // the BSDF's value (for a delta lobe: its weight / |cos|, pbrt's convention)
  float pdf = 0.0f;  // per unit solid angle; for a delta lobe, the probability of choosing it
  uint8_t lobe = 0;  // the one BsdfLobe bit sampled
  bool specular() const { return (lobe & kSpecularLobes) != 0; }
};

class Bsdf {
 public:
  Bsdf() = default;
  // `shading_normal` unit, on the geometric normal's side.
  Bsdf(const Imath::V3f& shading_normal, const BsdfLobes& lobes)
      : normal_(shading_normal),
        lobes_(lobes),
        layered_(lobes.layers.present()),
        lambertian_(is_lambertian(lobes, layered_)) {
    fix_choice();
  }

  const BsdfLobes& lobes() const { return lobes_; }

  // The BSDF as a path tracer samples it, where every lobe's light is found by some ray and
  // none may be counted twice: the layer is a delta mirror only where GGX cannot be evaluated
  // (alpha below kMinGgxAlpha: glTF's alpha = 0, a perfect mirror), and then the mirror alone,
  // eval() and pdf() leaving its GGX lobe out; everywhere else the layer is its GGX lobe,
  // sampled by the visible normals. The Whitted integrators' mirror above kMinGgxAlpha (up to
  // kMirrorRoughness) is an approximation they make, not the material.
  //
  // The transmissive part is likewise the smooth dielectric's delta lobes below kMinGgxAlpha
  // (and at ior 1, where refraction bends nothing and the rough lobe is a delta too) and the
  // rough dielectric above, with the layer's GGX lobe then covering only the opaque part
  // (mirror_f0, mirror_f90) as the dielectric reflects for itself. `back_face`: wo is inside.
  Bsdf path_traced(bool back_face = false) const {
    Bsdf b = *this;
    b.lobes_.mirror = lobes_.model == BrdfModel::gltf && lobes_.alpha < kMinGgxAlpha;
    b.lobes_.mirror_only = b.lobes_.mirror;
    b.lobes_.layers.clearcoat_mirror = false;  // the coat is its GGX lobe, as the base
    b.lobes_.rough_transmission = lobes_.model == BrdfModel::gltf && lobes_.transmission > 0.0f &&
                                  lobes_.alpha >= kMinGgxAlpha &&
                                  (lobes_.ior != 1.0f || lobes_.thin_walled);
    b.lobes_.back_face = back_face;
    b.lobes_.opaque_layer = lobes_.model == BrdfModel::gltf && lobes_.transmission > 0.0f;
    b.fix_choice();
    return b;
  }
  // The same lobes for an integrator that traces the delta lobes itself (whitted's mirror
  // rays), as an area light's sample sees them: a smooth layer or coat traced as a mirror
  // carries all of that lobe's light, so eval() leaves its GGX lobe out, and an emitter the
  // mirror ray meets is not counted again by the sample. For eval() only.
  Bsdf without_traced_mirrors() const {
    Bsdf b = *this;
    b.lobes_.mirror_only = lobes_.mirror;
    b.lobes_.layers.clearcoat_mirror_only = lobes_.layers.clearcoat_mirror;
    return b;
  }
  bool has_traced_mirror() const { return lobes_.mirror || lobes_.layers.clearcoat_mirror; }
  const Imath::V3f& shading_normal() const { return normal_; }
  // The same lobes about another shading normal (unit, on its geometric normal's side).
  Bsdf with_shading_normal(const Imath::V3f& shading_normal) const {
    Bsdf b = *this;
    b.normal_ = shading_normal;
    return b;
  }
  // The shading normal on wo's side: the hemisphere the reflection lobes live in.
  Imath::V3f normal_towards(const Imath::V3f& wo) const { return face_forward(normal_, wo); }

  uint8_t flags() const {
    uint8_t f = 0;
    if (has(lobes_.diffuse_albedo)) f |= kDiffuseReflection;
    if (has(lobes_.specular_f90) || has(lobes_.specular_f0)) f |= kGlossyReflection;
    if (lobes_.mirror && has(mirror_f90())) f |= kSpecularReflection;
    if (lobes_.rough_transmission)
      f |= kGlossyReflection | kGlossyTransmission;
    else if (lobes_.transmission > 0.0f)
      f |= kSpecularReflection | kSpecularTransmission;
    if (layered_) {
      f |= kGlossyReflection;
      if (lobes_.layers.clearcoat_mirror && lobes_.layers.clearcoat > 0.0f)
        f |= kSpecularReflection;
    }
    return f;
  }

  // f(wo, wi) of the non-delta lobes, for wi on wo's side of the shading normal `n`
  // (normal_towards(wo)); below it, only the rough dielectric's transmission.
  Imath::V3f eval(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    if (!layered_) return eval_base(wo, wi, n);
    // Light the rough dielectric passes through crosses the layers on wo's side only.
    if (dot(n, wi) <= 0.0f)
      return eval_base(wo, wi, n) * lobes_.layers.view_transmittance(wo, n, coat_normal(n));
    return lobes_.layers.eval(wo, wi, n, coat_normal(n), eval_base(wo, wi, n));
  }
  Imath::V3f eval(const Imath::V3f& wo, const Imath::V3f& wi) const {
    return eval(wo, wi, normal_towards(wo));
  }

  // The base's f alone, without the layers over it.
  Imath::V3f eval_base(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    const float cos_i = dot(n, wi);
    if (lambertian_) return cos_i > 0.0f ? lobes_.diffuse_albedo * kInvPi : Imath::V3f(0.0f);
    if (lobes_.rough_transmission) {
      const Imath::V3f transmitted = rough_dielectric_eval(wo, wi, n);
      if (cos_i <= 0.0f) return transmitted;
      return transmitted + eval_reflection(wo, wi, n, cos_i, mirror_f0(), mirror_f90());
    }
    if (cos_i <= 0.0f) return Imath::V3f(0.0f);
    if (lobes_.opaque_layer) return eval_reflection(wo, wi, n, cos_i, mirror_f0(), mirror_f90());
    return eval_reflection(wo, wi, n, cos_i, lobes_.specular_f0, lobes_.specular_f90);
  }

  // The reflection lobes' f: the diffuse base and the layer's GGX lobe with the Fresnel
  // of `f0`, `f90` (the whole layer's, or the opaque part's beside a rough dielectric).
  Imath::V3f eval_reflection(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n,
                             float cos_i, const Imath::V3f& f0, const Imath::V3f& f90) const {
    if (lobes_.model == BrdfModel::lecture) return eval_lecture(wo, wi, n);
    const float cos_o = fmax_inline(0.0f, dot(n, wo));
    Imath::V3f h = wo + wi;
    const float h_len = h.length();
    // wi opposite wo (both grazing): the half vector is the normal's limit.
    h = h_len > 0.0f ? h / h_len : n;
    const float weight = schlick_weight(fmax_inline(0.0f, dot(wo, h)));
    const Imath::V3f fresnel_d =
        lobes_.dielectric_f0 + (Imath::V3f(lobes_.dielectric_f90) - lobes_.dielectric_f0) * weight;
    const Imath::V3f diffuse = lobes_.diffuse_albedo * (kInvPi * (1.0f - max_of(fresnel_d)));
    if (lobes_.mirror_only) return diffuse;
    const float alpha = fmax_inline(lobes_.alpha, kMinGgxAlpha);
    const float dv = ggx_d(dot(n, h), alpha) * ggx_visibility(cos_i, cos_o, alpha);
    const Imath::V3f fresnel = f0 + (f90 - f0) * weight;
    return diffuse + fresnel * dv;
  }

  // The light the surface reflects towards wo under a uniform radiance of 1 from every
  // direction, for the lobes `scope` names: the lecture's ambient albedo k_a, made exact.
  // The diffuse base receives what the dielectric's layer does not reflect at this angle,
  // so that for rho <= 1 the total never exceeds 1 and is exactly 1 for a white, lossless
  // material (white Lambert, white smooth metal, a smooth or rough white dielectric, clear
  // glass). Rough layers use the tabulated GGX albedo (ggx_albedo.h). `back_face`: wo is
  // inside the transmissive part.
  Imath::V3f albedo(const Imath::V3f& wo, const Imath::V3f& n, bool back_face,
                    AlbedoScope scope) const {
    if (!layered_) return base_albedo(wo, n, back_face, scope);
    return lobes_.layers.albedo(wo, n, coat_normal(n), base_albedo(wo, n, back_face, scope),
                                scope == AlbedoScope::all_lobes);
  }
  // The base's albedo alone; its delta lobes' weights as specular_lobes() gives them would
  // carry the layers' transmittance, so they are taken unattenuated here.
  Imath::V3f base_albedo(const Imath::V3f& wo, const Imath::V3f& n, bool back_face,
                         AlbedoScope scope) const {
    if (lambertian_) return lobes_.diffuse_albedo;
    const OpaqueAlbedos opaque = opaque_albedos(fmin_inline(1.0f, fmax_inline(0.0f, dot(wo, n))));
    Imath::V3f total = opaque.diffuse;
    const bool with_delta = scope == AlbedoScope::all_lobes;
    if (!lobes_.mirror || with_delta) total += opaque.layer;
    if (with_delta && lobes_.transmission > 0.0f) {
      SpecularLobe lobes[2];
      const int count = base_specular_lobes<false, true>(wo, n, back_face, lobes);
      for (int i = 0; i < count; ++i) total += lobes[i].weight();
    }
    // The rough dielectric's albedo, estimated by the smooth one's (it loses a little to
    // single scattering): what the layers' choice weighs the base by.
    if (lobes_.rough_transmission) {
      const float cos_i = fmin_inline(1.0f, fmax_inline(0.0f, dot(wo, n)));
      const float eta = back_face ? 1.0f / lobes_.ior : lobes_.ior;
      const float fresnel = fresnel_dielectric(cos_i, eta);
      total +=
          (Imath::V3f(fresnel) + transmission_weight() / lobes_.transmission * (1.0f - fresnel)) *
          lobes_.transmission;
    }
    return total;
  }

  // The density sample() picks wi with among its non-delta lobes (the delta lobes' share
  // of the choice excluded, as pbrt's pdf does).
  float pdf(const Imath::V3f& wo, const Imath::V3f& wi) const {
    const Imath::V3f n = normal_towards(wo);
    const float cos_wi = dot(n, wi);
    if (lambertian_) return cos_wi > 0.0f ? cos_wi * kInvPi : 0.0f;
    const LobeChoice c = choice(wo, n);
    const float dielectric =
        c.dielectric > 0.0f
            ? c.dielectric * rough_dielectric().pdf(to_local(wo, n), to_local(wi, n))
            : 0.0f;
    if (cos_wi <= 0.0f) {
      // Only the rough dielectric reaches below; sample() picks it within the base's share.
      if (!layered_ || dielectric == 0.0f) return dielectric;
      const SurfaceLayers::Shares l = layer_shares(wo, n, coat_normal(n));
      return dielectric * (1.0f - l.coat - l.sheen);
    }
    float density = c.diffuse * cos_wi * kInvPi;
    if (c.glossy > 0.0f) density += c.glossy * glossy_pdf(wo, wi, n);
    density += dielectric;
    if (!layered_) return density;
    const Imath::V3f nc = coat_normal(n);
    const SurfaceLayers::Shares l = layer_shares(wo, n, nc);
    density *= 1.0f - l.coat - l.sheen;
    density += l.sheen * cos_wi * kInvPi;  // the sheen is sampled by the cosine
    if (l.coat > 0.0f) density += l.coat * lobes_.layers.coat_pdf(wo, wi, nc);
    return density;
  }

  // One lobe only (Lambert): sample() ignores its `u_lobe`, which a caller need not draw.
  bool single_lobe() const { return lambertian_; }

  // Picks a lobe with `u_lobe` (in proportion to its albedo estimate) and a direction with
  // `u`; false when nothing scatters or the direction falls below the surface.
  bool sample(const Imath::V3f& wo, float u_lobe, const Imath::V2f& u, bool back_face,
              BsdfSample* out) const {
    const Imath::V3f n = normal_towards(wo);
    if (lambertian_) {
      out->wi = from_local(square_to_cosine_hemisphere(u), n);
      out->lobe = kDiffuseReflection;
      const float cos_wi = dot(n, out->wi);
      if (cos_wi <= 0.0f) return false;
      out->f = lobes_.diffuse_albedo * kInvPi;
      out->pdf = cos_wi * kInvPi;
      return out->pdf > 0.0f;
    }
    // The base's share of the choice, after the layers over it took theirs.
    float base_share = 1.0f;
    if (layered_) {
      const Imath::V3f nc = coat_normal(n);
      const SurfaceLayers::Shares l = layer_shares(wo, n, nc);
      if (u_lobe < l.coat + l.sheen) {
        Imath::V3f wi;
        if (u_lobe < l.coat) {
          if (!lobes_.layers.sample_coat(wo, nc, u, &wi)) return false;
        } else {
          wi = from_local(square_to_cosine_hemisphere(u), n);
        }
        if (dot(n, wi) <= 0.0f) return false;
        out->wi = wi;
        out->f = eval(wo, wi, n);
        out->pdf = pdf(wo, wi);
        out->lobe = kGlossyReflection;
        return out->pdf > 0.0f;
      }
      base_share = 1.0f - l.coat - l.sheen;
      u_lobe = fmin_inline((u_lobe - l.coat - l.sheen) / base_share, 0x1.fffffep-1f);
    }
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
      const float p = base_share * c.specular * luminance(lobes[k].weight()) / total;
      const float cos_wi = std::fabs(dot(n, lobes[k].wi));
      out->wi = lobes[k].wi;
      out->pdf = p;
      // f |cos| / pdf = weight / p: the lobe's weight divided by the chance of choosing it.
      out->f = cos_wi > 0.0f ? lobes[k].weight() / cos_wi : Imath::V3f(0.0f);
      out->lobe = lobes[k].transmission ? kSpecularTransmission : kSpecularReflection;
      return cos_wi > 0.0f;
    }
    const float u_rest = (u_lobe - c.specular) / std::max(1e-30f, 1.0f - c.specular);
    return sample_reflection(wo, n, c, u_rest, u, out);
  }

  // The delta lobes' directions and weights at the shading normal `n` (normal_towards(wo)),
  // transmission first: the refracted ray (unless total internal reflection) and one
  // reflection ray carrying both the mirror's and the dielectric's reflection. `back_face`:
  // wo is inside the dielectric. Mirror and Transmission say which lobes to consider, so a
  // caller specialised on the scene leaves out what no surface has. Returns the count.
  template <bool Mirror, bool Transmission>
  int specular_lobes(const Imath::V3f& wo, const Imath::V3f& n, bool back_face,
                     SpecularLobe* out) const {
    const int count = base_specular_lobes<Mirror, Transmission>(wo, n, back_face, out);
    if (!layered_) return count;
    return layer_specular_lobes<Mirror>(wo, n, out, count);
  }

 private:
  struct LobeChoice {
    float specular = 0.0f, diffuse = 0.0f, glossy = 0.0f, dielectric = 0.0f;
  };

  // The non-delta lobes' part of sample(), `u_rest` choosing among them.
  bool sample_reflection(const Imath::V3f& wo, const Imath::V3f& n, const LobeChoice& c,
                         float u_rest, const Imath::V2f& u, BsdfSample* out) const {
    if (c.dielectric > 0.0f) {
      // The rough dielectric's share comes last.
      const float reflect_share = c.diffuse + c.glossy;
      const float x = u_rest * (reflect_share + c.dielectric);
      if (x >= reflect_share)
        return sample_rough_dielectric(wo, n, (x - reflect_share) / c.dielectric, u, out);
      u_rest = x / reflect_share;
    }
    Imath::V3f wi;
    if (u_rest * (c.diffuse + c.glossy) < c.diffuse || c.glossy <= 0.0f) {
      wi = from_local(square_to_cosine_hemisphere(u), n);
      out->lobe = kDiffuseReflection;
    } else if (lobes_.model == BrdfModel::lecture) {
      const Imath::V3f r = reflect(-wo, n);
      wi = from_local(square_to_cosine_power(u, lobes_.phong_exponent), r);
      out->lobe = kGlossyReflection;
    } else {
      const Imath::V3f wo_local = to_local(wo, n);
      const Imath::V3f h = sample_ggx_visible_normal(
          wo_local.z > 0.0f ? wo_local : Imath::V3f(wo_local.x, wo_local.y, 1e-6f),
          fmax_inline(lobes_.alpha, kMinGgxAlpha), u);
      wi = from_local(h * (2.0f * wo_local.dot(h)) - wo_local, n);
      out->lobe = kGlossyReflection;
    }
    if (dot(n, wi) <= 0.0f) return false;
    out->wi = wi;
    out->f = eval(wo, wi, n);
    out->pdf = pdf(wo, wi);
    return out->pdf > 0.0f;
  }

  // The base's delta lobes, as specular_lobes() without the layers.
  template <bool Mirror, bool Transmission>
  int base_specular_lobes(const Imath::V3f& wo, const Imath::V3f& n, bool back_face,
                          SpecularLobe* out) const {
    const float cos_i = fmin_inline(1.0f, fmax_inline(0.0f, dot(wo, n)));
    Imath::V3f reflect_weight(0.0f);
    int count = 0;
    if constexpr (Mirror) {
      if (lobes_.mirror) {
        const Imath::V3f f0 = mirror_f0();
        reflect_weight += f0 + (mirror_f90() - f0) * schlick_weight(cos_i);
      }
    }
    if constexpr (Transmission) {
      if (lobes_.transmission > 0.0f && !lobes_.rough_transmission) {
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

  // The base's `count` delta lobes in `out` dimmed by what the layers over them let through
  // (seen from wo: the mirror and the refracted ray leave the layers where they entered), and
  // the coat's own mirror, where traced, joined to the reflection ray.
  template <bool Mirror>
  int layer_specular_lobes(const Imath::V3f& wo, const Imath::V3f& n, SpecularLobe* out,
                           int count) const {
    const Imath::V3f nc = coat_normal(n);
    const float through = lobes_.layers.view_transmittance(wo, n, nc);
    for (int i = 0; i < count; ++i) out[i].colour *= through;
    if constexpr (Mirror) {
      if (lobes_.layers.clearcoat_mirror && lobes_.layers.clearcoat > 0.0f) {
        const Imath::V3f coat(lobes_.layers.coat_albedo(wo, nc));
        if (count > 0 && !out[count - 1].transmission)
          out[count - 1].colour += coat / out[count - 1].scale;
        else
          out[count++] = {normalize(reflect(-wo, n)), coat, 1.0f, false};
      }
    }
    return count;
  }
  Imath::V3f coat_normal(const Imath::V3f& n) const {
    return lobes_.layers.coat_normal(n, normal_);
  }
  // The base's albedo estimate is the luminance of the estimates choice() splits on.
  SurfaceLayers::Shares layer_shares(const Imath::V3f& wo, const Imath::V3f& n,
                                     const Imath::V3f& nc) const {
    return lobes_.layers.shares(wo, n, nc,
                                luminance(base_albedo(wo, n, false, AlbedoScope::all_lobes)));
  }

  // The rough dielectric at `n` (normal_towards(wo)) in its local frame.
  RoughDielectric rough_dielectric() const {
    const bool inside = lobes_.back_face && !lobes_.thin_walled;
    return {fmax_inline(lobes_.alpha, kMinGgxAlpha), inside ? 1.0f / lobes_.ior : lobes_.ior,
            lobes_.thin_walled};
  }
  // Its transmitted light takes the base colour on entry (every pass for a thin wall).
  Imath::V3f transmission_weight() const {
    const bool tinted = lobes_.thin_walled || !lobes_.back_face;
    return (tinted ? lobes_.transmission_tint : Imath::V3f(1.0f)) * lobes_.transmission;
  }
  Imath::V3f rough_dielectric_eval(const Imath::V3f& wo, const Imath::V3f& wi,
                                   const Imath::V3f& n) const {
    const Imath::V3f wi_local = to_local(wi, n);
    const float f = rough_dielectric().eval(to_local(wo, n), wi_local);
    return wi_local.z < 0.0f ? transmission_weight() * f : Imath::V3f(lobes_.transmission * f);
  }
  bool sample_rough_dielectric(const Imath::V3f& wo, const Imath::V3f& n, float u_choice,
                               const Imath::V2f& u, BsdfSample* out) const {
    RoughDielectricSample s;
    if (!rough_dielectric().sample(to_local(wo, n), u_choice, u, &s)) return false;
    out->wi = from_local(s.wi, n);
    out->f = eval(wo, out->wi, n);
    out->pdf = pdf(wo, out->wi);
    out->lobe = s.transmission ? kGlossyTransmission : kGlossyReflection;
    return out->pdf > 0.0f;
  }

  // The lecture's lobes: Lambert under the layer's normal-incidence share, and normalised
  // Phong about the mirror direction R = reflect(-wi, n).
  Imath::V3f eval_lecture(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    const float lobe_norm = (lobes_.phong_exponent + 2.0f) * (0.5f * kInvPi);
    const Imath::V3f reflected = reflect(-wi, n);
    const float cos_view = fmax_inline(0.0f, dot(reflected, wo));
    const float specular = lobes_.phong_exponent > 0.0f
                               ? lobe_norm * std::pow(cos_view, lobes_.phong_exponent)
                               : lobe_norm;
    return lobes_.diffuse_albedo * (kInvPi * (1.0f - max_of(lobes_.dielectric_f0))) +
           lobes_.specular_f0 * specular;
  }

  // The layer over the opaque parts (metal and opaque dielectric), which the mirror ray
  // carries: the whole layer less the transmissive part's, whose reflection is the smooth
  // dielectric's exact Fresnel.
  Imath::V3f mirror_f0() const {
    return clamp_non_negative(lobes_.specular_f0 - lobes_.dielectric_f0 * lobes_.transmission);
  }
  Imath::V3f mirror_f90() const {
    return clamp_non_negative(lobes_.specular_f90 -
                              Imath::V3f(lobes_.dielectric_f90 * lobes_.transmission));
  }

  // How sample() splits its choice: the delta lobes' share first, then diffuse and glossy in
  // proportion to estimates of their albedos (any positive split is unbiased).
  LobeChoice choice(const Imath::V3f& wo, const Imath::V3f& n) const {
    if (choice_is_fixed_) return fixed_choice_;
    if (choice_by_albedo_) return choice_by_albedo(wo, n);
    SpecularLobe lobes[2];
    float specular = 0.0f;
    const int count = base_specular_lobes<true, true>(wo, n, false, lobes);
    for (int i = 0; i < count; ++i) specular += luminance(lobes[i].weight());
    return choice_given(specular);
  }
  // Only the delta lobes' weights (their Fresnel at wo) make choice() depend on wo: without
  // them it is formed once, when the lobes are settled, by the same arithmetic.
  bool has_delta_lobes() const {
    return lobes_.mirror || (lobes_.transmission > 0.0f && !lobes_.rough_transmission);
  }
  void fix_choice() {
    choice_by_albedo_ = lobes_.model == BrdfModel::gltf && !has_delta_lobes() &&
                        !lobes_.rough_transmission && !lobes_.opaque_layer && !lambertian_;
    choice_is_fixed_ = !has_delta_lobes() && !choice_by_albedo_;
    if (choice_is_fixed_) fixed_choice_ = choice_given(0.0f);
    cached_choice_wo_ = Imath::V3f(0.0f);
    cached_choice_n_ = Imath::V3f(0.0f);
  }
  // The albedos at cos_v (the view's cosine to the normal) of the diffuse base, under what the
  // dielectric's layer reflects, and of the specular layer over the opaque parts, from the
  // tabulated GGX albedo (or the smooth layer's Schlick weight where it is a mirror): what
  // base_albedo() sums and choice_by_albedo() splits on.
  struct OpaqueAlbedos {
    Imath::V3f diffuse, layer;
  };
  OpaqueAlbedos opaque_albedos(float cos_v) const {
    GgxAlbedo layer{1.0f, schlick_weight(cos_v)};
    if (!lobes_.mirror) layer = ggx_albedo(cos_v, lobes_.alpha);
    const Imath::V3f dielectric_layer =
        lobes_.dielectric_f0 * layer.e +
        (Imath::V3f(lobes_.dielectric_f90) - lobes_.dielectric_f0) * layer.e_schlick;
    return {lobes_.diffuse_albedo * (1.0f - fmin_inline(1.0f, max_of(dielectric_layer))),
            mirror_f0() * layer.e + (mirror_f90() - mirror_f0()) * layer.e_schlick};
  }
  // The opaque glTF layer over its diffuse base: diffuse and glossy in proportion to their
  // albedos at wo (the tabulated GGX albedo, as base_albedo()). The layer's F90 of 1 would
  // otherwise weigh the glossy lobe as if it reflected everything, where a dielectric's
  // reflects 4 to 10 % away from grazing: two in three samples went to it. Sample, pdf and
  // eval at one vertex share wo, so the choice is formed once per wo.
  LobeChoice choice_by_albedo(const Imath::V3f& wo, const Imath::V3f& n) const {
    if (wo == cached_choice_wo_ && n == cached_choice_n_) return cached_choice_;
    const OpaqueAlbedos opaque = opaque_albedos(fmin_inline(1.0f, fmax_inline(0.0f, dot(wo, n))));
    const float diffuse = luminance(opaque.diffuse), glossy = luminance(opaque.layer);
    const float total = diffuse + glossy;
    LobeChoice c;
    if (total > 0.0f) c = {0.0f, diffuse / total, glossy / total};
    cached_choice_wo_ = wo;
    cached_choice_n_ = n;
    cached_choice_ = c;
    return c;
  }
  // The choice once the delta lobes' luminance `specular` is known.
  LobeChoice choice_given(float specular) const {
    const float diffuse = luminance(lobes_.diffuse_albedo);
    if (lobes_.rough_transmission) {
      // The layer's GGX lobe over the opaque part, and the rough dielectric by its weight.
      const float glossy = luminance(mirror_f90()), dielectric = lobes_.transmission;
      const float total = specular + diffuse + glossy + dielectric;
      return {specular / total, diffuse / total, glossy / total, dielectric / total};
    }
    // A smooth layer's light is the mirror's; its GGX lobe is for punctual lights only.
    const float glossy = lobes_.mirror                        ? 0.0f
                         : lobes_.model == BrdfModel::lecture ? luminance(lobes_.specular_f0)
                         : lobes_.opaque_layer                ? luminance(mirror_f90())
                                                              : luminance(lobes_.specular_f90);
    const float total = specular + diffuse + glossy;
    if (!(total > 0.0f)) return {};
    const float rest = 1.0f - specular / total;
    const float reflect_total = diffuse + glossy;
    if (!(reflect_total > 0.0f)) return {specular / total, 0.0f, 0.0f};
    return {specular / total, rest * diffuse / reflect_total, rest * glossy / reflect_total};
  }
  // Density of the glossy lobe's sampling: the visible normals' for GGX (Heitz 2018:
  // G1(wo) D(h) / (4 cos_o)), cos^n about the mirror direction R of wo for Phong.
  float glossy_pdf(const Imath::V3f& wo, const Imath::V3f& wi, const Imath::V3f& n) const {
    if (lobes_.model == BrdfModel::lecture) {
      const float cos_alpha = dot(reflect(-wo, n), wi);
      if (cos_alpha <= 0.0f) return 0.0f;
      return cosine_power_pdf(cos_alpha, lobes_.phong_exponent);
    }
    const float cos_o = dot(n, wo);
    if (!(cos_o > 0.0f)) return 0.0f;
    const Imath::V3f h = normalize(wo + wi);
    const float alpha = fmax_inline(lobes_.alpha, kMinGgxAlpha);
    return ggx_g1(cos_o, alpha) * ggx_d(dot(n, h), alpha) / (4.0f * cos_o);
  }
  static bool has(const Imath::V3f& c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }
  // glTF's model with no specular layer (F0 = F90 = 0: KHR_materials_specular's factor 0, or
  // an importer's diffuse-only material), nothing transmitted and no coat or sheen: a Lambert
  // surface, and most of a Cornell box. Every general formula then reduces to rho / pi, cos /
  // pi and rho exactly (the layer's terms are exact zeros, the diffuse's share exactly 1), so
  // the shortcut changes no bit; it only skips the GGX terms that would multiply by zero.
  static bool is_lambertian(const BsdfLobes& l, bool layered) {
    const Imath::V3f zero(0.0f);
    return l.model == BrdfModel::gltf && !layered && l.transmission == 0.0f &&
           l.specular_f0 == zero && l.specular_f90 == zero && l.dielectric_f0 == zero &&
           l.dielectric_f90 == 0.0f && luminance(l.diffuse_albedo) > 0.0f;
  }
  static float max_of(const Imath::V3f& c) { return fmax_inline(c.x, fmax_inline(c.y, c.z)); }
  static Imath::V3f clamp_non_negative(const Imath::V3f& c) {
    return Imath::V3f(fmax_inline(0.0f, c.x), fmax_inline(0.0f, c.y), fmax_inline(0.0f, c.z));
  }

  Imath::V3f normal_{0.0f, 0.0f, 1.0f};
  BsdfLobes lobes_;
  bool layered_ = false;          // lobes_.layers.present(): a coat or a sheen to evaluate
  bool lambertian_ = false;       // is_lambertian(): eval, pdf, sample and albedo take a shortcut
  bool choice_is_fixed_ = false;  // no delta lobe: choice() is fixed_choice_ for every wo
  bool choice_by_albedo_ = false;  // choice() is choice_by_albedo()
  LobeChoice fixed_choice_;
  // choice_by_albedo()'s last answer and its wo and n (zero, never a direction, when none yet).
  mutable Imath::V3f cached_choice_wo_{0.0f}, cached_choice_n_{0.0f};
  mutable LobeChoice cached_choice_;
};

}  // namespace prism
