// glTF's metallic-roughness material mapped onto the lecture's shading model:
//   ambient + Lambert diffuse + normalised Phong specular + mirror reflection + refraction,
// in radiometric units (docs/materials.md has the derivation). All colours are RGB in the
// working colour space.
#pragma once

#include <vector>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"
#include "renderer/surface_hit.h"
#include "renderer/texture.h"

namespace prism {

class ColourPipeline;
using Rgb = Imath::V3f;

// Roughness at or below which a surface is a perfect mirror for the whitted integrator.
constexpr float kMirrorRoughness = 0.1f;
// Phong's exponent is capped so that a smooth surface still shows a (tiny) highlight of a
// point light, which a mirror ray can never find.
constexpr float kMaxPhongExponent = 10000.0f;

// The material with its factors in the working space and its textures resolved.
struct Material {
  Rgb base_colour{1.0f, 1.0f, 1.0f};
  const Texture* base_colour_texture = nullptr;
  float metallic = 1.0f;
  float roughness = 1.0f;
  const Texture* metallic_roughness_texture = nullptr;
  Rgb emissive{0.0f, 0.0f, 0.0f};
  const Texture* emissive_texture = nullptr;
  float transmission = 0.0f;
  float ior = 1.5f;
  float specular = 1.0f;  // KHR_materials_specular
  Rgb specular_colour{1.0f, 1.0f, 1.0f};
};

// The shading model's parameters at one surface point.
struct SurfaceResponse {
  Rgb diffuse_albedo;    // rho_d; the BRDF is rho_d / pi
  Rgb specular_colour;   // k_s: reflectance at normal incidence (F0)
  float phong_exponent;  // n of the normalised lobe (n + 2) / (2 pi) (R.V)^n
  bool mirror;           // reflects a recursive mirror ray (whitted)
  float transmission;    // fraction refracted rather than diffusely reflected
  float ior;
  Rgb transmission_tint;  // colour of light passing through (the base colour)
  Rgb emission;           // emitted radiance
  // Unit, on the geometric normal's side: the hit's shading normal, bent by the material's
  // normal map where it has one. Integrators shade with this, not SurfaceHit's.
  Imath::V3f shading_normal;
};

Material make_material(const MaterialDescription& description, const std::vector<Texture>& textures,
                       const ColourPipeline& colour);

// Evaluates the material at a hit: its textures at the hit's texture coordinates (not read
// when untextured) and its normal map.
SurfaceResponse evaluate(const Material& material, const SurfaceHit& hit);

// The Phong exponent that matches a glTF roughness: the Blinn-Phong/Beckmann correspondence
// n = 2 / alpha^2 - 2 with alpha = roughness^2, capped at kMaxPhongExponent.
float phong_exponent_from_roughness(float roughness);

// Reflectance at normal incidence of a dielectric with index of refraction `ior` in air.
float dielectric_f0(float ior);

}  // namespace prism
