// Hostile glTF files (issue 6): paths leaving the asset's folder, data URIs that lie about
// their size, counts, strides and offsets past the data, huge images, node cycles and deep
// hierarchies, and documents too big or too deep. Each must give a one-line LoadError naming
// the element, before any large allocation; the limits are in scene_io/gltf_limits.h.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <OpenImageIO/strutil.h>
#include <nlohmann/json.hpp>

#include "scene_io/gltf_limits.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// Library base64 (OpenImageIO's), for the data URIs of hand-made files.
std::string base64(const std::vector<unsigned char>& data) {
  return OIIO::Strutil::base64_encode(
      OIIO::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

std::vector<unsigned char> bytes_of(const std::vector<float>& values) {
  std::vector<unsigned char> out(values.size() * sizeof(float));
  std::memcpy(out.data(), values.data(), out.size());
  return out;
}

// One triangle's positions, as raw bytes for a buffer.
const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

// A fresh folder per test, with `asset/` for the glTF and `outside/` next to it.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "prism_gltf_hostile_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "asset");
  fs::create_directories(dir / "outside");
  return dir;
}

void write_bytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::string write_json(const fs::path& path, const json& doc) {
  std::ofstream(path) << doc.dump();
  return path.string();
}

// A scene with one triangle whose 36-byte buffer comes from `uri`, plus the accessor and view.
json triangle_doc(const std::string& uri) {
  json doc;
  doc["asset"] = {{"version", "2.0"}};
  doc["scene"] = 0;
  doc["scenes"] = json::array({{{"nodes", {0}}}});
  doc["nodes"] = json::array({{{"mesh", 0}}});
  doc["meshes"] =
      json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}});
  doc["accessors"] =
      json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}});
  doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 36}}});
  doc["buffers"] = json::array({{{"byteLength", 36}, {"uri", uri}}});
  return doc;
}

std::string data_uri(const std::vector<unsigned char>& bytes) {
  return "data:application/octet-stream;base64," + base64(bytes);
}

std::string load_error(const std::string& path, const LoadOptions& options = {}) {
  try {
    load_gltf(path, options);
  } catch (const LoadError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    return message;
  }
  ADD_FAILURE() << path << " loaded without error";
  return {};
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

// ---------------------------------------------------------------------------------------------
// URIs

TEST(GltfHostile, ParentDirectoryUriIsRefusedUnlessAllowed) {
  const fs::path dir = scratch("parent");
  write_bytes(dir / "outside" / "tri.bin", bytes_of(kTriangle));
  const std::string path = write_json(dir / "asset" / "a.gltf", triangle_doc("../outside/tri.bin"));
  const std::string message = load_error(path);
  EXPECT_CONTAINS(message,
                  ": buffers[0].uri: \"../outside/tri.bin\" points outside the asset's folder");

  LoadOptions allow;
  allow.allow_external_paths = true;
  const SceneDescription scene = load_gltf(path, allow);
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.meshes[0].primitives.at(0).positions.size(), 3u);
  EXPECT_EQ(scene.meshes[0].primitives[0].positions[1], V3f(1, 0, 0));
  EXPECT_EQ(scene.meshes[0].primitives[0].positions[2], V3f(0, 1, 0));
}

TEST(GltfHostile, EscapedParentDirectoryIsRefused) {
  // %2e%2e is "..": the check is on the decoded path, as tinygltf reads it.
  const fs::path dir = scratch("escaped");
  write_bytes(dir / "outside" / "tri.bin", bytes_of(kTriangle));
  fs::create_directories(dir / "asset" / "sub");
  const std::string path =
      write_json(dir / "asset" / "a.gltf", triangle_doc("sub/%2e%2e/%2E%2E/outside/tri.bin"));
  EXPECT_CONTAINS(load_error(path), ": buffers[0].uri: ");
  EXPECT_CONTAINS(load_error(path), "points outside the asset's folder");
}

