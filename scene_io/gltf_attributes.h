// Readers for the vertex attributes materials use beyond positions, normals and TEXCOORD_n:
// COLOR_0 and TANGENT, with the component types glTF allows for each.
#pragma once

#include <string>
#include <vector>

#include <Imath/ImathVec.h>

#include "scene_io/gltf_accessors.h"

namespace prism::gltf_detail {

// COLOR_0: VEC3 or VEC4 of FLOAT, normalized UNSIGNED_BYTE or normalized UNSIGNED_SHORT, as
// linear RGBA (VEC3: alpha 1). Float values must be finite and are clamped to [0, 1].
std::vector<Imath::V4f> read_colours(const AccessorView& view, const std::string& file);

// TANGENT: VEC4 of FLOAT, xyz a unit vector and w = +1 or -1 (a sign kept from any w that is
// not zero); throws on non-finite values or a zero xyz.
std::vector<Imath::V4f> read_tangents(const AccessorView& view, const std::string& file);

}  // namespace prism::gltf_detail
