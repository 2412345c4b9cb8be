#include "scene_io/gltf_attributes.h"

#include <cmath>
#include <cstdint>

#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

std::vector<Imath::V4f> read_colours(const AccessorView& view, const std::string& file) {
  if (view.components != 3 && view.components != 4)
    fail(file, view.element(), "COLOR_0 must be VEC3 or VEC4");
  expect_float_or_normalized(view, "COLOR_0", file);
  charge(view.count, sizeof(Imath::V4f), view.element());
  std::vector<Imath::V4f> out(view.count, Imath::V4f(0.0f, 0.0f, 0.0f, 1.0f));
  if (!view.data) {
    if (view.components == 4)
      for (auto& c : out) c.w = 0.0f;  // an accessor without a bufferView is all zeros
    return out;
  }
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    for (int k = 0; k < view.components; ++k) {
      const float value = unit_component(view, p, k);
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
  charge(view.count, sizeof(Imath::V4f), view.element());
  std::vector<Imath::V4f> out(view.count, Imath::V4f(1.0f, 0.0f, 0.0f, 1.0f));
  if (!view.data) return out;
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    const Imath::V3f t(unit_component(view, p, 0), unit_component(view, p, 1),
                       unit_component(view, p, 2));
    const float w = unit_component(view, p, 3);
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
