#include "scene_io/gltf_json_check.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "scene_io/gltf_error.h"
#include "scene_io/gltf_extensions.h"

namespace prism::gltf_detail {

namespace {

using nlohmann::json;

class Checker {
 public:
  explicit Checker(const std::string& file) : file_(file) {}

  [[noreturn]] void error(const std::string& path, const std::string& what) const {
    fail(file_, path, what);
  }

  static std::string member(const std::string& path, const char* key) {
    return path.empty() ? std::string(key) : path + "." + key;
  }

  static std::string type_name(const json& j) {
    if (j.is_number()) return "a number";
    if (j.is_string()) return "a string";
    if (j.is_boolean()) return "a boolean";
    if (j.is_array()) return "an array";
    if (j.is_object()) return "an object";
    return "null";
  }

  // The properties every glTF object may carry. Extension values must be objects (glTF's
  // glTFProperty schema); their contents are only checked for the extensions Prism reads.
  void object(const json& j, const std::string& path) const {
    if (!j.is_object()) error(path, "expected an object, got " + type_name(j));
    string(j, "name", path);
    if (auto it = j.find("extensions"); it != j.end()) {
      const std::string ext_path = member(path, "extensions");
      if (!it->is_object()) error(ext_path, "expected an object, got " + type_name(*it));
      for (const auto& [name, value] : it->items()) {
        if (!value.is_object()) {
          error(ext_path + "." + name, "expected an object, got " + type_name(value));
        }
      }
    }
  }

  const json* find(const json& obj, const char* key, const std::string& path, bool required) const {
    auto it = obj.find(key);
    if (it == obj.end()) {
      if (required) error(member(path, key), "required property is missing");
      return nullptr;
    }
    return &*it;
  }

  // An integer stored by nlohmann as any number type; integral floats such as 2.0 are accepted
  // because some exporters write them, fractions are not.
  static bool integral(const json& j, double lo, double hi) {
    if (j.is_number_unsigned()) return static_cast<double>(j.get<std::uint64_t>()) <= hi;
    if (j.is_number_integer()) {
      const auto v = static_cast<double>(j.get<std::int64_t>());
      return v >= lo && v <= hi;
    }
    if (j.is_number_float()) {
      const double v = j.get<double>();
      return std::isfinite(v) && std::floor(v) == v && v >= lo && v <= hi;
    }
    return false;
  }

  // tinygltf stores indices as int.
  void index(const json& obj, const char* key, const std::string& path,
             bool required = false) const {
    if (const json* j = find(obj, key, path, required)) check_index(*j, member(path, key));
  }

  void check_index(const json& j, const std::string& path) const {
    if (!integral(j, 0, std::numeric_limits<int>::max())) {
      error(path, "expected an index (a non-negative integer), got " + describe(j));
    }
  }

  // Byte offsets, lengths and counts; glTF allows up to 2^53, tinygltf reads them as size_t.
  void unsigned_int(const json& obj, const char* key, const std::string& path, bool required,
                    double minimum = 0) const {
    if (const json* j = find(obj, key, path, required)) {
      if (!integral(*j, minimum, 9007199254740991.0)) {
        error(member(path, key),
              "expected an integer >= " + std::to_string(int(minimum)) + ", got " + describe(*j));
      }
    }
  }

  // Enumerations and small counts that tinygltf stores as int: a value such as 2^32 + 4 would
  // be truncated to 4 and mean something else.
  void int_value(const json& obj, const char* key, const std::string& path, bool required) const {
    if (const json* j = find(obj, key, path, required)) {
      if (!integral(*j, 0, std::numeric_limits<int>::max())) {
        error(member(path, key), "expected an integer in [0, 2^31 - 1], got " + describe(*j));
      }
    }
  }

  void number(const json& obj, const char* key, const std::string& path,
              bool required = false) const {
    if (const json* j = find(obj, key, path, required)) check_number(*j, member(path, key));
  }

  void check_number(const json& j, const std::string& path) const {
    if (!j.is_number()) error(path, "expected a number, got " + describe(j));
    if (!std::isfinite(j.get<double>())) error(path, "number is not finite");
  }

  void number_array(const json& obj, const char* key, const std::string& path,
                    std::size_t size) const {
    const json* j = find(obj, key, path, false);
    if (!j) return;
    const std::string p = member(path, key);
    if (!j->is_array()) error(p, "expected an array, got " + type_name(*j));
    if (size != 0 && j->size() != size) {
      error(p, "expected " + std::to_string(size) + " numbers, got " + std::to_string(j->size()));
    }
    for (std::size_t i = 0; i < j->size(); ++i) check_number((*j)[i], indexed(p, i));
  }