TEST(GltfHostile, AbsolutePathAndFileUriAreRefused) {
  const fs::path dir = scratch("absolute");
  write_bytes(dir / "outside" / "tri.bin", bytes_of(kTriangle));
  const std::string absolute = (dir / "outside" / "tri.bin").string();
  for (const std::string& uri : {absolute, "file://" + absolute}) {
    SCOPED_TRACE(uri);
    const std::string path = write_json(dir / "asset" / "a.gltf", triangle_doc(uri));
    const std::string message = load_error(path);
    EXPECT_CONTAINS(message, ": buffers[0].uri: \"" + uri + "\" is ");
    EXPECT_CONTAINS(message, "--allow-external-paths");
    // Allowing external paths does not make tinygltf resolve them: still a clear error.
    LoadOptions allow;
    allow.allow_external_paths = true;
    EXPECT_CONTAINS(load_error(path, allow), ": buffers[0].uri: ");
  }
}

TEST(GltfHostile, ImageUriOutsideTheFolderIsRefused) {
  const fs::path dir = scratch("image");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["images"] = json::array({{{"uri", "/etc/passwd"}}, {{"uri", "../outside/x.png"}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": images[0].uri: \"/etc/passwd\" is absolute");
  doc["images"].erase(0);
  write_bytes(dir / "outside" / "x.png", {0x89, 'P', 'N', 'G'});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": images[0].uri: \"../outside/x.png\" points outside");
}

TEST(GltfHostile, SymlinkOutOfTheFolderIsRefused) {
  const fs::path dir = scratch("symlink");
  write_bytes(dir / "outside" / "tri.bin", bytes_of(kTriangle));
  fs::create_symlink(dir / "outside" / "tri.bin", dir / "asset" / "tri.bin");
  const std::string path = write_json(dir / "asset" / "a.gltf", triangle_doc("tri.bin"));
  EXPECT_CONTAINS(load_error(path),
                  ": buffers[0].uri: \"tri.bin\" points outside the asset's folder");
  LoadOptions allow;
  allow.allow_external_paths = true;
  EXPECT_EQ(load_gltf(path, allow).meshes.at(0).primitives.at(0).positions.at(1), V3f(1, 0, 0));

  // A symlink that stays inside the folder is fine, and so is a subfolder.
  fs::create_directories(dir / "asset" / "data");
  fs::remove(dir / "asset" / "tri.bin");
  write_bytes(dir / "asset" / "data" / "tri.bin", bytes_of(kTriangle));
  fs::create_symlink(dir / "asset" / "data" / "tri.bin", dir / "asset" / "tri.bin");
  EXPECT_EQ(load_gltf(path).meshes.at(0).primitives.at(0).positions.at(2), V3f(0, 1, 0));
  const std::string sub = write_json(dir / "asset" / "b.gltf", triangle_doc("data/tri.bin"));
  EXPECT_EQ(load_gltf(sub).meshes.at(0).primitives.at(0).positions.at(2), V3f(0, 1, 0));
}

TEST(GltfHostile, DataUriSizeMustMatchByteLength) {
  const fs::path dir = scratch("data_uri");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["buffers"][0]["byteLength"] = 100;
  doc["bufferViews"][0]["byteLength"] = 36;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": buffers[0].uri: data URI holds 36 bytes but byteLength is 100");
  // 35 bytes encode to 47 characters with one '=': the count is exact, not rounded to 3.
  std::vector<unsigned char> shorter = bytes_of(kTriangle);
  shorter.pop_back();
  doc["buffers"][0]["uri"] = data_uri(shorter);
  doc["buffers"][0]["byteLength"] = 36;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": buffers[0].uri: data URI holds 35 bytes but byteLength is 36");
  doc["buffers"][0]["uri"] = "data:application/octet-stream,plain";
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": buffers[0].uri: only base64 data: URIs are supported");
  // And the exact size loads.
  doc["buffers"][0]["uri"] = data_uri(bytes_of(kTriangle));
  EXPECT_EQ(load_gltf(write_json(dir / "asset" / "a.gltf", doc))
                .meshes.at(0)
                .primitives.at(0)
                .positions.at(1),
            V3f(1, 0, 0));
}

