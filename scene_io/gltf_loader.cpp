#include "scene_io/gltf_loader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include <Imath/ImathBox.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include "renderer/geometry/tangents.h"
#include "renderer/math.h"
#include "renderer/parallel_index.h"
#include "scene_io/gltf_accessors.h"
#include "scene_io/gltf_attributes.h"
#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_draco.h"
#include "scene_io/gltf_error.h"
#include "scene_io/gltf_extensions.h"
#include "scene_io/gltf_files.h"
#include "scene_io/gltf_glb.h"
#include "scene_io/gltf_images.h"
#include "scene_io/gltf_json_check.h"
#include "scene_io/gltf_limits.h"
#include "scene_io/gltf_rest_pose.h"
#include "scene_io/gltf_scene_select.h"
#include "scene_io/gltf_sparse.h"

namespace prism {

namespace {

using namespace gltf_detail;

constexpr double kPi = 3.14159265358979323846;

// The renderer holds colours, intensities and vertex positions as float: a value that is finite
// as a double may not be.
bool finite_float(double v) {
  return std::isfinite(v) && std::fabs(v) <= double(std::numeric_limits<float>::max());
}

std::vector<unsigned char> read_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "file", "does not exist");
  // tinygltf takes lengths as unsigned int. The user named this file, so a symlink is followed.
  return read_regular_file(path, std::numeric_limits<unsigned int>::max() - 1, std::nullopt, "file",
                           path, /*follow_symlink=*/true);
}

bool is_glb(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

nlohmann::json parse_json(const std::string& text, const std::string& file) {
  // Depth is checked on the text before parsing, so that neither nlohmann nor tinygltf's
  // recursive conversion of extras ever holds a too-deep document. (nlohmann's parser callback
  // could do it, but makes parsing a million-object file take minutes.)
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > gltf_limits::kMaxJsonDepth) {
        fail(file, "JSON",
             "nested deeper than " + std::to_string(gltf_limits::kMaxJsonDepth) + " levels");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // Drop nlohmann's "[json.exception.parse_error.101] " tag: it means nothing to a user.
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0) {
      if (auto end = what.find("] "); end != std::string::npos) what = what.substr(end + 2);
    }
    fail(file, "JSON", what);
  }
}

// Decoded size of `length` base64 characters (without '=' padding), as tinygltf's decoder
// counts them: 3 bytes per 4 characters, and 1 or 2 bytes for a final 2 or 3.
std::size_t base64_decoded_size(std::size_t length) {
  return length / 4 * 3 + (length % 4 == 0 ? 0 : length % 4 - 1);
}

// The media types glTF allows in data: URIs, with the base64 encoding tinygltf decodes
// (tinygltf treats a data: URI of any other type as a file path).
const std::vector<std::string> kBufferMediaTypes = {"application/octet-stream",
                                                    "application/gltf-buffer"};
const std::vector<std::string> kImageMediaTypes = {"image/png", "image/jpeg"};

// A data: URI's media type and size, from its text, before tinygltf decodes it: tinygltf
// requires a buffer's decoded size to equal byteLength but only says "failed" when it does
// not, and it would decode a URI of any size first. Returns the media type.
std::string check_data_uri(const std::string& uri, const nlohmann::json& object, bool is_buffer,
                           const std::string& element, const std::string& file) {
  const std::vector<std::string>& allowed = is_buffer ? kBufferMediaTypes : kImageMediaTypes;
  std::string type;
  for (const std::string& t : allowed) {
    if (uri.rfind("data:" + t + ";base64,", 0) == 0) type = t;
  }
  if (type.empty()) {
    for (const std::string& t : allowed)
      if (uri.rfind("data:" + t + ",", 0) == 0 || uri.rfind("data:" + t + ";", 0) == 0)
        fail(file, element, "only base64 data: URIs are supported");
    const std::size_t end = std::min(uri.find_first_of(";,"), uri.size());
    fail(file, element,
         "data: URI of media type " + shown(uri.substr(5, end - 5)) + " is not allowed for " +
             (is_buffer ? "a buffer" : "an image") + " (only base64 " + allowed[0] + " or " +
             allowed[1] + ")");
  }
  const std::size_t comma = uri.find(',');
  const std::size_t length = uri.size() - comma - 1;
  std::size_t padding = 0;
  while (padding < length && padding < 2 && uri[uri.size() - 1 - padding] == '=') ++padding;
  const std::size_t decoded = base64_decoded_size(length - padding);
  if (decoded > gltf_limits::kMaxDataUriBytes) {
    fail(file, element,
         "data URI of " + std::to_string(decoded) + " bytes exceeds the limit of " +
             std::to_string(gltf_limits::kMaxDataUriBytes));
  }
  if (is_buffer) {
    // check_gltf_json has made byteLength an integer >= 1.
    const auto declared = object["byteLength"].get<std::uint64_t>();
    if (decoded != declared) {
      fail(file, element,
           "data URI holds " + std::to_string(decoded) + " bytes but byteLength is " +
               std::to_string(declared));
    }
  }
  // tinygltf's decoded copy; the base64 text is the file's own bytes.
  charge(decoded, 1, element);
  return type;
}

// Every buffer and image URI: data URIs typed and sized, files admitted by the FileGate
// (inside the asset's folder unless the caller allows otherwise, present, regular) and
// replaced in `root` by the gate's tokens. Returns each image's declared media type.
std::vector<std::string> check_uris(nlohmann::json& root, FileGate& gate, const std::string& file) {
  std::vector<std::string> declared;
  for (const char* array : {"buffers", "images"}) {
    auto it = root.find(array);
    if (it == root.end()) continue;
    const bool is_buffer = std::string(array) == "buffers";
    for (std::size_t i = 0; i < it->size(); ++i) {
      nlohmann::json& object = (*it)[i];
      std::string type = is_buffer ? "" : object.value("mimeType", std::string());
      if (auto uri = object.find("uri"); uri != object.end()) {
        const std::string element = indexed(array, i) + ".uri";
        const std::string text = uri->get<std::string>();
        if (text.rfind("data:", 0) == 0) {
          const std::string data_type = check_data_uri(text, object, is_buffer, element, file);
          if (!is_buffer && type.empty()) type = data_type;
        } else {
          const std::optional<std::size_t> exact =
              is_buffer ? std::optional<std::size_t>(object["byteLength"].get<std::size_t>())
                        : std::nullopt;
          *uri = gate.admit(text, element, exact,
                            is_buffer ? std::numeric_limits<unsigned int>::max() - 1
                                      : gltf_limits::kMaxImageFileBytes);
        }
      }
      if (!is_buffer) declared.push_back(type);
    }
  }
  return declared;
}

