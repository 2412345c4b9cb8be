// glTF's metallic-roughness material (specification Appendix B, KHR_materials_specular, _ior,
// _transmission, _emissive_strength) as the BSDF of renderer/shading/bsdf.h, in radiometric
// units (docs/materials.md has the formulas). All colours are RGB in the working colour space.
#pragma once

#include <optional>
#include <vector>

#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>

#include "renderer/geometry/surface_hit.h"
#include "renderer/scene_description.h"
#include "renderer/shading/bsdf.h"
#include "renderer/shading/texture.h"

namespace prism {

class ColourPipeline;
using Rgb = Imath::V3f;

// Roughness at or below which a surface's layer is also a delta mirror, traced by the
// integrators that follow mirror rays.
constexpr float kMirrorRoughness = 0.1f;
// The lecture model's Phong exponent is capped so that a smooth surface still shows a
// (tiny) highlight of a point light, which a mirror ray can never find.
constexpr float kMaxPhongExponent = 10000.0f;

// A material slot's texture and where it is read: the texture coordinate set and
// KHR_texture_transform as uv' = linear uv + offset.
struct TextureSlot {
  const Texture* texture = nullptr;  // null: the slot is empty
  int texcoord = 0;
  Imath::V2f row0{1.0f, 0.0f}, row1{0.0f, 1.0f};  // the 2x2 linear part, by rows
  Imath::V2f offset{0.0f, 0.0f};
  // How much the transform scales lengths in UV (sqrt |det|): a footprint of width w in the
  // mesh's UVs is one of width w * footprint_scale in the texture's.
  float footprint_scale = 1.0f;

  Imath::V2f transform(const Imath::V2f& uv) const {
    return Imath::V2f(row0.x * uv.x + row0.y * uv.y + offset.x,
                      row1.x * uv.x + row1.y * uv.y + offset.y);
  }
};

// What a material is at one surface point: its BSDF (renderer/shading/bsdf.h), the light it
// emits, and the two factors of glTF's model that are not scattering.
struct SurfaceResponse {
  // Its shading normal is the hit's, bent by the material's normal map where it has one:
  // integrators shade with this, not SurfaceHit's.
  Bsdf bsdf;
  Rgb emission;  // emitted radiance
  // The occlusion texture's factor 1 + strength (occlusion - 1), in [0, 1]: it scales the
  // ambient term only, glTF's "indirect light" (docs/materials.md, "Occlusion").
  float ambient_occlusion = 1.0f;
  float alpha = 1.0f;  // baseColorFactor's alpha x the texture's x COLOR_0's
};

// The material with its factors in the working space and its textures resolved.
struct Material {
  Rgb base_colour{1.0f, 1.0f, 1.0f};
  float alpha = 1.0f;
  TextureSlot base_colour_texture;
  float metallic = 1.0f;
  float roughness = 1.0f;
  TextureSlot metallic_roughness_texture;
  Rgb emissive{0.0f, 0.0f, 0.0f};
  TextureSlot emissive_texture;
  TextureSlot normal_texture;
  float normal_scale = 1.0f;
  TextureSlot occlusion_texture;
  float occlusion_strength = 1.0f;
  // COLOR_0 is linear Rec.709; this takes it to the working space (identity for Rec.709).
  Imath::M33f rec709_to_working;
  float transmission = 0.0f;
  float ior = 1.5f;
  // KHR_materials_volume: without it (or at thickness 0) the transmissive part is thin-walled;
  // with it, light travelling inside the object's volume keeps exp(-sigma_a distance), per
  // channel, sigma_a = -ln(attenuationColor) / attenuationDistance (0 when nothing absorbs).
  bool thin_walled = true;
  Rgb absorption{0.0f, 0.0f, 0.0f};
  float specular = 1.0f;  // KHR_materials_specular
  Rgb specular_colour{1.0f, 1.0f, 1.0f};
  // KHR_materials_clearcoat and KHR_materials_sheen (docs/materials.md, "Clearcoat and sheen").
  float clearcoat = 0.0f;
  float clearcoat_roughness = 0.0f;
  TextureSlot clearcoat_texture, clearcoat_roughness_texture, clearcoat_normal_texture;
  float clearcoat_normal_scale = 1.0f;
  Rgb sheen_colour{0.0f, 0.0f, 0.0f};
  float sheen_roughness = 0.0f;
  TextureSlot sheen_colour_texture, sheen_roughness_texture;
  BrdfModel brdf = BrdfModel::gltf;
  bool unlit = false;  // KHR_materials_unlit: emits its base colour, scatters nothing

  // What evaluate() gives wherever the surface has no vertex colours, when nothing else
  // varies over it (no texture in any slot, no clearcoat, whose normal is the hit's), with
  // the shading normal left for the hit's. A Cornell box's or an engine's materials are
  // then a copy per hit instead of being rebuilt from their factors: the same bits, a tenth
  // of the work. make_material fills it; a Material put together field by field leaves it
  // empty and evaluate() builds every response in full.
  std::optional<SurfaceResponse> uniform_response;
};

Material make_material(const MaterialDescription& description, const std::vector<Texture>& textures,
                       const ColourPipeline& colour, BrdfModel brdf = BrdfModel::gltf);

// Evaluates the material at a hit: its textures at the hit's texture coordinates (not read
// when untextured), filtered over the pixel's footprint, COLOR_0, its normal map and its
// occlusion map.
SurfaceResponse evaluate(const Material& material, const SurfaceHit& hit);

// The radiance the material emits at a hit (emissiveFactor x emissiveTexture), what evaluate
// puts in SurfaceResponse::emission, without the rest: for points sampled on an area light.
Rgb emitted_radiance(const Material& material, const SurfaceHit& hit);

// The base colour's alpha at a hit (baseColorFactor x texture x COLOR_0), for alpha modes,
// without the rest of evaluate. The texture is read at its finest level.
float base_colour_alpha(const Material& material, const SurfaceHit& hit);

// The lecture model's exponent n of (R.V)^n for a glTF roughness: the Blinn-Phong/Beckmann
// correspondence n_H = 2 / alpha^2 - 2 (alpha = roughness^2) for (N.H)^n, divided by 4 for
// the R.V form, capped at kMaxPhongExponent.
float phong_exponent_from_roughness(float roughness);

// Reflectance at normal incidence of a dielectric with index of refraction `ior` in air.
float dielectric_f0(float ior);

// The absorption coefficient sigma_a = -ln(colour) / distance per channel (infinite for a
// colour of 0, 0 for an infinite distance).
Rgb absorption_coefficient(const Rgb& attenuation_colour, float attenuation_distance);

// What a path keeps of its throughput after `distance` through absorption `sigma_a`:
// exp(-sigma_a distance) per channel (1 over no distance, whatever sigma_a).
Rgb transmittance(const Rgb& sigma_a, float distance);

}  // namespace prism