// ---------------------------------------------------------------------------------------------
// Counts, strides, offsets

TEST(GltfHostile, AccessorClaimingTwoToThe31ElementsIsRefused) {
  const fs::path dir = scratch("count");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["accessors"][0]["count"] = std::uint64_t{1} << 31;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": accessors[0]: byteOffset 0 + 2147483648 elements of 12 bytes (stride 12) "
                  "exceed the 36 bytes of bufferViews[0]");
  // Without a bufferView (all zeros), the count is capped instead.
  doc["accessors"][0].erase("bufferView");
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": accessors[0]: count 2147483648 without a bufferView");
}

TEST(GltfHostile, BufferViewPastItsBufferIsRefused) {
  const fs::path dir = scratch("view");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["bufferViews"][0]["byteOffset"] = 4;
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "a.gltf", doc)),
      ": bufferViews[0]: byteOffset 4 + byteLength 36 exceeds the 36 bytes of buffers[0]");
}

TEST(GltfHostile, StrideSmallerThanTheElementIsRefused) {
  const fs::path dir = scratch("stride");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["bufferViews"][0]["byteStride"] = 4;
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "a.gltf", doc)),
      ": accessors[0]: byteStride 4 of bufferViews[0] is smaller than the element size 12");
}

// ---------------------------------------------------------------------------------------------
// Images: the header's size is checked before the decoder allocates.

// A PNG signature and IHDR chunk claiming width x height RGBA pixels, and nothing else: the
// decoder would allocate width x height x 4 bytes before finding that the data is missing.
std::vector<unsigned char> png_header(uint32_t width, uint32_t height) {
  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n',
                                    0,    0,   0,   13,  'I',  'H',  'D',  'R'};
  for (uint32_t v : {width, height}) {
    for (int shift = 24; shift >= 0; shift -= 8) png.push_back(uint8_t(v >> shift));
  }
  png.insert(png.end(), {8, 6, 0, 0, 0, 0, 0, 0, 0});  // 8 bits RGBA, then a (dummy) CRC
  return png;
}

std::string image_error(const std::string& name, const std::vector<unsigned char>& image) {
  const fs::path dir = scratch(name);
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(image)}}});
  return load_error(write_json(dir / "asset" / "a.gltf", doc));
}