// tinygltf keeps every object of the file in memory, a few hundred bytes each.
void check_object_count(const nlohmann::json& root, const std::string& file) {
  std::size_t count = 0;
  for (const auto& [key, value] : root.items()) {
    if (!value.is_array()) continue;
    count += value.size();
    if (key == "meshes") {
      for (const auto& mesh : value) {
        if (auto p = mesh.find("primitives"); p != mesh.end() && p->is_array()) count += p->size();
      }
    }
  }
  if (count > gltf_limits::kMaxObjects) {
    fail(file, "glTF",
         std::to_string(count) + " objects exceed the limit of " +
             std::to_string(gltf_limits::kMaxObjects));
  }
}

const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& extensions, const char* name) {
  auto it = extensions.find(name);
  if (it == extensions.end() || !it->second.IsObject()) return nullptr;
  return &it->second;
}

class Converter final : public MaterialExtensionReader {
 public:
  Converter(const tinygltf::Model& model, const std::string& file, const std::string& scene,
            SceneDescription& out)
      : model_(model), file_(file), out_(out), scene_(scene) {}

  void convert() {
    for (std::size_t i = 0; i < model_.materials.size(); ++i) {
      out_.materials.push_back(material(i));
    }
    decode_texture_images();
    traverse(scene_roots());
  }

 private:
  void warn(const std::string& element, const std::string& what) override {
    out_.warnings.push_back(warning(element, what));
  }

  [[noreturn]] void error(const std::string& element, const std::string& what) const override {
    fail(file_, element, what);
  }

  // MaterialExtensionReader, for the extension handlers of gltf_extensions.h.
  double number(const tinygltf::Value& ext, const char* key, double fallback,
                const std::string& element) const override {
    return extension_number(ext, key, fallback, element);
  }
  float unit(double value, const std::string& element) const override {
    return unit_factor(value, element);
  }
  int texture(const tinygltf::TextureInfo& info, TextureEncoding encoding,
              const std::string& element, TextureMapping* mapping) override {
    return texture<tinygltf::TextureInfo>(info, encoding, element, mapping);
  }
  const std::string& file() const override { return file_; }

  // A name from the file as the scene description carries it to terminals, reports and EXR
  // metadata: control characters escaped, at most 256 bytes; the element when it has none.
  static std::string display_name(const std::string& name, const std::string& element) {
    if (name.empty()) return element;
    const std::string escaped = printable(name.substr(0, 256));
    return name.size() > 256 ? escaped + "..." : escaped;
  }

  void check_index(int index, std::size_t size, const std::string& element,
                   const char* what) const {
    if (index < 0 || static_cast<std::size_t>(index) >= size) {
      error(element, std::string(what) + " " + std::to_string(index) + " out of range (" +
                         std::to_string(size) + " " + what + "s)");
    }
  }

  // ---- materials and textures ----

  float unit_factor(double value, const std::string& element) const {
    if (!std::isfinite(value) || value < 0.0 || value > 1.0) {
      error(element, "value " + number_text(value) + " is outside [0, 1]");
    }
    return static_cast<float>(value);
  }

  C3f colour(const std::vector<double>& values, const std::string& element) const {
    if (values.size() < 3) error(element, "expected at least 3 numbers");
    C3f c;
    for (int i = 0; i < 3; ++i) c[i] = unit_factor(values[i], indexed(element, i));
    return c;
  }

