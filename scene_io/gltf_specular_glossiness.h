// KHR_materials_pbrSpecularGlossiness (archived by Khronos, still common in older assets),
// converted to the metallic-roughness factors the renderer uses.
#pragma once

#include <string>

#include <tiny_gltf.h>

#include "renderer/scene_description.h"

namespace prism::gltf_detail {

// The extension's values, validated (factors in [0, 1], as the extension requires).
struct SpecularGlossiness {
  C3f diffuse{1.0f, 1.0f, 1.0f};
  float alpha = 1.0f;
  C3f specular{1.0f, 1.0f, 1.0f};
  float glossiness = 1.0f;
  tinygltf::TextureInfo diffuse_texture;              // index -1 when absent
  tinygltf::TextureInfo specular_glossiness_texture;  // index -1 when absent
};

// The textureInfo `key` of an extension object (index -1 when absent), its index and texCoord
// checked; LoadError naming `element`.`key` otherwise.
tinygltf::TextureInfo texture_info(const tinygltf::Value& ext, const char* key,
                                   const std::string& element, const std::string& file);

// Reads the extension object; `element` names it in errors ("materials[0].extensions...").
SpecularGlossiness read_specular_glossiness(const tinygltf::Value& ext, const std::string& element,
                                            const std::string& file);

struct MetallicRoughness {
  C3f base_colour;
  float metallic = 0.0f;
  float roughness = 1.0f;
};

// Khronos' conversion: a dielectric reflects F0 = 0.04; metallic is the root of the quadratic
// that makes a metallic-roughness material reflect the same diffuse and specular energy
// (in perceived brightness), base colour blends the diffuse-derived and specular-derived
// colours by metallic², and roughness = 1 - glossiness. Exact for pure dielectrics with
// F0 = 0.04 and for pure metals; anything between is approximated.
MetallicRoughness to_metallic_roughness(const C3f& diffuse, const C3f& specular, float glossiness);

}  // namespace prism::gltf_detail
