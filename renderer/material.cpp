#include "renderer/material.h"

#include <algorithm>
#include <cmath>

#include "renderer/colour.h"
#include "renderer/math.h"

namespace prism {
namespace {

const Texture* texture_or_null(int index, const std::vector<Texture>& textures) {
  return index >= 0 && index < static_cast<int>(textures.size()) ? &textures[index] : nullptr;
}

Rgb to_rgb(const C3f& c) {
  return Rgb(c.x, c.y, c.z);
}

}  // namespace

float phong_exponent_from_roughness(float roughness) {
  const float alpha = std::max(roughness * roughness, 1e-4f);
  return std::clamp(2.0f / (alpha * alpha) - 2.0f, 0.0f, kMaxPhongExponent);
}

float dielectric_f0(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

Material make_material(const MaterialDescription& d, const std::vector<Texture>& textures,
                       const ColourPipeline& colour) {
  Material m;
  m.base_colour = to_rgb(colour.from_linear_rec709(d.base_colour));
  m.base_colour_texture = texture_or_null(d.base_colour_texture, textures);
  m.metallic = std::clamp(d.metallic, 0.0f, 1.0f);
  m.roughness = std::clamp(d.roughness, 0.0f, 1.0f);
  m.metallic_roughness_texture = texture_or_null(d.metallic_roughness_texture, textures);
  m.emissive = to_rgb(colour.from_linear_rec709(d.emissive));
  m.emissive_texture = texture_or_null(d.emissive_texture, textures);
  m.transmission = std::clamp(d.transmission, 0.0f, 1.0f);
  m.ior = d.ior >= 1.0f ? d.ior : 1.5f;
  m.specular = std::clamp(d.specular, 0.0f, 1.0f);
  m.specular_colour = to_rgb(colour.from_linear_rec709(d.specular_colour));
  return m;
}

SurfaceResponse evaluate(const Material& material, const SurfaceHit& hit) {
  const Imath::V2f& uv = hit.uv;
  Rgb base = material.base_colour;
  if (material.base_colour_texture) {
    const Imath::V4f t = material.base_colour_texture->sample(uv);
    base = hadamard(base, Rgb(t.x, t.y, t.z));
  }
  float metallic = material.metallic, roughness = material.roughness;
  if (material.metallic_roughness_texture) {
    const Imath::V4f t = material.metallic_roughness_texture->sample(uv);
    roughness *= t.y;  // glTF: roughness in green, metallic in blue
    metallic *= t.z;
  }
  Rgb emission = material.emissive;
  if (material.emissive_texture) {
    const Imath::V4f t = material.emissive_texture->sample(uv);
    emission = hadamard(emission, Rgb(t.x, t.y, t.z));
  }

  // Dielectric and metal responses are blended by `metallic`, as glTF does. The dielectric's
  // specular layer reflects F0 (from the ior, tinted and weighted by KHR_materials_specular)
  // and leaves (1 - max F0) for its diffuse and transmitted parts, so the albedo
  //   (1 - m)(1 - F0) rho + (1 - m) F0 + m rho
  // never exceeds 1 for rho <= 1: a white surface never reflects more than it receives.
  const float f0_ior = dielectric_f0(material.ior);
  const Rgb f0(std::min(f0_ior * material.specular_colour.x, 1.0f) * material.specular,
               std::min(f0_ior * material.specular_colour.y, 1.0f) * material.specular,
               std::min(f0_ior * material.specular_colour.z, 1.0f) * material.specular);
  const float layer = std::max({f0.x, f0.y, f0.z});
  const float dielectric = 1.0f - metallic;
  SurfaceResponse r;
  r.transmission = dielectric * material.transmission;
  r.diffuse_albedo = base * (dielectric * (1.0f - material.transmission) * (1.0f - layer));
  r.specular_colour = f0 * dielectric + base * metallic;
  r.phong_exponent = phong_exponent_from_roughness(roughness);
  r.mirror = roughness <= kMirrorRoughness;
  r.ior = material.ior;
  r.transmission_tint = base;
  r.emission = emission;
  r.shading_normal = hit.shading_normal;
  return r;
}

}  // namespace prism
