// Sparse accessors (glTF 2.0 §3.6.2.3): a base (a bufferView, or zeros) with some elements
// replaced. They are densified once, right after parsing, so that every reader sees a plain
// accessor and applies its usual checks to the substituted values too.
#pragma once

#include <string>

#include <tiny_gltf.h>

namespace prism::gltf_detail {

// Rewrites every sparse accessor of `model` onto a new dense bufferView. Throws LoadError naming
// accessors[i].sparse... when the indices are not strictly increasing, not below the accessor's
// count, of an invalid type, or when either the indices or the values lie outside their
// bufferView.
void apply_sparse_accessors(tinygltf::Model& model, const std::string& file);

}  // namespace prism::gltf_detail
