#include "scene_io/gltf_sparse.h"

#include <cstdint>
#include <cstring>
#include <vector>

#include "scene_io/gltf_accessors.h"
#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"
#include "scene_io/gltf_limits.h"

namespace prism::gltf_detail {

namespace {

// The bytes [byteOffset, byteOffset + size) of bufferView `index`, checked to lie inside the view
// and the view inside its buffer.
const unsigned char* checked_range(const tinygltf::Model& model, int index, std::size_t offset,
                                   std::size_t size, const std::string& element,
                                   const std::string& file) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.bufferViews.size()) {
    fail(file, element + ".bufferView",
         "bufferView " + std::to_string(index) + " out of range (" +
             std::to_string(model.bufferViews.size()) + " bufferViews)");
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(index)];
  const std::string view_element = indexed("bufferViews", static_cast<std::size_t>(index));
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    fail(file, view_element + ".buffer", "buffer " + std::to_string(view.buffer) + " out of range");
  }
  const std::vector<unsigned char>& buffer =
      model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
    fail(file, view_element, "byteOffset + byteLength exceeds its buffer");
  }
  // The spec forbids a byteStride here: sparse indices and values are always tightly packed.
  if (view.byteStride != 0)
    fail(file, view_element, "a sparse accessor's bufferView has a byteStride");
  if (offset > view.byteLength || size > view.byteLength - offset) {
    fail(file, element,
         "byteOffset " + std::to_string(offset) + " + " + std::to_string(size) +
             " bytes exceed the " + std::to_string(view.byteLength) + " bytes of " + view_element);
  }
  return buffer.data() + view.byteOffset + offset;
}

std::size_t index_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return 4;
    default:
      return 0;
  }
}

uint32_t read_index(const unsigned char* p, std::size_t size) {
  if (size == 1) return p[0];
  if (size == 2) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

void densify(tinygltf::Model& model, std::size_t index, const std::string& file) {
  const std::string element = indexed("accessors", index);
  const std::string sparse_element = element + ".sparse";
  const AccessorView base = view_base_accessor(model, static_cast<int>(index), element, file);
  const std::size_t element_size = base.component_size * static_cast<std::size_t>(base.components);
  if (!base.data && base.count * element_size > gltf_limits::kMaxZeroFilledSparseBytes) {
    fail(file, element,
         "sparse accessor of " + std::to_string(base.count) + " elements without a bufferView " +
             "exceeds the limit of " + std::to_string(gltf_limits::kMaxZeroFilledSparseBytes) +
             " bytes");
  }
  const tinygltf::Accessor& accessor = model.accessors[index];
  const auto& sparse = accessor.sparse;
  if (sparse.count < 1 || static_cast<std::size_t>(sparse.count) > base.count) {
    fail(file, sparse_element + ".count",
         "count " + std::to_string(sparse.count) + " must be in [1, " + std::to_string(base.count) +
             "] (the accessor's count)");
  }
  const std::size_t count = static_cast<std::size_t>(sparse.count);
  const std::size_t isize = index_size(sparse.indices.componentType);
  if (isize == 0) {
    fail(file, sparse_element + ".indices.componentType",
         std::string("must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not ") +
             component_type_name(sparse.indices.componentType));
  }
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
    fail(file, sparse_element, "negative byteOffset");
  }
  const unsigned char* indices =
      checked_range(model, sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset),
                    count * isize, sparse_element + ".indices", file);
  const unsigned char* values =
      checked_range(model, sparse.values.bufferView, std::size_t(sparse.values.byteOffset),
                    count * element_size, sparse_element + ".values", file);

  charge(base.count, element_size, element);
  std::vector<unsigned char> dense(base.count * element_size, 0);
  if (base.data) {
    for (std::size_t i = 0; i < base.count; ++i) {
      std::memcpy(dense.data() + i * element_size, base.data + i * base.stride, element_size);
    }
  }
  uint32_t previous = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const uint32_t target = read_index(indices + k * isize, isize);
    if (k > 0 && target <= previous) {
      fail(file, sparse_element + ".indices",
           "index " + std::to_string(target) + " at position " + std::to_string(k) +
               " is not greater than the one before (" + std::to_string(previous) +
               "); sparse indices must strictly increase");
    }
    if (target >= base.count) {
      fail(file, sparse_element + ".indices",
           "index " + std::to_string(target) + " at position " + std::to_string(k) +
               " out of range (the accessor has " + std::to_string(base.count) + " elements)");
    }
    std::memcpy(dense.data() + std::size_t(target) * element_size, values + k * element_size,
                element_size);
    previous = target;
  }
  // Everything read from the model is done before it grows (buffers may move).
  const int view = append_buffer_view(model, std::move(dense));
  tinygltf::Accessor& out = model.accessors[index];
  out.bufferView = view;
  out.byteOffset = 0;
  out.sparse.isSparse = false;
}

}  // namespace

void apply_sparse_accessors(tinygltf::Model& model, const std::string& file) {
  for (std::size_t i = 0; i < model.accessors.size(); ++i) {
    if (model.accessors[i].sparse.isSparse) densify(model, i, file);
  }
}

}  // namespace prism::gltf_detail
