#include "scene_io/gltf_draco.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "scene_io/draco_module.h"
#include "scene_io/gltf_accessors.h"
#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

constexpr const char* kExtension = "KHR_draco_mesh_compression";

// The Draco type of a glTF accessor's component type, or nothing for one Draco cannot make.
std::optional<DracoComponent> draco_component(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return DracoComponent::int8;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return DracoComponent::uint8;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return DracoComponent::int16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return DracoComponent::uint16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return DracoComponent::uint32;
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return DracoComponent::float32;
    default:
      return std::nullopt;
  }
}

class PrimitiveDecoder {
 public:
  PrimitiveDecoder(tinygltf::Model& model, const std::string& file, std::size_t mesh,
                   std::size_t primitive)
      : model_(model),
        file_(file),
        mesh_(mesh),
        primitive_(primitive),
        element_(indexed(indexed("meshes", mesh) + ".primitives", primitive)) {}

  void run(const tinygltf::Value& ext) {
    const std::string ext_element = element_ + ".extensions." + kExtension;
    if (!ext.Has("bufferView") || !ext.Get("bufferView").IsInt()) {
      fail(file_, ext_element + ".bufferView", "expected a bufferView index");
    }
    if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) {
      fail(file_, ext_element + ".attributes", "expected an object");
    }
    const std::unique_ptr<DracoMesh> mesh =
        decode(ext.Get("bufferView").GetNumberAsInt(), ext_element);
    if (mesh->faces() == 0) fail(file_, ext_element, "the Draco mesh has no triangles");

    // Everything below only appends to model_: references into it are re-taken after.
    tinygltf::Primitive& primitive = this->primitive();
    if (primitive.mode >= 0 && primitive.mode != TINYGLTF_MODE_TRIANGLES &&
        primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP) {
      fail(file_, element_ + ".mode", "Draco compresses triangles only");
    }
    const int indices = this->primitive().indices;
    if (indices >= 0) {
      const std::size_t expected = 3 * std::size_t(mesh->faces());
      const std::size_t declared = accessor(indices, element_ + ".indices").count;
      if (declared != expected) {
        fail(file_, element_ + ".indices",
             "accessor count " + std::to_string(declared) + " but the Draco mesh has " +
                 std::to_string(mesh->faces()) + " triangles");
      }
    }
    const int new_indices = decoded_indices(*mesh);
    this->primitive().indices = new_indices;

