// Choosing which of a file's scenes to load (`--scene NAME|INDEX`). Shared by the loader and by
// `prism info`, which marks the scene it loaded.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace prism::gltf_detail {

// The index of the scene named `wanted` (by `names`, the file's scenes in order), else the one
// whose index `wanted` spells in decimal. Throws SceneSelectionError (gltf_loader.h) listing
// the scenes when neither exists.
std::size_t select_scene(const std::vector<std::string>& names, const std::string& wanted,
                         const std::string& file);

}  // namespace prism::gltf_detail
