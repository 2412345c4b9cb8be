#include "scene_io/gltf_accessors.h"

#include <cstring>

#include "renderer/parallel_index.h"
#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

std::size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not glTF 2.0 accessor component types
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

const char* type_name(int components) {
  switch (components) {
    case 1:
      return "SCALAR";
    case 2:
      return "VEC2";
    case 3:
      return "VEC3";
    case 4:
      return "VEC4 (or MAT2)";
    case 16:
      return "MAT4";
    default:
      return "a type with more components";
  }
}

// Unaligned little-endian reads: glTF only guarantees alignment to the component size
// relative to the buffer, and tinygltf's std::vector gives no alignment promise beyond that.
template <typename T>
T load(const unsigned char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// The copy a reader returns, charged to the load's budget before it is allocated: every read
// is a new copy, whether or not another primitive or pose read the same accessor.
template <typename T>
std::vector<T> charged_copy(const AccessorView& view, const T& zero) {
  charge(view.count, sizeof(T), view.element());
  return std::vector<T>(view.count, zero);
}

void expect_components(const AccessorView& view, int components, const std::string& what,
                       const std::string& file) {
  if (view.components != components) {
    fail(file, view.element(),
         what + " must be " + type_name(components) + ", not " + type_name(view.components));
  }
}

}  // namespace

const char* component_type_name(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    default:
      return "an invalid component type";
  }
}

AccessorView view_accessor(const tinygltf::Model& model, int index, const std::string& referrer,
                           const std::string& file) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    fail(file, referrer,
         "accessor " + std::to_string(index) + " out of range (" +
             std::to_string(model.accessors.size()) + " accessors)");
  }
  // load_gltf densifies sparse accessors before any is viewed (apply_sparse_accessors).
  if (model.accessors[static_cast<std::size_t>(index)].sparse.isSparse) {
    fail(file, "accessors[" + std::to_string(index) + "]", "sparse accessor was not densified");
  }
  return view_base_accessor(model, index, referrer, file);
}

AccessorView view_base_accessor(const tinygltf::Model& model, int index,
                                const std::string& referrer, const std::string& file) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    fail(file, referrer,
         "accessor " + std::to_string(index) + " out of range (" +
             std::to_string(model.accessors.size()) + " accessors)");
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
  AccessorView view;
  view.index = index;
  const std::string element = view.element();

  view.component_type = accessor.componentType;
  view.component_size = component_size(accessor.componentType);
  if (view.component_size == 0) {
    fail(file, element, "componentType " + std::to_string(accessor.componentType) + " is invalid");
  }
  view.components = component_count(accessor.type);
  if (view.components == 0) fail(file, element, "type is invalid");
  view.normalized = accessor.normalized;
  view.count = accessor.count;
  if (view.count == 0) fail(file, element, "count must be at least 1");
  const std::size_t element_size = view.component_size * static_cast<std::size_t>(view.components);

  if (accessor.bufferView < 0) {
    // glTF: an accessor without a bufferView reads as zeros. Cap the count so that a tiny file
    // cannot make the loader allocate gigabytes of zeros.
    if (view.count > (std::size_t{1} << 26)) {
      fail(file, element, "count " + std::to_string(view.count) + " without a bufferView");
    }
    view.stride = element_size;
    return view;
  }
  if (static_cast<std::size_t>(accessor.bufferView) >= model.bufferViews.size()) {
    fail(file, element + ".bufferView",
         "bufferView " + std::to_string(accessor.bufferView) + " out of range (" +
             std::to_string(model.bufferViews.size()) + " bufferViews)");
  }
  const tinygltf::BufferView& buffer_view =
      model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
  const std::string view_element = indexed("bufferViews", std::size_t(accessor.bufferView));
  if (buffer_view.buffer < 0 ||
      static_cast<std::size_t>(buffer_view.buffer) >= model.buffers.size()) {
    fail(file, view_element + ".buffer",
         "buffer " + std::to_string(buffer_view.buffer) + " out of range (" +
             std::to_string(model.buffers.size()) + " buffers)");
  }
  const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(buffer_view.buffer)];
  const std::size_t buffer_size = buffer.data.size();
  if (buffer_view.byteOffset > buffer_size ||
      buffer_view.byteLength > buffer_size - buffer_view.byteOffset) {
    fail(file, view_element,
         "byteOffset " + std::to_string(buffer_view.byteOffset) + " + byteLength " +
             std::to_string(buffer_view.byteLength) + " exceeds the " +
             std::to_string(buffer_size) + " bytes of buffers[" +
             std::to_string(buffer_view.buffer) + "]");
  }

  view.stride = buffer_view.byteStride != 0 ? buffer_view.byteStride : element_size;
  if (view.stride < element_size) {
    fail(file, element,
         "byteStride " + std::to_string(view.stride) + " of " + view_element +
             " is smaller than the element size " + std::to_string(element_size));
  }
  // offset + stride * (count - 1) + element_size <= byteLength, without overflow.
  const std::size_t length = buffer_view.byteLength;
  const std::size_t last = view.count - 1;
  const bool fits = accessor.byteOffset <= length && element_size <= length - accessor.byteOffset &&
                    last <= (length - accessor.byteOffset - element_size) / view.stride;
  if (!fits) {
    fail(file, element,
         "byteOffset " + std::to_string(accessor.byteOffset) + " + " + std::to_string(view.count) +
             " elements of " + std::to_string(element_size) + " bytes (stride " +
             std::to_string(view.stride) + ") exceed the " + std::to_string(length) + " bytes of " +
             view_element);
  }
  view.data = buffer.data.data() + buffer_view.byteOffset + accessor.byteOffset;
  return view;
}