  // Reads a number from a material extension object, or returns `fallback` if absent.
  double extension_number(const tinygltf::Value& ext, const char* key, double fallback,
                          const std::string& element) const {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) {
      error(element + "." + key, "expected a finite number");
    }
    return v.GetNumberAsDouble();
  }

  AlphaMode alpha_mode(const std::string& mode, const std::string& element) const {
    if (mode == "OPAQUE") return AlphaMode::opaque;
    if (mode == "MASK") return AlphaMode::mask;
    if (mode == "BLEND") return AlphaMode::blend;
    const std::string shown = mode.size() > 32 ? mode.substr(0, 32) + "..." : mode;
    error(element, "\"" + shown + "\" is not OPAQUE, MASK or BLEND");
  }

  MaterialDescription material(std::size_t index) {
    const tinygltf::Material& m = model_.materials[index];
    const std::string element = indexed("materials", index);
    const std::string pbr_element = element + ".pbrMetallicRoughness";
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    MaterialDescription d;
    d.name = display_name(m.name, element);
    if (pbr.baseColorFactor.size() != 4) error(pbr_element + ".baseColorFactor", "expected 4");
    d.base_colour = colour(pbr.baseColorFactor, pbr_element + ".baseColorFactor");
    d.alpha = unit_factor(pbr.baseColorFactor[3], pbr_element + ".baseColorFactor[3]");
    d.metallic = unit_factor(pbr.metallicFactor, pbr_element + ".metallicFactor");
    d.roughness = unit_factor(pbr.roughnessFactor, pbr_element + ".roughnessFactor");
    d.base_colour_texture = texture(pbr.baseColorTexture, TextureEncoding::srgb,
                                    pbr_element + ".baseColorTexture", &d.base_colour_mapping);
    d.metallic_roughness_texture =
        texture(pbr.metallicRoughnessTexture, TextureEncoding::linear_data,
                pbr_element + ".metallicRoughnessTexture", &d.metallic_roughness_mapping);
    d.normal_texture = texture(m.normalTexture, TextureEncoding::linear_data,
                               element + ".normalTexture", &d.normal_mapping);
    if (!std::isfinite(m.normalTexture.scale))
      error(element + ".normalTexture.scale", "expected a finite number");
    if (!finite_float(m.normalTexture.scale))
      error(element + ".normalTexture.scale", "not finite as a float");
    d.normal_scale = static_cast<float>(m.normalTexture.scale);
    d.occlusion_texture = texture(m.occlusionTexture, TextureEncoding::linear_data,
                                  element + ".occlusionTexture", &d.occlusion_mapping);
    d.occlusion_strength =
        unit_factor(m.occlusionTexture.strength, element + ".occlusionTexture.strength");
    if (!m.emissiveFactor.empty()) {
      d.emissive = colour(m.emissiveFactor, element + ".emissiveFactor");
    }
    d.emissive_texture = texture(m.emissiveTexture, TextureEncoding::srgb,
                                 element + ".emissiveTexture", &d.emissive_mapping);
    d.double_sided = m.doubleSided;
    d.alpha_mode = alpha_mode(m.alphaMode, element + ".alphaMode");
    // glTF sets no upper bound: a cutoff above 1 removes the whole surface.
    if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.0)
      error(element + ".alphaCutoff", "expected a finite number >= 0");
    d.alpha_cutoff = static_cast<float>(m.alphaCutoff);

    for (const ExtensionHandler& h : extension_handlers()) {
      if (!h.material) continue;
      if (const tinygltf::Value* ext = find_extension(m.extensions, h.name))
        h.material(*this, *ext, element + ".extensions." + h.name, d);
    }
    return d;
  }

  TextureWrap wrap(int mode, const std::string& element) const {
    switch (mode) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT:
        return TextureWrap::repeat;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return TextureWrap::clamp_to_edge;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return TextureWrap::mirrored_repeat;
      default:
        error(element, "wrap mode " + std::to_string(mode) + " is invalid");
    }
  }

  // glTF's sampler into the texture's wrap modes and filters; no sampler, or a filter left
  // out, leaves the defaults (repeat; bilinear magnification, trilinear minification).
  void sampler(int index, const std::string& texture_element, TextureImage& image) const {
    if (index < 0) return;
    check_index(index, model_.samplers.size(), texture_element + ".sampler", "sampler");
    const std::string element = indexed("samplers", std::size_t(index));
    const tinygltf::Sampler& s = model_.samplers[std::size_t(index)];
    image.wrap_s = wrap(s.wrapS, element + ".wrapS");
    image.wrap_t = wrap(s.wrapT, element + ".wrapT");
    switch (s.magFilter) {
      case -1:
      case TINYGLTF_TEXTURE_FILTER_LINEAR:
        image.mag_filter = TextureFilter::linear;
        break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST:
        image.mag_filter = TextureFilter::nearest;
        break;
      default:
        error(element + ".magFilter", "filter " + std::to_string(s.magFilter) + " is invalid");
    }
    struct MinFilter {
      int gl;
      TextureFilter filter;
      MipMode mip;
    };
    static constexpr MinFilter kMinFilters[] = {
        {-1, TextureFilter::linear, MipMode::linear},
        {TINYGLTF_TEXTURE_FILTER_NEAREST, TextureFilter::nearest, MipMode::none},
        {TINYGLTF_TEXTURE_FILTER_LINEAR, TextureFilter::linear, MipMode::none},
        {TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST, TextureFilter::nearest, MipMode::nearest},
        {TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST, TextureFilter::linear, MipMode::nearest},
        {TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR, TextureFilter::nearest, MipMode::linear},
        {TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR, TextureFilter::linear, MipMode::linear}};
    for (const MinFilter& f : kMinFilters) {
      if (f.gl == s.minFilter) {
        image.min_filter = f.filter;
        image.mip_mode = f.mip;
        return;
      }
    }
    error(element + ".minFilter", "filter " + std::to_string(s.minFilter) + " is invalid");
  }

  // A textureInfo's texCoord: TEXCOORD_0 or TEXCOORD_1 (Primitive holds those two).
  int texcoord_set(int texcoord, const std::string& element) {
    if (texcoord < 0) error(element, "texCoord " + std::to_string(texcoord) + " is negative");
    if (texcoord > 1) {
      warn(element,
           "TEXCOORD_" + std::to_string(texcoord) + " is not supported; TEXCOORD_0 is used");
      return 0;
    }
    return texcoord;
  }

  V2f pair(const tinygltf::Value& ext, const char* key, V2f fallback, const std::string& e) const {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
      error(e + "." + key, "expected 2 numbers");
    const V2f out(static_cast<float>(v.Get(0).GetNumberAsDouble()),
                  static_cast<float>(v.Get(1).GetNumberAsDouble()));
    if (!std::isfinite(out.x) || !std::isfinite(out.y)) error(e + "." + key, "not finite");
    return out;
  }

  // KHR_texture_transform on a textureInfo.
  void texture_transform(const tinygltf::Value& ext, const std::string& e, TextureMapping& m) {
    m.offset = pair(ext, "offset", m.offset, e);
    m.scale = pair(ext, "scale", m.scale, e);
    const double rotation = extension_number(ext, "rotation", 0.0, e);
    if (!std::isfinite(static_cast<float>(rotation))) error(e + ".rotation", "not finite");
    m.rotation = static_cast<float>(rotation);
    if (ext.Has("texCoord")) {
      if (!ext.Get("texCoord").IsInt()) error(e + ".texCoord", "expected an integer");
      m.texcoord = texcoord_set(ext.Get("texCoord").GetNumberAsInt(), e + ".texCoord");
    }
  }

  // The texture a material slot reads (TextureInfo, NormalTextureInfo, OcclusionTextureInfo),
  // as an index into out_.textures, -1 for none; `mapping` receives its texCoord and
  // KHR_texture_transform. Its image is decoded later, with all the others, by
  // decode_texture_images.
  template <typename Info>
  int texture(const Info& info, TextureEncoding encoding, const std::string& element,
              TextureMapping* mapping = nullptr) {
    if (info.index < 0) return -1;
    check_index(info.index, model_.textures.size(), element + ".index", "texture");
    TextureMapping m;
    m.texcoord = texcoord_set(info.texCoord, element + ".texCoord");
    if (const auto* ext = find_extension(info.extensions, "KHR_texture_transform"))
      texture_transform(*ext, element + ".extensions.KHR_texture_transform", m);
    if (mapping) *mapping = m;
    const std::string texture_element = indexed("textures", std::size_t(info.index));
    const tinygltf::Texture& t = model_.textures[std::size_t(info.index)];
    if (t.source < 0) {
      warn(texture_element, "no source image in a supported format; texture ignored");
      return -1;
    }
    check_index(t.source, model_.images.size(), texture_element + ".source", "image");
    const auto key = std::make_tuple(t.source, t.sampler, encoding);
    if (auto it = texture_map_.find(key); it != texture_map_.end()) return it->second;
    TextureImage image;
    const tinygltf::Image& source = model_.images[std::size_t(t.source)];
    image.name = display_name(!source.name.empty()                             ? source.name
                              : !source.uri.empty() && source.uri.size() < 256 ? source.uri
                                                                               : std::string(),
                              indexed("images", std::size_t(t.source)));
    image.image = t.source;
    image.encoding = encoding;
    sampler(t.sampler, texture_element, image);
    out_.textures.push_back(std::move(image));
    const int result = static_cast<int>(out_.textures.size() - 1);
    texture_map_.emplace(key, result);
    return result;
  }

  // Every image a texture reads, decoded once and in parallel (gltf_images.h), into the
  // textures that read it.
  void decode_texture_images() {
    if (out_.textures.empty()) return;
    std::vector<bool> wanted(model_.images.size(), false);
    for (const TextureImage& t : out_.textures) wanted[std::size_t(t.image)] = true;
    const std::vector<DecodedImage> decoded = decode_images(model_, wanted, file_);
    for (TextureImage& t : out_.textures) {
      const DecodedImage& d = decoded[std::size_t(t.image)];
      t.width = d.width;
      t.height = d.height;
      t.channels = d.channels;
      t.shared_codes = d.codes;
      t.shared_texels = d.texels;
    }
  }

  // ---- meshes ----

  // Returns the index in out_.meshes, converting the glTF mesh on first use, or -1 for a mesh
  // whose every primitive was skipped (points, lines): it has nothing to render.
  // A mesh is converted once per distinct rest pose (morph weights, skin): nodes placing it
  // with the same pose share the converted mesh.
  int mesh(const tinygltf::Node& node, const std::string& node_element) {
    check_index(node.mesh, model_.meshes.size(), node_element + ".mesh", "mesh");
    RestPose pose;
    pose.weights = morph_weights(model_, node, node_element, file_);
    if (node.skin >= 0) {
      check_index(node.skin, model_.skins.size(), node_element + ".skin", "skin");
      auto [it, added] = joint_matrices_.try_emplace(node.skin);
      if (added) {
        it->second = joint_matrices(
            model_, node.skin, [this](int n) { return world_matrix(n); }, file_);
      }
      pose.joint_matrices = it->second;
    }
    const auto key = std::make_tuple(node.mesh, node.skin, pose.weights);
    if (auto it = mesh_map_.find(key); it != mesh_map_.end()) return it->second;
    Mesh converted = convert_mesh(std::size_t(node.mesh), pose);
    int mapped = -1;
    if (!converted.primitives.empty()) {
      out_.meshes.push_back(std::move(converted));
      mapped = static_cast<int>(out_.meshes.size() - 1);
    }
    mesh_map_.emplace(key, mapped);
    return mapped;
  }

  // The world matrix of any node of the forest (a skin's joints need not be in the scene).
  M44d world_matrix(int index) const {
    M44d world;
    std::size_t steps = 0;
    for (int n = index; n >= 0; n = parent_[std::size_t(n)]) {
      if (++steps > model_.nodes.size()) {
        error(indexed("nodes", std::size_t(index)), "the node hierarchy has a cycle");
      }
      world = world * local_matrix(model_.nodes[std::size_t(n)], indexed("nodes", std::size_t(n)));
    }
    if (!is_finite(world))
      error(indexed("nodes", std::size_t(index)), "world transform is not finite");
    return world;
  }

  Mesh convert_mesh(std::size_t index, const RestPose& pose) {
    const tinygltf::Mesh& m = model_.meshes[index];
    const std::string element = indexed("meshes", index);
    Mesh out;
    out.name = display_name(m.name, element);
    for (std::size_t p = 0; p < m.primitives.size(); ++p) {
      Primitive primitive;
      const std::string primitive_element = indexed(element + ".primitives", p);
      if (convert_primitive(m.primitives[p], primitive_element, primitive)) {
        pose_primitive(model_, m.primitives[p], pose, primitive_element, file_, primitive,
                       out_.warnings);
        out.primitives.push_back(std::move(primitive));
      }
    }
    return out;
  }

  // Returns false for primitives that are skipped (with a warning).
  bool convert_primitive(const tinygltf::Primitive& in, const std::string& element,
                         Primitive& out) {
    static const char* const kModeNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    const int mode = in.mode < 0 ? TINYGLTF_MODE_TRIANGLES : in.mode;
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN) {
      error(element + ".mode", "mode " + std::to_string(mode) + " is invalid");
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) {
      warn(element, std::string("mode ") + kModeNames[mode] + " is not rendered; skipped");
      return false;
    }
    if (in.material >= 0) {
      check_index(in.material, model_.materials.size(), element + ".material", "material");
    }
    out.material = in.material;

    const auto position = in.attributes.find("POSITION");
    if (position == in.attributes.end()) error(element + ".attributes", "POSITION is missing");
    const AccessorView positions =
        view_accessor(model_, position->second, element + ".attributes.POSITION", file_);
    out.positions = read_vec3_float(positions, "POSITION", file_);
    const std::size_t nonfinite = first_index_where(
        out.positions.size(), [&](std::size_t i) { return !is_finite(out.positions[i]); });
    if (nonfinite < out.positions.size()) {
      error(positions.element(), "vertex " + std::to_string(nonfinite) + " position is not finite");
    }
    const std::size_t vertices = out.positions.size();
    if (vertices > std::numeric_limits<uint32_t>::max()) {
      error(positions.element(), "too many vertices");
    }

    auto attribute = [&](const char* name) -> std::optional<AccessorView> {
      const auto it = in.attributes.find(name);
      if (it == in.attributes.end()) return std::nullopt;
      const std::string attr_element = element + ".attributes." + name;
      AccessorView view = view_accessor(model_, it->second, attr_element, file_);
      if (view.count != vertices) {
        error(attr_element, std::string(name) + " has " + std::to_string(view.count) +
                                " elements but POSITION has " + std::to_string(vertices));
      }
      return view;
    };
    if (const auto normals = attribute("NORMAL")) {
      out.normals = read_vec3_float(*normals, "NORMAL", file_);
      const std::size_t broken = first_index_where(out.normals.size(), [&](std::size_t i) {
        const V3f& n = out.normals[i];
        const float length = n.length();
        return !is_finite(n) || !std::isfinite(length) || length <= 0.0f;
      });
      if (broken < out.normals.size()) {
        warn(normals->element(), "normal " + std::to_string(broken) +
                                     " is zero or not finite; the primitive's normals are "
                                     "dropped and flat normals used");
        out.normals.clear();
      }
      for_each_index(out.normals.size(), [&](std::size_t i) {
        V3f& n = out.normals[i];
        n /= n.length();
      });
    }
    if (const auto uv = attribute("TEXCOORD_0")) {
      out.uv0 = read_texcoords(*uv, file_);
      for (std::size_t i = 0; i < out.uv0.size(); ++i) {
        if (!std::isfinite(out.uv0[i].x) || !std::isfinite(out.uv0[i].y)) {
          error(uv->element(), "texture coordinate " + std::to_string(i) + " is not finite");
        }
      }
    }
    if (const auto uv = attribute("TEXCOORD_1")) {
      out.uv1 = read_texcoords(*uv, file_);
      for (std::size_t i = 0; i < out.uv1.size(); ++i) {
        if (!std::isfinite(out.uv1[i].x) || !std::isfinite(out.uv1[i].y)) {
          error(uv->element(), "texture coordinate " + std::to_string(i) + " is not finite");
        }
      }
    }
    if (const auto colours = attribute("COLOR_0")) out.colours = read_colours(*colours, file_);
    if (const auto tangents = attribute("TANGENT")) out.tangents = read_tangents(*tangents, file_);

    std::vector<uint32_t> indices;
    if (in.indices >= 0) {
      const AccessorView view = view_accessor(model_, in.indices, element + ".indices", file_);
      indices = read_indices(view, file_);
      const std::size_t i =
          first_index_where(indices.size(), [&](std::size_t k) { return indices[k] >= vertices; });
      if (i < indices.size()) {
        error(element + ".indices", "index " + std::to_string(indices[i]) + " at position " +
                                        std::to_string(i) + " out of range (" +
                                        std::to_string(vertices) + " vertices)");
      }
    } else {
      charge(vertices, sizeof(uint32_t), element + ".indices");
      indices.resize(vertices);
      for (std::size_t i = 0; i < vertices; ++i) indices[i] = static_cast<uint32_t>(i);
    }

    const std::size_t n = indices.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) {
        error(element, std::to_string(n) + (in.indices >= 0 ? " indices" : " vertices") +
                           " do not make whole TRIANGLES (not a multiple of 3)");
      }
      out.indices = std::move(indices);
    } else if (n >= 3) {
      charge(3 * (n - 2), sizeof(uint32_t), element + ".indices");
      out.indices.reserve(3 * (n - 2));
      for (std::size_t i = 0; i + 2 < n; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
          // glTF's strip rule keeps every triangle counter-clockwise.
          out.indices.insert(out.indices.end(),
                             {indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]});
        } else {
          out.indices.insert(out.indices.end(), {indices[i + 1], indices[i + 2], indices[0]});
        }
      }
    }
    if (out.indices.empty()) {
      warn(element, "fewer than 3 vertices; skipped");
      return false;
    }
    generate_missing_tangents(out, element);
    return true;
  }

  // A normal-mapped primitive without TANGENT gets MikkTSpace-style tangents from the UVs
  // its normal map reads (renderer/geometry/tangents.h); without those UVs the map cannot be
  // placed.
  void generate_missing_tangents(Primitive& p, const std::string& element) {
    if (!p.tangents.empty() || p.material < 0) return;
    const MaterialDescription& m = out_.materials.at(std::size_t(p.material));
    if (m.normal_texture < 0) return;
    const std::vector<V2f>& uv = m.normal_mapping.texcoord == 1 ? p.uv1 : p.uv0;
    if (uv.empty()) {
      warn(element, "the material's normal map needs TEXCOORD_" +
                        std::to_string(m.normal_mapping.texcoord) +
                        ", which is missing; not normal mapped");
      return;
    }
    p.tangents = generate_tangents(p.positions, p.normals, uv, p.indices);
  }

  // ---- nodes ----

  std::vector<int> scene_roots() {
    const std::size_t node_count = model_.nodes.size();
    // glTF requires the nodes to form disjoint trees; checking it up front turns shared
    // children (which would otherwise be visited repeatedly, exponentially in the worst case)
    // into an error.
    std::vector<int> parent(node_count, -1);
    for (std::size_t i = 0; i < node_count; ++i) {
      const std::vector<int>& children = model_.nodes[i].children;
      for (std::size_t c = 0; c < children.size(); ++c) {
        const std::string element = indexed(indexed("nodes", i) + ".children", c);
        check_index(children[c], node_count, element, "node");
        int& p = parent[std::size_t(children[c])];
        if (p >= 0) {
          error(indexed("nodes", std::size_t(children[c])),
                "node has more than one parent (nodes[" + std::to_string(p) + "] and nodes[" +
                    std::to_string(i) + "])");
        }
        p = static_cast<int>(i);
      }
    }
    parent_ = parent;

    if (model_.scenes.empty()) {
      if (!scene_.empty()) error("scenes", "--scene " + scene_ + ": the file has no scenes");
      if (model_.defaultScene >= 0) {
        error("scene", "scene " + std::to_string(model_.defaultScene) +
                           " out of range (the file has no scenes)");
      }
      std::vector<int> roots;
      for (std::size_t i = 0; i < node_count; ++i) {
        if (parent[i] < 0) roots.push_back(static_cast<int>(i));
      }
      warn("scenes", "the file has no scenes; all " + std::to_string(roots.size()) +
                         " root nodes are rendered");
      return roots;
    }
    std::size_t scene = 0;
    if (model_.defaultScene >= 0) {
      check_index(model_.defaultScene, model_.scenes.size(), "scene", "scene");
      scene = std::size_t(model_.defaultScene);
    }
    if (!scene_.empty()) {
      std::vector<std::string> names;
      for (const tinygltf::Scene& s : model_.scenes) names.push_back(s.name);
      scene = select_scene(names, scene_, file_);
    }
    const std::string element = indexed("scenes", scene);
    const std::vector<int>& roots = model_.scenes[scene].nodes;
    for (std::size_t i = 0; i < roots.size(); ++i) {
      check_index(roots[i], node_count, indexed(element + ".nodes", i), "node");
    }
    if (roots.empty()) warn(element, "the scene has no nodes");
    return roots;
  }

  M44d local_matrix(const tinygltf::Node& node, const std::string& element) const {
    M44d m;  // identity
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) error(element + ".matrix", "expected 16 numbers");
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) m[i][j] = node.matrix[std::size_t(4 * i + j)];
      }
      if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
        error(element + ".matrix", "not an affine transform (bottom row must be 0 0 0 1)");
      }
      return m;
    }
    double s[3] = {1.0, 1.0, 1.0};
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) error(element + ".scale", "expected 3 numbers");
      std::copy(node.scale.begin(), node.scale.end(), s);
    }
    double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) error(element + ".rotation", "expected 4 numbers");
      const double length =
          std::sqrt(node.rotation[0] * node.rotation[0] + node.rotation[1] * node.rotation[1] +
                    node.rotation[2] * node.rotation[2] + node.rotation[3] * node.rotation[3]);
      if (!std::isfinite(length) || length < 1e-12) {
        error(element + ".rotation", "not a unit quaternion");
      }
      // Exporters round quaternions to float precision; renormalising avoids a slight scale.
      x = node.rotation[0] / length;
      y = node.rotation[1] / length;
      z = node.rotation[2] / length;
      w = node.rotation[3] / length;
    }
    // The column-vector rotation matrix, stored transposed for Imath's row vectors.
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] = s[i] * r[j][i];
    }
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) error(element + ".translation", "expected 3 numbers");
      for (int j = 0; j < 3; ++j) m[3][j] = node.translation[std::size_t(j)];
    }
    return m;
  }

  void traverse(const std::vector<int>& roots) {
    struct Item {
      int node;
      int parent;
      M44d parent_world;
    };
    // Explicit stack: a deep (or hostile) hierarchy must not overflow the call stack.
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, M44d()});
    std::vector<int> parent_of(model_.nodes.size(), -1);
    std::vector<bool> visited(model_.nodes.size(), false);
    while (!stack.empty()) {
      const Item item = stack.back();
      stack.pop_back();
      const std::size_t index = std::size_t(item.node);
      const std::string element = indexed("nodes", index);
      if (visited[index]) {
        for (int a = item.parent; a >= 0; a = parent_of[std::size_t(a)]) {
          if (a == item.node) {
            error(element, "the node hierarchy has a cycle (the node is its own ancestor)");
          }
        }
        error(element,
              "node is reached twice (listed as a scene root more than once, or both "
              "a root and a child)");
      }
      visited[index] = true;
      parent_of[index] = item.parent;
      const tinygltf::Node& node = model_.nodes[index];
      const M44d world = local_matrix(node, element) * item.parent_world;
      check_world(world, node, element);
      visit(node, index, world);
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
        stack.push_back({*it, item.node, world});
      }
    }
  }

  // The world transform as the renderer uses it, in float: an entry past float's range (a
  // scale of 1e39) would turn every vertex infinite, and a scale that flattens the node (a
  // determinant that is 0 in float) leaves its mesh nothing to render.
  void check_world(const M44d& world, const tinygltf::Node& node, const std::string& element) {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (!finite_float(world[i][j])) {
          error(element, "world transform is not finite as a float (entry " +
                             number_text(world[i][j]) + ")");
        }
    const double det = world[0][0] * (world[1][1] * world[2][2] - world[1][2] * world[2][1]) -
                       world[0][1] * (world[1][0] * world[2][2] - world[1][2] * world[2][0]) +
                       world[0][2] * (world[1][0] * world[2][1] - world[1][1] * world[2][0]);
    if (node.mesh >= 0 && node.skin < 0 && static_cast<float>(std::fabs(det)) == 0.0f) {
      warn(element,
           "the world transform's scale flattens the node's mesh to nothing "
           "(determinant " +
               number_text(det) + "); it renders nothing");
    }
  }

  // Every vertex of mesh `m` placed by `world` must stay finite in float.
  void check_placed_mesh(int m, const M44d& world, const std::string& element) {
    auto [it, added] = mesh_bounds_.try_emplace(m);
    if (added) {
      for (const Primitive& p : out_.meshes[std::size_t(m)].primitives)
        for (const V3f& v : p.positions) it->second.extendBy(V3d(v));
    }
    const Imath::Box3d& box = it->second;
    for (int corner = 0; corner < 8; ++corner) {
      const V3d c((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                  (corner & 4) ? box.max.z : box.min.z);
      const V3d w = c * world;
      if (!finite_float(w.x) || !finite_float(w.y) || !finite_float(w.z)) {
        error(element, "the world transform places mesh vertices beyond float's range");
      }
    }
  }

  void visit(const tinygltf::Node& node, std::size_t index, const M44d& world) {
    const std::string element = indexed("nodes", index);
    const std::string name = display_name(node.name, element);
    const tinygltf::Value* sphere_ext = find_extension(node.extensions, "PRISM_sphere");
    if (sphere_ext) {
      sphere(*sphere_ext, node, element, name, world);
    } else if (node.mesh >= 0) {
      if (const int m = mesh(node, element); m >= 0) {
        check_placed_mesh(m, node.skin >= 0 ? M44d() : world, element);
        // glTF: a skinned mesh is placed by its joints alone; the node's own transform is
        // ignored (the skin's matrices already put its vertices in world space).
        out_.instances.push_back({m, node.skin >= 0 ? M44d() : world, name});
      }
    }
    if (node.camera >= 0) camera(node.camera, element, world);
    if (const auto* light_ext = find_extension(node.extensions, "KHR_lights_punctual")) {
      const std::string e = element + ".extensions.KHR_lights_punctual.light";
      if (!light_ext->Has("light") || !light_ext->Get("light").IsInt()) {
        error(e, "expected a light index");
      }
      light(light_ext->Get("light").GetNumberAsInt(), e, world);
    }
  }

  void sphere(const tinygltf::Value& ext, const tinygltf::Node& node, const std::string& element,
              const std::string& name, const M44d& world) {
    const std::string e = element + ".extensions.PRISM_sphere";
    if (!ext.Has("radius") || !ext.Get("radius").IsNumber()) {
      error(e + ".radius", "expected a number");
    }
    const double radius = ext.Get("radius").GetNumberAsDouble();
    if (!std::isfinite(radius) || radius <= 0.0) {
      error(e + ".radius", "radius " + std::to_string(radius) + " must be finite and > 0");
    }
    Sphere s;
    s.node_name = name;
    s.centre = V3d(world[3][0], world[3][1], world[3][2]);
    V3d axes[3];
    double largest = 0.0;
    for (int i = 0; i < 3; ++i) {
      axes[i] = V3d(world[i][0], world[i][1], world[i][2]);
      largest = std::max(largest, axes[i].length());
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = i + 1; j < 3; ++j) {
        const bool same_length = std::abs(axes[i].length() - axes[j].length()) <= 1e-6 * largest;
        const bool orthogonal = std::abs(axes[i].dot(axes[j])) <= 1e-6 * largest * largest;
        if (!same_length || !orthogonal) {
          error(element, "PRISM_sphere needs a uniform world scale, but the node's axes scale by " +
                             std::to_string(axes[0].length()) + ", " +
                             std::to_string(axes[1].length()) + ", " +
                             std::to_string(axes[2].length()) +
                             (same_length ? " and are sheared" : ""));
        }
      }
    }
    s.radius = radius * (axes[0].length() + axes[1].length() + axes[2].length()) / 3.0;
    if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
      error(element, "PRISM_sphere's world radius " + std::to_string(s.radius) + " is not > 0");
    }
    if (ext.Has("material")) {
      const tinygltf::Value& m = ext.Get("material");
      if (!m.IsInt()) error(e + ".material", "expected a material index");
      s.material = m.GetNumberAsInt();
      check_index(s.material, model_.materials.size(), e + ".material", "material");
    } else if (node.mesh >= 0) {
      check_index(node.mesh, model_.meshes.size(), element + ".mesh", "mesh");
      const tinygltf::Mesh& m = model_.meshes[std::size_t(node.mesh)];
      if (!m.primitives.empty() && m.primitives[0].material >= 0) {
        s.material = m.primitives[0].material;
        check_index(s.material, model_.materials.size(),
                    indexed("meshes", std::size_t(node.mesh)) + ".primitives[0].material",
                    "material");
      }
    }
    out_.spheres.push_back(s);
  }

  void camera(int index, const std::string& node_element, const M44d& world) {
    check_index(index, model_.cameras.size(), node_element + ".camera", "camera");
    const tinygltf::Camera& c = model_.cameras[std::size_t(index)];
    const std::string element = indexed("cameras", std::size_t(index));
    CameraDescription d;
    d.name = display_name(c.name, element);
    d.camera_to_world = world;
    if (c.type == "perspective") {
      const std::string e = element + ".perspective";
      d.projection = Projection::perspective;
      d.yfov = c.perspective.yfov;
      if (!(d.yfov > 0.0 && d.yfov < kPi)) {
        error(e + ".yfov", "field of view " + std::to_string(d.yfov) + " is not in (0, pi)");
      }
      d.aspect_ratio = c.perspective.aspectRatio;
      if (!(d.aspect_ratio >= 0.0) || !std::isfinite(d.aspect_ratio)) {
        error(e + ".aspectRatio", "must be > 0");
      }
      d.znear = c.perspective.znear;
      if (!(d.znear > 0.0) || !std::isfinite(d.znear)) error(e + ".znear", "must be > 0");
    } else if (c.type == "orthographic") {
      const std::string e = element + ".orthographic";
      d.projection = Projection::orthographic;
      d.xmag = c.orthographic.xmag;
      d.ymag = c.orthographic.ymag;
      d.znear = c.orthographic.znear;
      if (!(d.xmag > 0.0) || !std::isfinite(d.xmag)) error(e + ".xmag", "must be > 0");
      if (!(d.ymag > 0.0) || !std::isfinite(d.ymag)) error(e + ".ymag", "must be > 0");
      if (!(d.znear >= 0.0) || !std::isfinite(d.znear)) error(e + ".znear", "must be >= 0");
    } else {
      error(element + ".type", "unknown camera type " + shown(c.type));
    }
    out_.cameras.push_back(d);
  }

  void light(int index, const std::string& node_element, const M44d& world) {
    check_index(index, model_.lights.size(), node_element, "light");
    const tinygltf::Light& l = model_.lights[std::size_t(index)];
    const std::string element =
        indexed("extensions.KHR_lights_punctual.lights", std::size_t(index));
    Light d;
    d.name = display_name(l.name, element);
    if (l.type == "directional") {
      d.type = LightType::directional;
    } else if (l.type == "point") {
      d.type = LightType::point;
    } else if (l.type == "spot") {
      d.type = LightType::spot;
    } else {
      error(element + ".type", "unknown light type " + shown(l.type));
    }
    if (!l.color.empty()) {
      if (l.color.size() != 3) error(element + ".color", "expected 3 numbers");
      for (int i = 0; i < 3; ++i) {
        const double c = l.color[std::size_t(i)];
        if (!finite_float(c) || c < 0.0)
          error(indexed(element + ".color", i), "must be >= 0 and finite as a float");
        d.colour[i] = static_cast<float>(c);
      }
    }
    // The renderer multiplies colour and intensity in float.
    if (!finite_float(l.intensity) || l.intensity < 0.0 ||
        !is_finite(d.colour * static_cast<float>(l.intensity))) {
      error(element + ".intensity", "must be >= 0, and finite as a float times the colour, got " +
                                        number_text(l.intensity));
    }
    d.intensity = static_cast<float>(l.intensity);
    if (!std::isfinite(l.range) || l.range < 0.0) error(element + ".range", "must be > 0");
    d.range = l.range;
    if (d.type == LightType::spot) {
      d.inner_cone_angle = l.spot.innerConeAngle;
      d.outer_cone_angle = l.spot.outerConeAngle;
      if (!(d.inner_cone_angle >= 0.0 && d.inner_cone_angle < d.outer_cone_angle &&
            d.outer_cone_angle <= kPi / 2 + 1e-9)) {
        error(element + ".spot", "needs 0 <= innerConeAngle < outerConeAngle <= pi/2, got " +
                                     std::to_string(d.inner_cone_angle) + " and " +
                                     std::to_string(d.outer_cone_angle));
      }
    }
    d.position = V3d(world[3][0], world[3][1], world[3][2]);
    const V3d forward(-world[2][0], -world[2][1], -world[2][2]);
    const double length = forward.length();
    if (!(length > 1e-300) || !std::isfinite(length)) {
      if (d.type != LightType::point) {
        error(node_element, "the node's transform collapses the light's direction");
      }
    } else {
      d.direction = forward / length;
    }
    out_.lights.push_back(d);
  }

  const tinygltf::Model& model_;
  const std::string& file_;
  SceneDescription& out_;
  const std::string& scene_;  // --scene: a name or index, empty = the file's default
  std::map<std::tuple<int, int, std::vector<double>>, int> mesh_map_;
  std::map<int, std::vector<M44d>> joint_matrices_;                   // per skin
  std::map<int, Imath::Box3d> mesh_bounds_;                           // per out_.meshes index
  std::vector<int> parent_;                                           // per node, -1 for roots
  std::map<std::tuple<int, int, TextureEncoding>, int> texture_map_;  // (image, sampler, encoding)
};

