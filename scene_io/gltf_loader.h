// Loading glTF 2.0 (.gltf with external or data-URI buffers, and .glb) into a
// SceneDescription. Every index, count and value is validated before use; a file that cannot
// be rendered as its author meant raises LoadError, never a crash or a silently wrong scene.
#pragma once

#include <stdexcept>
#include <string>

#include "renderer/scene_description.h"

namespace prism {

// One line: "<file>: <glTF element>: <what is wrong>",
// e.g. "scene.gltf: meshes[2].primitives[0].indices: index 9 out of range (24 vertices)".
class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

SceneDescription load_gltf(const std::string& path);

}  // namespace prism
