// KHR_draco_mesh_compression: primitives whose geometry is a Draco-compressed bufferView.
// tinygltf (Debian's build) does not decode Draco, so the loader does it with Debian's
// libdraco right after parsing, and rewrites each compressed primitive onto plain accessors.
#pragma once

#include <optional>
#include <string>

#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

namespace prism::gltf_detail {

// tinygltf 2.7 refuses a primitive whose indices accessor has no bufferView, which is how
// Draco files declare it (the data is in the compressed stream). Returns a copy of `root` in
// which such accessors borrow their primitive's compressed bufferView (any valid index would
// do: decode_draco_primitives replaces the accessor), or nothing when no accessor needs it.
std::optional<nlohmann::json> draco_json_for_tinygltf(const nlohmann::json& root);

// For every primitive carrying the extension: decodes its bufferView, checks the decoded mesh
// against the primitive's accessors (each listed attribute exists, has the accessor's count and
// component count; the indices accessor's count is three per decoded triangle), and points the
// primitive at new accessors holding the decoded data in the accessors' declared component
// types, with the extension removed. The usual checks (indices in range, finite positions...)
// follow when the scene is converted. A stream Draco cannot decode is a one-line LoadError
// naming the primitive and Draco's reason.
void decode_draco_primitives(tinygltf::Model& model, const std::string& file);

}  // namespace prism::gltf_detail