  void index_array(const json& obj, const char* key, const std::string& path) const {
    const json* j = find(obj, key, path, false);
    if (!j) return;
    const std::string p = member(path, key);
    if (!j->is_array()) error(p, "expected an array, got " + type_name(*j));
    for (std::size_t i = 0; i < j->size(); ++i) check_index((*j)[i], indexed(p, i));
  }

  void string(const json& obj, const char* key, const std::string& path,
              bool required = false) const {
    if (const json* j = find(obj, key, path, required); j && !j->is_string()) {
      error(member(path, key), "expected a string, got " + describe(*j));
    }
  }

  void boolean(const json& obj, const char* key, const std::string& path) const {
    if (const json* j = find(obj, key, path, false); j && !j->is_boolean()) {
      error(member(path, key), "expected a boolean, got " + describe(*j));
    }
  }

  // Calls check(element, path) for each element of an optional array of objects.
  template <typename F>
  void object_array(const json& obj, const char* key, const std::string& path, F check,
                    bool required = false, bool non_empty = false) const {
    const json* j = find(obj, key, path, required);
    if (!j) return;
    const std::string p = member(path, key);
    if (!j->is_array()) error(p, "expected an array, got " + type_name(*j));
    if (non_empty && j->empty()) error(p, "array must not be empty");
    for (std::size_t i = 0; i < j->size(); ++i) {
      const std::string element = indexed(p, i);
      object((*j)[i], element);
      check((*j)[i], element);
    }
  }

  // An optional member that must be an object when present; returns it for further checks.
  const json* sub_object(const json& obj, const char* key, const std::string& path,
                         bool required = false) const {
    const json* j = find(obj, key, path, required);
    if (j) object(*j, member(path, key));
    return j;
  }

  void texture_info(const json& obj, const char* key, const std::string& path) const {
    if (const json* t = sub_object(obj, key, path)) {
      const std::string p = member(path, key);
      index(*t, "index", p, true);
      int_value(*t, "texCoord", p, false);
      number(*t, "scale", p);
      number(*t, "strength", p);
    }
  }

  static std::string describe(const json& j) {
    if (j.is_number() || j.is_boolean()) return j.dump();
    if (j.is_string()) {
      std::string s = j.get<std::string>();
      if (s.size() > 40) s = s.substr(0, 40) + "...";
      return "\"" + s + "\"";
    }
    return type_name(j);
  }

