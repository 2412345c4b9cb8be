// The handlers of KHR_materials_clearcoat and KHR_materials_sheen (gltf_extensions.h's
// table): factors and textures read into MaterialDescription, every value checked.
#pragma once

#include <string>

#include "scene_io/gltf_extensions.h"

namespace prism::gltf_detail {

void read_clearcoat(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                    MaterialDescription& d);
void read_sheen(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                MaterialDescription& d);

}  // namespace prism::gltf_detail
