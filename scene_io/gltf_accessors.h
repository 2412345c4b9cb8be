// Bounds-checked access to glTF accessor data held by a tinygltf::Model.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "renderer/scene_description.h"

namespace prism::gltf_detail {

// An accessor whose every byte has been checked to lie inside its bufferView and buffer.
struct AccessorView {
  int index = -1;
  const unsigned char* data = nullptr;  // first element; nullptr: no bufferView, all zeros
  std::size_t count = 0;
  std::size_t stride = 0;
  std::size_t component_size = 0;
  int components = 0;
  int component_type = 0;
  bool normalized = false;

  std::string element() const { return "accessors[" + std::to_string(index) + "]"; }
};

// Validates accessor `index` (referenced from `referrer`, used in messages when the index
// itself is out of range) and its bufferView and buffer; throws LoadError naming the culprit.
AccessorView view_accessor(const tinygltf::Model& model, int index, const std::string& referrer,
                           const std::string& file);

// The same checks as view_accessor, for the accessor's own bufferView (or zeros) whether or
// not it is sparse: the base that apply_sparse_accessors (gltf_sparse.h) substitutes into.
AccessorView view_base_accessor(const tinygltf::Model& model, int index,
                                const std::string& referrer, const std::string& file);

// Appends `bytes` to the model as a new buffer with one tightly packed bufferView over it and
// returns the bufferView's index. Draco decoding and sparse substitution rewrite accessors onto
// such views before the scene is converted, so every reader downstream sees plain accessors
// and applies its usual checks.
int append_buffer_view(tinygltf::Model& model, std::vector<unsigned char> bytes);

// Bytes per element of componentType x type (0 when either is invalid).
std::size_t accessor_element_size(int component_type, int type);

// Texture coordinates, weights and colours share one encoding: FLOAT, or UNSIGNED_BYTE/SHORT
// normalised to [0, 1]. The check fails with "WHAT must be FLOAT or normalized ...";
// unit_component reads component k of the element at `element` in that encoding.
void expect_float_or_normalized(const AccessorView& view, const std::string& what,
                                const std::string& file);
float unit_component(const AccessorView& view, const unsigned char* element, int k);

// Each reader checks the accessor's type and component type for its purpose, then copies.
std::vector<V3f> read_vec3_float(const AccessorView& view, const std::string& what,
                                 const std::string& file);
std::vector<V2f> read_texcoords(const AccessorView& view, const std::string& file);
std::vector<uint32_t> read_indices(const AccessorView& view, const std::string& file);
// Skinning: JOINTS_n (VEC4 UNSIGNED_BYTE/SHORT), WEIGHTS_n (VEC4 FLOAT or normalised
// UNSIGNED_BYTE/SHORT), inverseBindMatrices (MAT4 FLOAT, column-major as glTF stores it, loaded
// as M[i][j] = m[4i + j]: Imath's row-vector convention, like node matrices).
std::vector<std::array<uint32_t, 4>> read_joints(const AccessorView& view, const std::string& what,
                                                 const std::string& file);
std::vector<std::array<float, 4>> read_weights(const AccessorView& view, const std::string& what,
                                               const std::string& file);
std::vector<M44d> read_mat4_float(const AccessorView& view, const std::string& what,
                                  const std::string& file);

const char* component_type_name(int component_type);

}  // namespace prism::gltf_detail
