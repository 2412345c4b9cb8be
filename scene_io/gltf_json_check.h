// Type checking of the glTF JSON before tinygltf sees it.
//
// tinygltf 2.7 silently replaces a property of the wrong JSON type by its default (a string
// where a mesh index belongs just means "no mesh"), which would render a different scene than
// the author meant. This pass checks the type of every property the loader relies on and
// names the offending element, so that such files fail with a precise LoadError instead.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace prism::gltf_detail {

// Throws LoadError on the first problem; appends warnings (unsupported optional extensions).
void check_gltf_json(const nlohmann::json& root, const std::string& file,
                     std::vector<std::string>& warnings);

}  // namespace prism::gltf_detail
