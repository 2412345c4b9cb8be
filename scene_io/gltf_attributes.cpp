#include "scene_io/gltf_attributes.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

template <typename T>
T load(const unsigned char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

}  // namespace

std::vector<Imath::V4f> read_colours(const AccessorView& view, const std::string& file) {
  const int type = view.component_type;
  const bool normalized_integer = (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                   type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) &&
                                  view.normalized;
  if (view.components != 3 && view.components != 4)
    fail(file, view.element(), "COLOR_0 must be VEC3 or VEC4");
  if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_integer) {
    fail(file, view.element(),
         std::string("COLOR_0 must be FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT, not ") +
             (view.normalized ? "normalized " : "") + component_type_name(type));
  }
  std::vector<Imath::V4f> out(view.count, Imath::V4f(0.0f, 0.0f, 0.0f, 1.0f));
  if (!view.data) {
    if (view.components == 4)
      for (auto& c : out) c.w = 0.0f;  // an accessor without a bufferView is all zeros
    return out;
  }
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    for (int k = 0; k < view.components; ++k) {
      float value;
      if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        value = load<float>(p + 4 * k);
      } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        value = p[k] / 255.0f;
      } else {
        value = load<uint16_t>(p + 2 * k) / 65535.0f;
      }
      if (!std::isfinite(value)) {
        fail(file, view.element(),
             "colour " + std::to_string(i) + " component " + std::to_string(k) + " is not finite");
      }
      // Exporters' float colours stray past 1 by rounding; glTF's range is [0, 1].
      out[i][k] = std::fmin(std::fmax(value, 0.0f), 1.0f);
    }
  }
  return out;
}

std::vector<Imath::V4f> read_tangents(const AccessorView& view, const std::string& file) {
  if (view.components != 4 || view.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT ||
      view.normalized) {
    fail(file, view.element(), "TANGENT must be VEC4 of FLOAT");
  }
  std::vector<Imath::V4f> out(view.count, Imath::V4f(1.0f, 0.0f, 0.0f, 1.0f));
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    const Imath::V3f t(load<float>(p), load<float>(p + 4), load<float>(p + 8));
    const float w = load<float>(p + 12);
    const float length = t.length();
    if (!std::isfinite(length) || !(length > 0.0f) || !std::isfinite(w)) {
      fail(file, view.element(), "tangent " + std::to_string(i) + " is zero or not finite");
    }
    const Imath::V3f u = t / length;
    out[i] = Imath::V4f(u.x, u.y, u.z, w < 0.0f ? -1.0f : 1.0f);
  }
  return out;
}

}  // namespace prism::gltf_detail