int append_buffer_view(tinygltf::Model& model, std::vector<unsigned char> bytes) {
  tinygltf::BufferView view;
  view.buffer = static_cast<int>(model.buffers.size());
  view.byteOffset = 0;
  view.byteLength = bytes.size();
  view.byteStride = 0;
  tinygltf::Buffer buffer;
  buffer.data = std::move(bytes);
  model.buffers.push_back(std::move(buffer));
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

std::size_t accessor_element_size(int component_type, int type) {
  return component_size(component_type) * static_cast<std::size_t>(component_count(type));
}

namespace {

void expect_float(const AccessorView& view, const std::string& what, const std::string& file) {
  if (view.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    fail(file, view.element(),
         what + " must have componentType FLOAT, not " + component_type_name(view.component_type));
  }
}

}  // namespace

std::vector<V3f> read_vec3_float(const AccessorView& view, const std::string& what,
                                 const std::string& file) {
  expect_components(view, 3, what, file);
  expect_float(view, what, file);
  std::vector<V3f> out = charged_copy(view, V3f(0.0f));
  if (!view.data) return out;
  for_each_index(view.count, [&](std::size_t i) {
    const unsigned char* p = view.data + i * view.stride;
    out[i] = V3f(load<float>(p), load<float>(p + 4), load<float>(p + 8));
  });
  return out;
}

void expect_float_or_normalized(const AccessorView& view, const std::string& what,
                                const std::string& file) {
  const int type = view.component_type;
  const bool normalized_integer = (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                   type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) &&
                                  view.normalized;
  if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_integer) {
    fail(file, view.element(),
         what + " must be FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT, not " +
             (view.normalized ? "normalized " : "") + component_type_name(type));
  }
}

float unit_component(const AccessorView& view, const unsigned char* element, int k) {
  switch (view.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(element + 4 * k);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return element[k] / 255.0f;
    default:
      return load<uint16_t>(element + 2 * k) / 65535.0f;
  }
}

std::vector<V2f> read_texcoords(const AccessorView& view, const std::string& file) {
  expect_components(view, 2, "TEXCOORD_0", file);
  expect_float_or_normalized(view, "TEXCOORD_0", file);
  std::vector<V2f> out = charged_copy(view, V2f(0.0f));
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    out[i] = V2f(unit_component(view, p, 0), unit_component(view, p, 1));
  }
  return out;
}

std::vector<uint32_t> read_indices(const AccessorView& view, const std::string& file) {
  expect_components(view, 1, "indices", file);
  const int type = view.component_type;
  if ((type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
       type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) ||
      view.normalized) {
    fail(file, view.element(),
         std::string("indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not ") +
             (view.normalized ? "normalized " : "") + component_type_name(type));
  }
  std::vector<uint32_t> out = charged_copy(view, uint32_t{0});
  if (!view.data) return out;
  for_each_index(view.count, [&](std::size_t i) {
    const unsigned char* p = view.data + i * view.stride;
    if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      out[i] = p[0];
    } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      out[i] = load<uint16_t>(p);
    } else {
      out[i] = load<uint32_t>(p);
    }
  });
  return out;
}

std::vector<std::array<uint32_t, 4>> read_joints(const AccessorView& view, const std::string& what,
                                                 const std::string& file) {
  expect_components(view, 4, what, file);
  const int type = view.component_type;
  if ((type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
       type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) ||
      view.normalized) {
    fail(file, view.element(),
         what + " must be UNSIGNED_BYTE or UNSIGNED_SHORT, not " +
             (view.normalized ? "normalized " : "") + component_type_name(type));
  }
  std::vector<std::array<uint32_t, 4>> out = charged_copy(view, std::array<uint32_t, 4>{});
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    for (int c = 0; c < 4; ++c) {
      out[i][c] = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? p[c] : load<uint16_t>(p + 2 * c);
    }
  }
  return out;
}

std::vector<std::array<float, 4>> read_weights(const AccessorView& view, const std::string& what,
                                               const std::string& file) {
  expect_components(view, 4, what, file);
  expect_float_or_normalized(view, what, file);
  std::vector<std::array<float, 4>> out = charged_copy(view, std::array<float, 4>{});
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    for (int c = 0; c < 4; ++c) out[i][c] = unit_component(view, p, c);
  }
  return out;
}

std::vector<M44d> read_mat4_float(const AccessorView& view, const std::string& what,
                                  const std::string& file) {
  expect_components(view, 16, what, file);
  expect_float(view, what, file);
  std::vector<M44d> out = charged_copy(view, M44d(0.0));
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    for (int k = 0; k < 16; ++k) out[i][k / 4][k % 4] = load<float>(p + 4 * k);
  }
  return out;
}

}  // namespace prism::gltf_detail
