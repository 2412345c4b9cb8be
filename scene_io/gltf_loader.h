// Loading glTF 2.0 (.gltf with external or data-URI buffers, and .glb) into a
// SceneDescription. Every index, count and value is validated before use; a file that cannot
// be rendered as its author meant raises LoadError, never a crash or a silently wrong scene.
#pragma once

#include <cstddef>
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

// `LoadOptions::scene` names a scene the file does not have: the caller's mistake rather than
// the file's, so a command line can report it as a usage error.
class SceneSelectionError : public LoadError {
 public:
  using LoadError::LoadError;
};

// How far the loader trusts the file. A default-constructed LoadOptions is the safe choice for
// files from elsewhere.
struct LoadOptions {
  // Buffers and images may only come from the asset's folder (or below it): a downloaded file
  // must not be able to read other files of the user's, such as "../../.ssh/id_rsa" or
  // "/etc/passwd", into a texture. True lifts that for relative paths leaving the folder
  // ("../textures/x.png", symlinks); absolute paths and file:// URIs are never resolved.
  bool allow_external_paths = false;
  // The scene to load: a scene's name, or its index in decimal. Empty: the file's `scene`, else
  // scenes[0] (else, for a file without scenes, every root node).
  std::string scene;
  // Bytes the load may allocate for the file, all of its geometry, texels, buffers and copies
  // together (8 GiB by default, for a 24 GiB machine); a file needing more is refused with a
  // LoadError naming the element whose allocation crossed it.
  std::size_t memory_limit = std::size_t{8} << 30;
};

SceneDescription load_gltf(const std::string& path, const LoadOptions& options);
SceneDescription load_gltf(const std::string& path);  // default LoadOptions

}  // namespace prism