    const tinygltf::Value& attributes = ext.Get("attributes");
    for (const std::string& name : attributes.Keys()) {
      const std::string attr_element = ext_element + ".attributes." + name;
      const tinygltf::Value& id = attributes.Get(name);
      if (!id.IsInt() || id.GetNumberAsInt() < 0) fail(file_, attr_element, "expected an id");
      const auto it = this->primitive().attributes.find(name);
      if (it == this->primitive().attributes.end()) {
        fail(file_, attr_element, "the primitive has no attribute " + name);
      }
      const int decoded = decoded_attribute(*mesh, uint32_t(id.GetNumberAsInt()), it->second,
                                            element_ + ".attributes." + name, attr_element);
      this->primitive().attributes[name] = decoded;
    }
    this->primitive().mode = TINYGLTF_MODE_TRIANGLES;
    this->primitive().extensions.erase(kExtension);
  }

 private:
  tinygltf::Primitive& primitive() { return model_.meshes[mesh_].primitives[primitive_]; }

  const tinygltf::Accessor& accessor(int index, const std::string& referrer) const {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size()) {
      fail(file_, referrer,
           "accessor " + std::to_string(index) + " out of range (" +
               std::to_string(model_.accessors.size()) + " accessors)");
    }
    return model_.accessors[static_cast<std::size_t>(index)];
  }

  std::unique_ptr<DracoMesh> decode(int view_index, const std::string& ext_element) const {
    if (view_index < 0 || static_cast<std::size_t>(view_index) >= model_.bufferViews.size()) {
      fail(file_, ext_element + ".bufferView",
           "bufferView " + std::to_string(view_index) + " out of range (" +
               std::to_string(model_.bufferViews.size()) + " bufferViews)");
    }
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(view_index)];
    const std::string view_element = indexed("bufferViews", static_cast<std::size_t>(view_index));
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size()) {
      fail(file_, view_element + ".buffer",
           "buffer " + std::to_string(view.buffer) + " out of range");
    }
    const std::vector<unsigned char>& buffer =
        model_.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
      fail(file_, view_element, "byteOffset + byteLength exceeds its buffer");
    }
    std::string error;
    const DracoModule* draco = draco_module(error);
    if (!draco) fail(file_, ext_element, error);
    std::unique_ptr<DracoMesh> mesh =
        draco->decode(buffer.data() + view.byteOffset, view.byteLength, error);
    if (!mesh) fail(file_, ext_element, "Draco cannot decode it: " + error);
    return mesh;
  }

  int add_accessor(tinygltf::Accessor accessor, std::vector<unsigned char> bytes) {
    accessor.bufferView = append_buffer_view(model_, std::move(bytes));
    accessor.byteOffset = 0;
    accessor.sparse.isSparse = false;
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size() - 1);
  }

  int decoded_indices(const DracoMesh& mesh) {
    const std::size_t count = std::size_t(mesh.faces()) * 3;
    charge(count, sizeof(uint32_t), element_ + ".indices");
    std::vector<uint32_t> indices(count);
    mesh.indices(indices.data());
    std::vector<unsigned char> bytes(count * sizeof(uint32_t));
    std::memcpy(bytes.data(), indices.data(), bytes.size());
    tinygltf::Accessor a;
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = count;
    return add_accessor(a, std::move(bytes));
  }

  int decoded_attribute(const DracoMesh& mesh, uint32_t id, int accessor_index,
                        const std::string& referrer, const std::string& attr_element) {
    const int draco_components = mesh.attribute_components(id);
    if (draco_components < 0) {
      fail(file_, attr_element, "the Draco mesh has no attribute with id " + std::to_string(id));
    }
    const tinygltf::Accessor original = accessor(accessor_index, referrer);
    const std::string element = indexed("accessors", std::size_t(accessor_index));
    const std::size_t element_size = accessor_element_size(original.componentType, original.type);
    if (element_size == 0) fail(file_, element, "componentType or type is invalid");
    const int components =
        static_cast<int>(element_size / tinygltf::GetComponentSizeInBytes(original.componentType));
    if (draco_components != components) {
      fail(file_, attr_element,
           "the Draco attribute has " + std::to_string(draco_components) + " components but " +
               element + " has " + std::to_string(components));
    }
    if (original.count != mesh.points()) {
      fail(file_, element,
           "count " + std::to_string(original.count) + " but the Draco mesh has " +
               std::to_string(mesh.points()) + " points");
    }
    const std::optional<DracoComponent> type = draco_component(original.componentType);
    charge(mesh.points(), element_size, attr_element);
    std::vector<unsigned char> bytes(std::size_t(mesh.points()) * element_size);
    if (!type || !mesh.attribute_values(id, *type, components, bytes.data())) {
      fail(file_, attr_element, "Draco cannot convert the attribute to the accessor's type");
    }
    return add_accessor(original, std::move(bytes));
  }

  tinygltf::Model& model_;
  const std::string& file_;
  std::size_t mesh_;
  std::size_t primitive_;
  std::string element_;
};

}  // namespace

std::optional<nlohmann::json> draco_json_for_tinygltf(const nlohmann::json& root) {
  // check_gltf_json has checked the types of everything read here.
  const auto meshes = root.find("meshes");
  const auto accessors = root.find("accessors");
  if (meshes == root.end() || accessors == root.end()) return std::nullopt;
  std::optional<nlohmann::json> patched;
  for (std::size_t m = 0; m < meshes->size(); ++m) {
    const nlohmann::json& primitives = (*meshes)[m]["primitives"];
    for (std::size_t p = 0; p < primitives.size(); ++p) {
      const nlohmann::json& primitive = primitives[p];
      const auto extensions = primitive.find("extensions");
      const auto indices = primitive.find("indices");
      if (extensions == primitive.end() || indices == primitive.end()) continue;
      const auto draco = extensions->find(kExtension);
      if (draco == extensions->end()) continue;
      const auto index = indices->get<std::size_t>();
      if (index >= accessors->size() || (*accessors)[index].contains("bufferView")) continue;
      if (!patched) patched = root;
      (*patched)["accessors"][index]["bufferView"] = (*draco)["bufferView"];
    }
  }
  return patched;
}

void decode_draco_primitives(tinygltf::Model& model, const std::string& file) {
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      const auto& extensions = model.meshes[m].primitives[p].extensions;
      const auto it = extensions.find(kExtension);
      if (it == extensions.end()) continue;
      const tinygltf::Value ext = it->second;  // a copy: the primitive's map is edited
      PrimitiveDecoder(model, file, m, p).run(ext);
    }
  }
}

}  // namespace prism::gltf_detail
