// Bounds-checked access to glTF accessor data held by a tinygltf::Model.
#pragma once

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

// Each reader checks the accessor's type and component type for its purpose, then copies.
std::vector<V3f> read_vec3_float(const AccessorView& view, const std::string& what,
                                 const std::string& file);
std::vector<V2f> read_texcoords(const AccessorView& view, const std::string& file);
std::vector<uint32_t> read_indices(const AccessorView& view, const std::string& file);

const char* component_type_name(int component_type);

}  // namespace prism::gltf_detail