TEST(GltfHostile, HugeImageIsRefusedFromItsHeader) {
  EXPECT_CONTAINS(image_error("image_huge", png_header(100000, 100000)),
                  ": images[0]: 100000 x 100000 pixels; each side is limited to 16384");
  EXPECT_CONTAINS(image_error("image_wide", png_header(16385, 1)),
                  ": images[0]: 16385 x 1 pixels; each side is limited to 16384");
  EXPECT_CONTAINS(
      image_error("image_many", png_header(10000, 10000)),
      ": images[0]: 10000 x 10000 pixels exceed the limit of 67108864 pixels per image");
  EXPECT_CONTAINS(image_error("image_garbage", {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i'}),
                  ": images[0]: not an image in a format the decoder reads");
}

// ---------------------------------------------------------------------------------------------
// Node graph and document size

TEST(GltfHostile, NodeCyclesAreRefused) {
  const fs::path dir = scratch("cycle");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["nodes"] = json::array({{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": nodes[0]: the node hierarchy has a cycle (the node is its own ancestor)");
  doc["nodes"] = json::array({{{"children", {0}}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": nodes[0]: the node hierarchy has a cycle");
  // A cycle no scene reaches is never traversed, so it cannot loop either.
  doc["nodes"] = json::array({{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}});
  doc["scenes"][0]["nodes"] = {0};
  EXPECT_EQ(load_gltf(write_json(dir / "asset" / "a.gltf", doc)).instances.size(), 1u);
}

TEST(GltfHostile, DeepHierarchyLoadsWithoutRecursion) {
  // 100000 nested nodes, each moving its child by 1 in x: the traversal is iterative, so this
  // neither overflows the stack nor takes long, and the leaf's mesh ends up at x = 100000.
  const fs::path dir = scratch("deep");
  constexpr int kDepth = 100000;
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) {
    json n = {{"translation", {1.0, 0.0, 0.0}}};
    if (i + 1 < kDepth)
      n["children"] = {i + 1};
    else
      n["mesh"] = 0;
    nodes.push_back(n);
  }
  doc["nodes"] = nodes;
  const SceneDescription scene = load_gltf(write_json(dir / "asset" / "a.gltf", doc));
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_DOUBLE_EQ(scene.instances[0].object_to_world[3][0], double(kDepth));
  EXPECT_DOUBLE_EQ(scene.instances[0].object_to_world[3][1], 0.0);
}

TEST(GltfHostile, TooManyObjectsAreRefusedBeforeTinygltf) {
  const fs::path dir = scratch("objects");
  // Written as text: building a million-element nlohmann array in the test would dominate.
  std::string text = triangle_doc(data_uri(bytes_of(kTriangle))).dump();
  text.pop_back();
  text += ",\"samplers\":[{}";
  for (std::size_t i = 1; i < gltf_limits::kMaxObjects; ++i) text += ",{}";
  text += "]}";
  std::ofstream(dir / "asset" / "a.gltf") << text;
  // Plus the scene, node, mesh, primitive, accessor, view and buffer of the triangle.
  EXPECT_CONTAINS(load_error((dir / "asset" / "a.gltf").string()),
                  ": glTF: 1000007 objects exceed the limit of 1000000");
}

TEST(GltfHostile, DeeplyNestedJsonIsRefused) {
  // tinygltf converts extras recursively; 100000 levels would overflow its stack.
  const fs::path dir = scratch("nested");
  std::string text = triangle_doc(data_uri(bytes_of(kTriangle))).dump();
  text.pop_back();
  text += ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  std::ofstream(dir / "asset" / "a.gltf") << text;
  const std::string path = (dir / "asset" / "a.gltf").string();
  EXPECT_CONTAINS(load_error(path), ": JSON: nested deeper than 128 levels");
  // 100 levels are fine.
  text = triangle_doc(data_uri(bytes_of(kTriangle))).dump();
  text.pop_back();
  text += ",\"extras\":" + std::string(100, '[') + std::string(100, ']') + "}";
  std::ofstream(dir / "asset" / "a.gltf") << text;
  EXPECT_EQ(load_gltf(path).meshes.size(), 1u);
}

// Found by the fuzzer (docs/fuzzing.md): a GLB whose header declares a total length under the
// 20 bytes of header and chunk header once made `length - 20` wrap around, and the loader
// copied 285 MB past the end of the file.
TEST(GltfHostile, GlbDeclaringALengthShorterThanItsHeaderIsRefused) {
  const fs::path path = fs::path(::testing::TempDir()) / "short_length.glb";
  const std::string json_text = R"({"asset":{"version":"2.0"}})";
  std::string bytes("glTF", 4);
  auto put32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes += static_cast<char>((v >> (8 * i)) & 0xff);
  };
  put32(2);           // version
  put32(0);           // declared total length: shorter than any header
  put32(0x11080000);  // JSON chunk length, as in the fuzzer's input
  put32(0x4E4F534A);  // "JSON"
  bytes += json_text;
  std::ofstream(path, std::ios::binary) << bytes;
  const std::string message = load_error(path.string());
  EXPECT_CONTAINS(message, ": GLB header: declared length 0 is shorter than the 20-byte header");
}

}  // namespace
}  // namespace prism