 private:
  const std::string& file_;
};

void check_extension_list(const Checker& c, const json& root, const char* key) {
  const json* list = c.find(root, key, "", false);
  if (!list) return;
  if (!list->is_array()) c.error(key, "expected an array, got " + Checker::type_name(*list));
  for (std::size_t i = 0; i < list->size(); ++i) {
    if (!(*list)[i].is_string()) {
      c.error(indexed(key, i), "expected a string, got " + Checker::describe((*list)[i]));
    }
  }
}

void check_material(const Checker& c, const json& m, const std::string& p) {
  if (const json* pbr = c.sub_object(m, "pbrMetallicRoughness", p)) {
    const std::string pp = Checker::member(p, "pbrMetallicRoughness");
    c.number_array(*pbr, "baseColorFactor", pp, 4);
    c.texture_info(*pbr, "baseColorTexture", pp);
    c.number(*pbr, "metallicFactor", pp);
    c.number(*pbr, "roughnessFactor", pp);
    c.texture_info(*pbr, "metallicRoughnessTexture", pp);
  }
  c.texture_info(m, "normalTexture", p);
  c.texture_info(m, "occlusionTexture", p);
  c.texture_info(m, "emissiveTexture", p);
  c.number_array(m, "emissiveFactor", p, 3);
  c.string(m, "alphaMode", p);
  c.number(m, "alphaCutoff", p);
  c.boolean(m, "doubleSided", p);
  if (auto ext = m.find("extensions"); ext != m.end()) {
    const std::string ep = Checker::member(p, "extensions");
    if (auto t = ext->find("KHR_materials_transmission"); t != ext->end()) {
      c.number(*t, "transmissionFactor", ep + ".KHR_materials_transmission");
      c.texture_info(*t, "transmissionTexture", ep + ".KHR_materials_transmission");
    }
    if (auto t = ext->find("KHR_materials_volume"); t != ext->end()) {
      const std::string vp = ep + ".KHR_materials_volume";
      c.number(*t, "thicknessFactor", vp);
      c.texture_info(*t, "thicknessTexture", vp);
      c.number(*t, "attenuationDistance", vp);
      c.number_array(*t, "attenuationColor", vp, 3);
    }
    if (auto t = ext->find("KHR_materials_ior"); t != ext->end()) {
      c.number(*t, "ior", ep + ".KHR_materials_ior");
    }
    if (auto t = ext->find("KHR_materials_specular"); t != ext->end()) {
      c.number(*t, "specularFactor", ep + ".KHR_materials_specular");
      c.number_array(*t, "specularColorFactor", ep + ".KHR_materials_specular", 3);
      c.texture_info(*t, "specularTexture", ep + ".KHR_materials_specular");
      c.texture_info(*t, "specularColorTexture", ep + ".KHR_materials_specular");
    }
    if (auto t = ext->find("KHR_materials_clearcoat"); t != ext->end()) {
      const std::string cp = ep + ".KHR_materials_clearcoat";
      c.number(*t, "clearcoatFactor", cp);
      c.number(*t, "clearcoatRoughnessFactor", cp);
      for (const char* slot :
           {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"})
        c.texture_info(*t, slot, cp);
    }
    if (auto t = ext->find("KHR_materials_sheen"); t != ext->end()) {
      const std::string sp = ep + ".KHR_materials_sheen";
      c.number_array(*t, "sheenColorFactor", sp, 3);
      c.number(*t, "sheenRoughnessFactor", sp);
      c.texture_info(*t, "sheenColorTexture", sp);
      c.texture_info(*t, "sheenRoughnessTexture", sp);
    }
    if (auto t = ext->find("KHR_materials_emissive_strength"); t != ext->end()) {
      c.number(*t, "emissiveStrength", ep + ".KHR_materials_emissive_strength");
    }
    if (auto t = ext->find("KHR_materials_pbrSpecularGlossiness"); t != ext->end()) {
      const std::string sp = ep + ".KHR_materials_pbrSpecularGlossiness";
      c.number_array(*t, "diffuseFactor", sp, 4);
      c.number_array(*t, "specularFactor", sp, 3);
      c.number(*t, "glossinessFactor", sp);
      c.texture_info(*t, "diffuseTexture", sp);
      c.texture_info(*t, "specularGlossinessTexture", sp);
    }
  }
}

void check_node(const Checker& c, const json& n, const std::string& p) {
  c.index(n, "camera", p);
  c.index(n, "mesh", p);
  c.index(n, "skin", p);
  c.index_array(n, "children", p);
  c.number_array(n, "matrix", p, 16);
  c.number_array(n, "rotation", p, 4);
  c.number_array(n, "scale", p, 3);
  c.number_array(n, "translation", p, 3);
  c.number_array(n, "weights", p, 0);
  if (auto ext = n.find("extensions"); ext != n.end()) {
    const std::string ep = Checker::member(p, "extensions");
    if (auto l = ext->find("KHR_lights_punctual"); l != ext->end()) {
      c.index(*l, "light", ep + ".KHR_lights_punctual", true);
    }
    if (auto s = ext->find("PRISM_sphere"); s != ext->end()) {
      c.number(*s, "radius", ep + ".PRISM_sphere", true);
      c.index(*s, "material", ep + ".PRISM_sphere");
    }
  }
}

void check_primitive(const Checker& c, const json& prim, const std::string& p) {
  const json* attributes = c.sub_object(prim, "attributes", p, true);
  for (const auto& [name, value] : attributes->items()) {
    c.check_index(value, p + ".attributes." + name);
  }
  c.index(prim, "indices", p);
  c.index(prim, "material", p);
  c.int_value(prim, "mode", p, false);
  c.object_array(prim, "targets", p, [&](const json& target, const std::string& tp) {
    for (const auto& [name, value] : target.items()) c.check_index(value, tp + "." + name);
  });
  if (auto ext = prim.find("extensions"); ext != prim.end()) {
    if (auto d = ext->find("KHR_draco_mesh_compression"); d != ext->end()) {
      const std::string dp = p + ".extensions.KHR_draco_mesh_compression";
      c.index(*d, "bufferView", dp, true);
      const json* attributes = c.sub_object(*d, "attributes", dp, true);
      for (const auto& [name, value] : attributes->items()) {
        c.check_index(value, dp + ".attributes." + name);
      }
    }
  }
}

void check_camera(const Checker& c, const json& cam, const std::string& p) {
  c.string(cam, "type", p, true);
  const std::string type = cam["type"].get<std::string>();
  if (type != "perspective" && type != "orthographic") {
    c.error(p + ".type", "unknown camera type " + shown(type));
  }
  if (const json* persp = c.sub_object(cam, "perspective", p, type == "perspective")) {
    const std::string pp = p + ".perspective";
    c.number(*persp, "aspectRatio", pp);
    c.number(*persp, "yfov", pp, true);
    c.number(*persp, "zfar", pp);
    c.number(*persp, "znear", pp, true);
  }
  if (const json* ortho = c.sub_object(cam, "orthographic", p, type == "orthographic")) {
    const std::string op = p + ".orthographic";
    for (const char* key : {"xmag", "ymag", "zfar", "znear"}) c.number(*ortho, key, op, true);
  }
}

// tinygltf 2.7 decodes images stored in a bufferView while parsing, without checking that the
// view lies inside its buffer; it would read past the buffer's end. Buffers it loads always hold
// exactly their declared byteLength, so checking against the declared length here suffices.
void check_image_buffer_views(const Checker& c, const json& root) {
  auto images = root.find("images");
  if (images == root.end()) return;
  const json empty = json::array();
  auto views_it = root.find("bufferViews");
  auto buffers_it = root.find("buffers");
  const json& views = views_it != root.end() ? *views_it : empty;
  const json& buffers = buffers_it != root.end() ? *buffers_it : empty;
  for (std::size_t i = 0; i < images->size(); ++i) {
    auto view_index = (*images)[i].find("bufferView");
    if (view_index == (*images)[i].end()) continue;
    const std::string p = indexed("images", i) + ".bufferView";
    const auto v = view_index->get<std::size_t>();
    if (v >= views.size()) {
      c.error(p, "bufferView " + std::to_string(v) + " out of range (" +
                     std::to_string(views.size()) + " bufferViews)");
    }
    const json& view = views[v];
    const auto b = view["buffer"].get<std::size_t>();
    const std::string vp = indexed("bufferViews", v);
    if (b >= buffers.size()) {
      c.error(vp + ".buffer", "buffer " + std::to_string(b) + " out of range (" +
                                  std::to_string(buffers.size()) + " buffers)");
    }
    const auto offset = view.value("byteOffset", json(0)).get<double>();
    const auto length = view["byteLength"].get<double>();
    const auto buffer_length = buffers[b]["byteLength"].get<double>();
    if (offset + length > buffer_length) {
      c.error(vp, "byteOffset + byteLength exceeds the byteLength of buffers[" + std::to_string(b) +
                      "]");
    }
  }
}

}  // namespace

void check_gltf_json(const nlohmann::json& root, const std::string& file,
                     std::vector<std::string>& warnings) {
  const Checker c(file);
  if (!root.is_object()) c.error("glTF", "the JSON document is not an object");

  // Checked first: a file needing an extension Prism lacks (e.g. Draco) is otherwise reported
  // as some confusing consequence of not decoding it.
  check_extension_list(c, root, "extensionsUsed");
  check_extension_list(c, root, "extensionsRequired");
  if (auto req = root.find("extensionsRequired"); req != root.end()) {
    for (const auto& name : *req) {
      if (!is_supported_extension(name.get<std::string>())) {
        c.error("extensionsRequired",
                "extension " + shown(name.get<std::string>()) + " is required but not supported");
      }
    }
  }
  if (auto used = root.find("extensionsUsed"); used != root.end()) {
    for (const auto& name : *used) {
      if (!is_supported_extension(name.get<std::string>())) {
        warnings.push_back(warning("extensionsUsed", "extension " + shown(name.get<std::string>()) +
                                                         " is not supported and is ignored"));
      }
    }
  }

  const json* asset = c.sub_object(root, "asset", "", true);
  c.string(*asset, "version", "asset", true);
  const std::string version = (*asset)["version"].get<std::string>();
  if (version.rfind("2.", 0) != 0) {
    c.error("asset.version", "glTF version " + version + " is not supported (2.x only)");
  }
  c.object(root, "");
  c.index(root, "scene", "");

  auto nothing = [](const json&, const std::string&) {};
  c.object_array(root, "scenes", "",
                 [&](const json& s, const std::string& p) { c.index_array(s, "nodes", p); });
  c.object_array(root, "nodes", "",
                 [&](const json& n, const std::string& p) { check_node(c, n, p); });
  c.object_array(root, "meshes", "", [&](const json& m, const std::string& p) {
    c.object_array(
        m, "primitives", p,
        [&](const json& prim, const std::string& pp) { check_primitive(c, prim, pp); }, true, true);
    c.number_array(m, "weights", p, 0);
  });
  c.object_array(root, "accessors", "", [&](const json& a, const std::string& p) {
    c.index(a, "bufferView", p);
    c.unsigned_int(a, "byteOffset", p, false);
    c.int_value(a, "componentType", p, true);
    c.boolean(a, "normalized", p);
    c.unsigned_int(a, "count", p, true, 1);
    c.string(a, "type", p, true);
    c.number_array(a, "min", p, 0);
    c.number_array(a, "max", p, 0);
    if (const json* sparse = c.sub_object(a, "sparse", p)) {
      // tinygltf stores the count and byte offsets of sparse accessors as int.
      const std::string sp = p + ".sparse";
      const json* count = c.find(*sparse, "count", sp, true);
      if (!Checker::integral(*count, 1, std::numeric_limits<int>::max())) {
        c.error(sp + ".count", "expected an integer >= 1, got " + Checker::describe(*count));
      }
      for (const char* part : {"indices", "values"}) {
        const json* o = c.sub_object(*sparse, part, sp, true);
        const std::string pp = sp + "." + part;
        c.index(*o, "bufferView", pp, true);
        c.index(*o, "byteOffset", pp);
        if (std::string(part) == "indices") c.int_value(*o, "componentType", pp, true);
      }
    }
  });
  c.object_array(root, "bufferViews", "", [&](const json& v, const std::string& p) {
    c.index(v, "buffer", p, true);
    c.unsigned_int(v, "byteOffset", p, false);
    c.unsigned_int(v, "byteLength", p, true, 1);
    c.unsigned_int(v, "byteStride", p, false, 4);
    c.int_value(v, "target", p, false);
  });
  c.object_array(root, "buffers", "", [&](const json& b, const std::string& p) {
    c.string(b, "uri", p);
    c.unsigned_int(b, "byteLength", p, true, 1);
  });
  c.object_array(root, "materials", "",
                 [&](const json& m, const std::string& p) { check_material(c, m, p); });
  c.object_array(root, "textures", "", [&](const json& t, const std::string& p) {
    c.index(t, "sampler", p);
    c.index(t, "source", p);
  });
  c.object_array(root, "images", "", [&](const json& i, const std::string& p) {
    c.string(i, "uri", p);
    c.string(i, "mimeType", p);
    c.index(i, "bufferView", p);
  });
  check_image_buffer_views(c, root);
  c.object_array(root, "samplers", "", [&](const json& s, const std::string& p) {
    for (const char* key : {"magFilter", "minFilter", "wrapS", "wrapT"}) {
      c.int_value(s, key, p, false);
    }
  });
  c.object_array(root, "cameras", "",
                 [&](const json& cam, const std::string& p) { check_camera(c, cam, p); });
  c.object_array(root, "skins", "", [&](const json& s, const std::string& p) {
    c.index(s, "inverseBindMatrices", p);
    c.index(s, "skeleton", p);
    if (!s.contains("joints")) c.error(p + ".joints", "required property is missing");
    c.index_array(s, "joints", p);
  });
  c.object_array(root, "animations", "", nothing);

  if (auto ext = root.find("extensions"); ext != root.end()) {
    if (auto lights = ext->find("KHR_lights_punctual"); lights != ext->end()) {
      c.object_array(*lights, "lights", "extensions.KHR_lights_punctual",
                     [&](const json& l, const std::string& p) {
                       c.string(l, "type", p, true);
                       c.number_array(l, "color", p, 3);
                       c.number(l, "intensity", p);
                       c.number(l, "range", p);
                       if (const json* spot = c.sub_object(l, "spot", p)) {
                         c.number(*spot, "innerConeAngle", p + ".spot");
                         c.number(*spot, "outerConeAngle", p + ".spot");
                       }
                     });
    }
  }
}

}  // namespace prism::gltf_detail