SceneDescription load(const std::string& path, const LoadOptions& options) {
  SceneDescription scene;
  scene.source_path = path;
  std::vector<unsigned char> bytes = read_file(path);
  const bool binary = is_glb(bytes);
  GlbChunks glb;
  if (binary) glb = parse_glb(bytes, path);
  std::string json_text =
      binary ? std::string(reinterpret_cast<const char*>(bytes.data() + glb.json_offset),
                           glb.json_length)
             : std::string(bytes.begin(), bytes.end());
  nlohmann::json root = parse_json(json_text, path);
  check_object_count(root, path);
  check_gltf_json(root, path, scene.warnings);
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  FileGate gate(base.empty() ? std::filesystem::path(".") : base, options.allow_external_paths,
                path);
  ImageGuard image_guard;
  image_guard.declared_type = check_uris(root, gate, path);
  bool rewritten = gate.admitted() > 0;
  if (auto patched = draco_json_for_tinygltf(root)) {
    root = std::move(*patched);
    rewritten = true;
  }
  if (rewritten) json_text = root.dump();
  if (binary && (rewritten || glb.has_other_chunks)) {
    bytes = make_glb(json_text, glb.has_bin ? bytes.data() + glb.bin_offset : nullptr,
                     glb.bin_length, path);
  }

  tinygltf::TinyGLTF loader;
  loader.SetPreserveImageChannels(true);
  loader.SetImageLoader(check_image_header, &image_guard);
  loader.SetFsCallbacks(gate.callbacks());
  tinygltf::Model model;
  std::string err;
  std::string warn;
  bool ok = false;
  // No base directory: tinygltf only sees the gate's tokens, which its callbacks resolve.
  if (binary) {
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                     static_cast<unsigned int>(bytes.size()), "");
  } else {
    ok = loader.LoadASCIIFromString(&model, &err, &warn, json_text.data(),
                                    static_cast<unsigned int>(json_text.size()), "");
  }
  // tinygltf holds its own copy of every buffer: the file's bytes are not needed again, and
  // on a big binary file they are as large as the scene about to be made from them.
  std::vector<unsigned char>().swap(bytes);
  if (!gate.failed_element().empty()) throw LoadError(gate.failure());
  if (!image_guard.element.empty()) fail(path, image_guard.element, image_guard.what);
  // tinygltf also reports some problems (such as a missing required property) in `err` while
  // returning true; the model is then incomplete, so both count as failure.
  if (!ok || !err.empty()) fail(path, "glTF", err.empty() ? "tinygltf failed to load" : err);
  if (!warn.empty()) scene.warnings.push_back(warning("glTF", warn));
  // The file's own URIs again, for texture names and messages.
  for (tinygltf::Buffer& b : model.buffers) b.uri = gate.original_uri(b.uri);
  for (tinygltf::Image& i : model.images) i.uri = gate.original_uri(i.uri);

  // Both rewrite the model onto plain accessors, so the conversion below reads them as usual.
  decode_draco_primitives(model, path);
  apply_sparse_accessors(model, path);

  Converter(model, path, options.scene, scene).convert();
  scene.source_files.push_back(path);
  for (const std::string& file : gate.admitted_paths()) scene.source_files.push_back(file);
  return scene;
}

}  // namespace

SceneDescription load_gltf(const std::string& path) {
  return load_gltf(path, LoadOptions());
}

SceneDescription load_gltf(const std::string& path, const LoadOptions& options) {
  MemoryBudget budget(options.memory_limit, path);
  try {
    const BudgetScope budget_scope(budget);
    return load(path, options);
  } catch (const LoadError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // The budget allowed more than the machine could give.
    fail(path, budget.last_element().empty() ? "file" : budget.last_element(),
         "out of memory (std::bad_alloc) with " + byte_size(budget.used()) +
             " charged to the load; lower --memory-limit to be refused sooner");
  } catch (const std::exception& e) {
    // tinygltf and nlohmann throw on some malformed input; the caller only needs to know the
    // file could not be loaded.
    throw LoadError(one_line(path + ": glTF: " + e.what()));
  } catch (...) {
    throw LoadError(one_line(path + ": glTF: unknown error while loading"));
  }
}

}  // namespace prism
