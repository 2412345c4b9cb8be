// libprism_draco.so: the Draco calls of draco_module.h, the only code that includes Draco.
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include "renderer/version.h"
#include "scene_io/draco_module.h"

namespace prism::gltf_detail {
namespace {

// Converts every point's value of `attribute` to T, `components` per point, into `out`.
template <typename T>
bool convert(const draco::PointAttribute& attribute, uint32_t points, int components,
             unsigned char* out) {
  std::vector<T> value(static_cast<std::size_t>(components));
  for (uint32_t i = 0; i < points; ++i) {
    const draco::AttributeValueIndex mapped = attribute.mapped_index(draco::PointIndex(i));
    if (mapped.value() >= attribute.size()) return false;
    if (!attribute.ConvertValue<T>(mapped, static_cast<int8_t>(components), value.data())) {
      return false;
    }
    std::memcpy(out + std::size_t(i) * components * sizeof(T), value.data(),
                components * sizeof(T));
  }
  return true;
}

class Mesh final : public DracoMesh {
 public:
  explicit Mesh(std::unique_ptr<draco::Mesh> mesh) : mesh_(std::move(mesh)) {}

  uint32_t faces() const override { return mesh_->num_faces(); }
  uint32_t points() const override { return mesh_->num_points(); }

  void indices(uint32_t* out) const override {
    for (uint32_t f = 0; f < mesh_->num_faces(); ++f) {
      const draco::Mesh::Face& face = mesh_->face(draco::FaceIndex(f));
      for (int k = 0; k < 3; ++k) out[std::size_t(f) * 3 + k] = face[k].value();
    }
  }

  int attribute_components(uint32_t id) const override {
    const draco::PointAttribute* attribute = mesh_->GetAttributeByUniqueId(id);
    return attribute ? attribute->num_components() : -1;
  }

  bool attribute_values(uint32_t id, DracoComponent type, int components,
                        unsigned char* out) const override {
    const draco::PointAttribute* attribute = mesh_->GetAttributeByUniqueId(id);
    if (!attribute) return false;
    const uint32_t n = mesh_->num_points();
    switch (type) {
      case DracoComponent::int8:
        return convert<int8_t>(*attribute, n, components, out);
      case DracoComponent::uint8:
        return convert<uint8_t>(*attribute, n, components, out);
      case DracoComponent::int16:
        return convert<int16_t>(*attribute, n, components, out);
      case DracoComponent::uint16:
        return convert<uint16_t>(*attribute, n, components, out);
      case DracoComponent::uint32:
        return convert<uint32_t>(*attribute, n, components, out);
      case DracoComponent::float32:
        return convert<float>(*attribute, n, components, out);
    }
    return false;
  }

 private:
  std::unique_ptr<draco::Mesh> mesh_;
};

class Module final : public DracoModule {
 public:
  std::unique_ptr<DracoMesh> decode(const unsigned char* bytes, std::size_t size,
                                    std::string& error) const override {
    draco::DecoderBuffer stream;
    stream.Init(reinterpret_cast<const char*>(bytes), size);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&stream);
    if (!decoded.ok()) {
      error = decoded.status().error_msg_string();
      return nullptr;
    }
    std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (!mesh) {
      error = "not a mesh";
      return nullptr;
    }
    return std::make_unique<Mesh>(std::move(mesh));
  }
};

std::string g_build = std::string(kVersion) + " " + kBuildCommit;

}  // namespace
}  // namespace prism::gltf_detail

extern "C" {
__attribute__((visibility("default"))) const prism::gltf_detail::DracoModule* prism_draco_module() {
  static const prism::gltf_detail::Module module;
  return &module;
}
__attribute__((visibility("default"))) const char* prism_draco_module_build() {
  return prism::gltf_detail::g_build.c_str();
}
}
