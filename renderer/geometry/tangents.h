// Per-vertex tangents for normal mapping when a glTF primitive has no TANGENT attribute.
#pragma once

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>

namespace prism {

// MikkTSpace-style tangents: each triangle's tangent (the direction of increasing u,
// dP/du) and bitangent (dP/dv) from its UV derivatives, accumulated at its vertices weighted
// by the triangle's angle there, then made orthogonal to the vertex normal (Gram-Schmidt).
// w is glTF's handedness: the bitangent is cross(normal, tangent) * w, and points towards
// decreasing v, "up" in the image, since glTF's UV origin is the image's top-left corner;
// a mirrored UV layout gets w = -1. `normals` may be empty (the face normals are used).
// Vertices without usable UVs get an arbitrary tangent orthogonal to their normal.
std::vector<Imath::V4f> generate_tangents(const std::vector<Imath::V3f>& positions,
                                          const std::vector<Imath::V3f>& normals,
                                          const std::vector<Imath::V2f>& uvs,
                                          const std::vector<uint32_t>& indices);

}  // namespace prism
