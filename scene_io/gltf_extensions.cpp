#include "scene_io/gltf_extensions.h"

#include <cmath>
#include <limits>

#include "scene_io/gltf_clearcoat_sheen.h"
#include "scene_io/gltf_error.h"
#include "scene_io/gltf_limits.h"
#include "scene_io/gltf_specular_glossiness.h"

namespace prism::gltf_detail {

namespace {

void emissive_strength(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                       MaterialDescription& d) {
  const double strength = r.number(ext, "emissiveStrength", 1.0, e);
  if (strength < 0.0) r.error(e + ".emissiveStrength", "must not be negative");
  // The renderer multiplies in float: finite as a double is not enough.
  const C3f scaled = d.emissive * static_cast<float>(strength);
  if (strength > double(std::numeric_limits<float>::max()) || !std::isfinite(scaled[0]) ||
      !std::isfinite(scaled[1]) || !std::isfinite(scaled[2])) {
    r.error(e + ".emissiveStrength", "strength " + number_text(strength) +
                                         " times the emissive factor is not finite as a float");
  }
  d.emissive = scaled;
}

void transmission(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                  MaterialDescription& d) {
  d.transmission = r.unit(r.number(ext, "transmissionFactor", 0.0, e), e + ".transmissionFactor");
  if (ext.Has("transmissionTexture")) {
    r.warn(e + ".transmissionTexture", "not supported; transmissionFactor is used alone");
  }
}

void ior(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
         MaterialDescription& d) {
  const double value = r.number(ext, "ior", 1.5, e);
  if (value < 1.0) r.error(e + ".ior", "index of refraction " + number_text(value) + " is < 1");
  // Squared by the Fresnel terms in float; no material has an index beyond a few units.
  if (value > gltf_limits::kMaxIor) {
    r.error(e + ".ior", "index of refraction " + number_text(value) + " exceeds " +
                            std::to_string(int(gltf_limits::kMaxIor)));
  }
  d.ior = static_cast<float>(value);
}

// The spec's ranges: thickness >= 0 (0: thin-walled), distance > 0 (absent: nothing is
// absorbed), colour components in [0, 1]; all finite as floats, as the renderer reads them.
void volume(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
            MaterialDescription& d) {
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  const double thickness = r.number(ext, "thicknessFactor", 0.0, e);
  if (!(thickness >= 0.0) || thickness > kFloatMax)
    r.error(e + ".thicknessFactor", "expected a number >= 0, finite as a float");
  d.thickness = static_cast<float>(thickness);
  if (ext.Has("attenuationDistance")) {
    const double distance = r.number(ext, "attenuationDistance", 1.0, e);
    if (!(distance > 0.0) || distance > kFloatMax)
      r.error(e + ".attenuationDistance", "expected a number > 0, finite as a float");
    d.attenuation_distance = static_cast<float>(distance);
  }
  if (ext.Has("attenuationColor")) {
    const tinygltf::Value& v = ext.Get("attenuationColor");
    if (!v.IsArray() || v.ArrayLen() != 3) r.error(e + ".attenuationColor", "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const tinygltf::Value& c = v.Get(i);
      d.attenuation_colour[i] = r.unit(c.IsNumber() ? c.GetNumberAsDouble() : -1.0,
                                       e + ".attenuationColor[" + std::to_string(i) + "]");
    }
  }
  if (ext.Has("thicknessTexture"))
    r.warn(e + ".thicknessTexture", "not supported; a path tracer measures the real thickness");
}

void specular(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
              MaterialDescription& d) {
  d.specular = r.unit(r.number(ext, "specularFactor", 1.0, e), e + ".specularFactor");
  if (ext.Has("specularColorFactor")) {
    const tinygltf::Value& v = ext.Get("specularColorFactor");
    if (!v.IsArray() || v.ArrayLen() != 3)
      r.error(e + ".specularColorFactor", "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const tinygltf::Value& c = v.Get(i);
      const double value = c.IsNumber() ? c.GetNumberAsDouble() : -1.0;
      // The extension allows colours above 1 (F0 is clamped to 1 after the product).
      if (!(value >= 0.0) || value > double(std::numeric_limits<float>::max())) {
        r.error(e + ".specularColorFactor[" + std::to_string(i) + "]",
                "expected a number >= 0, finite as a float");
      }
      d.specular_colour[i] = static_cast<float>(value);
    }
  }
  for (const char* slot : {"specularTexture", "specularColorTexture"}) {
    if (ext.Has(slot)) r.warn(e + "." + slot, "not supported yet; the factors are used alone");
  }
}

// Replaces the metallic-roughness values by the converted specular-glossiness ones
// (gltf_specular_glossiness.h; docs/gltf.md says what the textures lose).
void specular_glossiness(MaterialExtensionReader& r, const tinygltf::Value& ext,
                         const std::string& e, MaterialDescription& d) {
  const SpecularGlossiness sg = read_specular_glossiness(ext, e, r.file());
  const MetallicRoughness mr = to_metallic_roughness(sg.diffuse, sg.specular, sg.glossiness);
  d.base_colour = mr.base_colour;
  d.alpha = sg.alpha;
  d.metallic = mr.metallic;
  d.roughness = mr.roughness;
  d.base_colour_mapping = TextureMapping();
  d.base_colour_texture = r.texture(sg.diffuse_texture, TextureEncoding::srgb,
                                    e + ".diffuseTexture", &d.base_colour_mapping);
  d.metallic_roughness_texture = -1;
  if (sg.specular_glossiness_texture.index >= 0) {
    r.warn(e + ".specularGlossinessTexture",
           "not converted; the specular and glossiness factors are used alone");
  }
}

// The extension has no properties: its presence is the whole statement.
void unlit(MaterialExtensionReader&, const tinygltf::Value&, const std::string&,
           MaterialDescription& d) {
  d.unlit = true;
}

constexpr ExtensionHandler kExtensions[] = {
    {"KHR_materials_pbrSpecularGlossiness", true, specular_glossiness, "materials"},
    {"KHR_materials_emissive_strength", true, emissive_strength, "materials"},
    {"KHR_materials_transmission", true, transmission, "materials"},
    {"KHR_materials_ior", true, ior, "materials"},
    {"KHR_materials_volume", true, volume, "materials"},
    {"KHR_materials_specular", true, specular, "materials"},
    {"KHR_materials_unlit", true, unlit, "materials"},
    {"KHR_materials_sheen", true, read_sheen, "materials"},
    {"KHR_materials_clearcoat", true, read_clearcoat, "materials"},
    {"KHR_lights_punctual", true, nullptr, "the document (lights) and nodes (placement)"},
    {"PRISM_sphere", true, nullptr, "nodes (docs/spheres.md)"},
    {"KHR_draco_mesh_compression", true, nullptr, "primitives (gltf_draco.h)"},
    {"KHR_texture_transform", true, nullptr, "textureInfo objects"},
    // Known, and refused when required: the image formats they bring are not decoded (only
    // PNG and JPEG reach a decoder, gltf_images.h).
    {"EXT_texture_webp", false, nullptr, "textures (WebP images are refused)"},
    {"KHR_texture_basisu", false, nullptr, "textures (KTX2 images are refused)"},
};

}  // namespace

std::span<const ExtensionHandler> extension_handlers() {
  return kExtensions;
}

const ExtensionHandler* find_extension_handler(const std::string& name) {
  for (const ExtensionHandler& h : kExtensions)
    if (name == h.name) return &h;
  return nullptr;
}

}  // namespace prism::gltf_detail
