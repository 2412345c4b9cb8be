// Hostile glTF files (issue 6): paths leaving the asset's folder, data URIs that lie about
// their size, counts, strides and offsets past the data, huge images, node cycles and deep
// hierarchies, and documents too big or too deep. Each must give a one-line LoadError naming
// the element, before any large allocation; the limits are in scene_io/gltf_limits.h.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>
#include <nlohmann/json.hpp>

#include "scene_io/gltf_limits.h"
#include "scene_io/gltf_loader.h"
#include "tests/scratch_dir.h"

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
  const fs::path dir =
      test::scratch_dir("hostile") / name;  // short: a URI over 64 bytes is quoted cut
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
                  ": images[0]: not a PNG or JPEG image (it starts with 6E 6F 74 20 61 6E 20 "
                  "69); glTF images must be PNG or JPEG");
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
  EXPECT_CONTAINS(message, ": GLB header: declared length 0 differs from the file size 47");
}

// ---------------------------------------------------------------------------------------------
// Images: only PNG and JPEG reach a decoder, and only their own

// Bytes of an image OpenImageIO writes (format by the name's extension), read back from disk.
std::vector<unsigned char> encoded_image(const std::string& name, int width, int height,
                                         bool progressive = false) {
  const fs::path path = fs::path(::testing::TempDir()) / name;
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (progressive) spec.attribute("jpeg:progressive", 1);
  std::vector<unsigned char> pixels(std::size_t(width) * std::size_t(height) * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>(i * 7);
  auto out = OIIO::ImageOutput::create(path.string());
  EXPECT_TRUE(out && out->open(path.string(), spec) &&
              out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

// A DDS volume texture (DDSD_DEPTH, DDSCAPS2_VOLUME) of 4 x 4 x 4 RGBA texels: OpenImageIO's
// DDS reader once wrote all four slices into storage sized for one.
std::vector<unsigned char> dds_volume() {
  std::vector<unsigned char> out = {'D', 'D', 'S', ' '};
  const auto put = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
  };
  for (uint32_t v : {124u, 0x1u | 0x2u | 0x4u | 0x1000u | 0x800000u, 4u, 4u, 16u, 4u, 1u}) put(v);
  for (int i = 0; i < 11; ++i) put(0);
  for (uint32_t v : {32u, 0x41u, 0u, 32u, 0xFF0000u, 0xFF00u, 0xFFu, 0xFF000000u}) put(v);
  for (uint32_t v : {0x1000u, 0x200000u, 0u, 0u, 0u}) put(v);
  for (int i = 0; i < 256; ++i) out.push_back(0x7F);  // a float 3.4e38 wherever it lands
  return out;
}

// `size` bytes: `head`, then `fill`.
std::vector<unsigned char> starting_with(std::initializer_list<unsigned char> head,
                                         std::size_t size, unsigned char fill) {
  std::vector<unsigned char> out(size, fill);
  std::copy(head.begin(), head.end(), out.begin());
  return out;
}

// A scene with one textured triangle whose image comes from `image` (uri or bufferView).
json textured_doc(const json& image, const std::vector<unsigned char>& bin = {}) {
  std::vector<unsigned char> buffer = bytes_of(kTriangle);
  json doc = triangle_doc("");
  if (!bin.empty()) {
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", bin.size()}});
    buffer.insert(buffer.end(), bin.begin(), bin.end());
  }
  doc["buffers"] = json::array({{{"byteLength", buffer.size()}, {"uri", data_uri(buffer)}}});
  doc["images"] = json::array({image});
  doc["textures"] = json::array({{{"source", 0}}});
  doc["materials"] =
      json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  return doc;
}

TEST(GltfHostile, VolumeAndOtherFormatsNeverReachADecoder) {
  const fs::path dir = scratch("formats");
  const std::vector<unsigned char> dds = dds_volume();
  const std::string not_png = ": images[0]: not a PNG or JPEG image (it starts with 44 44 53 20 ";
  // In a data URI, a bufferView and a file, each claiming to be a PNG.
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "uri.gltf",
                            textured_doc({{"uri", "data:image/png;base64," + base64(dds)}}))),
      not_png);
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "view.gltf",
                            textured_doc({{"bufferView", 1}, {"mimeType", "image/png"}}, dds))),
      not_png);
  write_bytes(dir / "asset" / "volume.png", dds);
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "file.gltf", textured_doc({{"uri", "volume.png"}}))),
      not_png);
  // In a bufferView declared as PNG or JPEG: a Maya IFF (FOR4) and a DPX (SDPX), formats whose
  // readers overflowed the heap or aborted, and WebP, named with the extension it would need.
  const struct {
    std::vector<unsigned char> bytes;
    const char* mime;
    std::string expected;
  } cases[] = {
      {starting_with({'F', 'O', 'R', '4', 0, 0, 0, 0x80, 'C', 'I', 'M', 'G'}, 140, 0xFF),
       "image/png", "(it starts with 46 4F 52 34 00 00 00 80)"},
      {starting_with({'S', 'D', 'P', 'X'}, 2600, 0x41), "image/jpeg",
       "(it starts with 53 44 50 58 41 41 41 41)"},
      {starting_with({'R', 'I', 'F', 'F', 26, 0, 0, 0, 'W', 'E', 'B', 'P'}, 34, 0), "image/png",
       ": images[0]: a WebP image (EXT_texture_webp), which is not supported"},
  };
  for (const auto& c : cases) {
    EXPECT_CONTAINS(
        load_error(write_json(dir / "asset" / "view.gltf",
                              textured_doc({{"bufferView", 1}, {"mimeType", c.mime}}, c.bytes))),
        c.expected);
  }
}

TEST(GltfHostile, ImageBytesMustAgreeWithTheDeclaredType) {
  const fs::path dir = scratch("mime");
  const std::vector<unsigned char> jpeg = encoded_image("small.jpg", 4, 4);
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "a.gltf",
                            textured_doc({{"bufferView", 1}, {"mimeType", "image/png"}}, jpeg))),
      ": images[0]: declared as \"image/png\" but the bytes are JPEG");
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "b.gltf",
                            textured_doc({{"uri", "data:image/png;base64," + base64(jpeg)}}))),
      ": images[0]: declared as \"image/png\" but the bytes are JPEG");
  // Agreeing, it loads, and the texture has the JPEG's size.
  const SceneDescription s =
      load_gltf(write_json(dir / "asset" / "c.gltf",
                           textured_doc({{"bufferView", 1}, {"mimeType", "image/jpeg"}}, jpeg)));
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 4);
  EXPECT_EQ(s.textures[0].value_count(), 4u * 4u * 3u);
}

// The JPEG with its scan (SOS header and entropy-coded data) repeated until it has `scans`.
std::vector<unsigned char> with_scans(const std::vector<unsigned char>& jpeg, int scans) {
  std::size_t sos = 2;
  while (!(jpeg[sos] == 0xFF && jpeg[sos + 1] == 0xDA))
    sos += 2 + (jpeg[sos + 2] << 8 | jpeg[sos + 3]);
  const std::size_t eoi = jpeg.size() - 2;
  std::vector<unsigned char> out(jpeg.begin(), jpeg.begin() + std::ptrdiff_t(sos));
  for (int i = 0; i < scans; ++i)
    out.insert(out.end(), jpeg.begin() + std::ptrdiff_t(sos), jpeg.begin() + std::ptrdiff_t(eoi));
  out.insert(out.end(), {0xFF, 0xD9});
  return out;
}

TEST(GltfHostile, JpegWithTooManyScansIsRefusedBeforeDecoding) {
  const fs::path dir = scratch("scans");
  const std::vector<unsigned char> baseline = encoded_image("scan.jpg", 16, 16);
  const auto doc = [&](const std::vector<unsigned char>& jpeg) {
    return textured_doc({{"bufferView", 1}, {"mimeType", "image/jpeg"}}, jpeg);
  };
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc(with_scans(baseline, 129)))),
                  ": images[0]: 129 JPEG scans of 256 pixels exceed the decoding limits (128 "
                  "scans, 2147483648 pixels x scans)");
  // A real progressive JPEG (about ten scans) loads.
  const SceneDescription s = load_gltf(
      write_json(dir / "asset" / "b.gltf", doc(encoded_image("progressive.jpg", 64, 48, true))));
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].height, 48);
}

TEST(GltfHostile, DecompressionBombIsRefusedFromItsHeader) {
  // A 16 x 16 JPEG whose frame header claims 8192 x 8192: within the size limits, but no
  // 700-byte JPEG can encode it, and its texels (768 MiB as floats) would be allocated first.
  std::vector<unsigned char> jpeg = encoded_image("bomb.jpg", 16, 16);
  std::size_t sof = 2;
  while (!(jpeg[sof] == 0xFF && jpeg[sof + 1] == 0xC0))
    sof += 2 + (jpeg[sof + 2] << 8 | jpeg[sof + 3]);
  for (std::size_t at : {sof + 5, sof + 7}) jpeg[at] = 0x20, jpeg[at + 1] = 0x00;
  const fs::path dir = scratch("bomb");
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "a.gltf",
                            textured_doc({{"bufferView", 1}, {"mimeType", "image/jpeg"}}, jpeg))),
      ": images[0]: 8192 x 8192 pixels cannot be encoded in " + std::to_string(jpeg.size()) +
          " bytes (JPEG compresses at most 4096:1)");
}

// ---------------------------------------------------------------------------------------------
// GLB container

// A GLB of a one-triangle scene whose 36-byte buffer is the BIN chunk.
std::vector<unsigned char> triangle_glb() {
  json doc = triangle_doc("");
  doc["buffers"][0].erase("uri");
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  std::vector<unsigned char> out;
  const auto put = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
  };
  put(0x46546C67);
  put(2);
  put(uint32_t(12 + 8 + text.size() + 8 + 36));
  put(uint32_t(text.size()));
  put(0x4E4F534A);
  out.insert(out.end(), text.begin(), text.end());
  put(36);
  put(0x004E4942);
  const std::vector<unsigned char> bin = bytes_of(kTriangle);
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

void set32(std::vector<unsigned char>& bytes, std::size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + std::size_t(i)] = uint8_t(v >> (8 * i));
}

TEST(GltfHostile, GlbContainerIsValidatedCompletely) {
  const fs::path dir = scratch("glb");
  const fs::path path = dir / "asset" / "a.glb";
  const std::vector<unsigned char> good = triangle_glb();
  write_bytes(path, good);
  EXPECT_EQ(load_gltf(path.string()).meshes.size(), 1u);
  const std::size_t bin_header = good.size() - 36 - 8;
  // Cut by 4 and by 8 bytes with the header's total length fixed: tinygltf read past the end.
  for (uint32_t cut : {4u, 8u}) {
    std::vector<unsigned char> bytes(good.begin(), good.end() - cut);
    set32(bytes, 8, uint32_t(bytes.size()));
    write_bytes(path, bytes);
    EXPECT_CONTAINS(load_error(path.string()),
                    ": GLB chunk 1: length 36 at byte " + std::to_string(bin_header) + " runs " +
                        std::to_string(cut) + " bytes past the end of the file");
  }
  std::vector<unsigned char> bytes = good;
  set32(bytes, 8, uint32_t(good.size() + 4));
  write_bytes(path, bytes);
  EXPECT_CONTAINS(load_error(path.string()), ": GLB header: declared length " +
                                                 std::to_string(good.size() + 4) +
                                                 " differs from the file size");
  bytes = good;
  bytes.insert(bytes.end(), {0, 0, 0});  // a chunk header cut short
  set32(bytes, 8, uint32_t(bytes.size()));
  write_bytes(path, bytes);
  EXPECT_CONTAINS(load_error(path.string()),
                  ": GLB chunk 2: header at byte " + std::to_string(good.size()) + " is cut short");
  // A second BIN chunk, and a BIN chunk of a length that is not a multiple of 4.
  bytes = good;
  bytes.insert(bytes.end(), {4, 0, 0, 0, 'B', 'I', 'N', 0, 1, 2, 3, 4});
  set32(bytes, 8, uint32_t(bytes.size()));
  write_bytes(path, bytes);
  EXPECT_CONTAINS(load_error(path.string()),
                  ": GLB chunk 2: a BIN chunk that does not follow the JSON chunk");
  bytes = good;
  set32(bytes, bin_header, 35);
  write_bytes(path, bytes);
  EXPECT_CONTAINS(load_error(path.string()), ": GLB chunk 1: length 35 is not a multiple of 4");
  // A chunk of an unknown type after the first two is ignored, as the spec asks.
  bytes = good;
  bytes.insert(bytes.end(), {4, 0, 0, 0, 'X', 'T', 'R', 'A', 1, 2, 3, 4});
  set32(bytes, 8, uint32_t(bytes.size()));
  write_bytes(path, bytes);
  const SceneDescription s = load_gltf(path.string());
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].primitives[0].positions[1], V3f(1, 0, 0));
}

// ---------------------------------------------------------------------------------------------
// URIs: decoded once by RFC 3986, opened exactly as checked

TEST(GltfHostile, UrisAreDecodedByRfc3986Only) {
  const fs::path dir = scratch("rfc3986");
  // `+` is a plus: "tri+1.bin" is that file, never "tri 1.bin" (tinygltf's form decoding).
  write_bytes(dir / "asset" / "tri+1.bin", bytes_of(kTriangle));
  write_bytes(dir / "asset" / "tri 1.bin", bytes_of({5, 5, 5, 6, 5, 5, 5, 6, 5}));
  const SceneDescription s =
      load_gltf(write_json(dir / "asset" / "a.gltf", triangle_doc("tri+1.bin")));
  EXPECT_EQ(s.meshes.at(0).primitives.at(0).positions[1], V3f(1, 0, 0));
  // %20 is the space.
  const SceneDescription t =
      load_gltf(write_json(dir / "asset" / "b.gltf", triangle_doc("tri%201.bin")));
  EXPECT_EQ(t.meshes.at(0).primitives.at(0).positions[1], V3f(6, 5, 5));
  // An invalid escape and an escaped NUL (which cut tinygltf's path short) are refused.
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "c.gltf", triangle_doc("tri%zz/../../outside/x.bin"))),
      ": buffers[0].uri: \"tri%zz/../../outside/x.bin\" has an invalid percent-escape at "
      "character 3");
  EXPECT_CONTAINS(
      load_error(write_json(dir / "asset" / "d.gltf", triangle_doc("tri+1.bin%00.png"))),
      ": buffers[0].uri: \"tri+1.bin%00.png\" decodes to a NUL character (%00)");
}

TEST(GltfHostile, DataUrisOfOtherMediaTypesAreErrors) {
  const fs::path dir = scratch("media");
  write_bytes(dir / "outside" / "secret.bin", bytes_of(kTriangle));
  // tinygltf read this as the path "/../../outside/secret.bin" relative to the asset.
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf",
                                        triangle_doc("data:x;base64,/../../outside/secret.bin"))),
                  ": buffers[0].uri: data: URI of media type \"x\" is not allowed for a buffer "
                  "(only base64 application/octet-stream or application/gltf-buffer)");
  const std::vector<unsigned char> bin = bytes_of(kTriangle);
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "b.gltf",
                                        triangle_doc("data:text/plain;base64," + base64(bin)))),
                  ": buffers[0].uri: data: URI of media type \"text/plain\" is not allowed");
  EXPECT_EQ(
      load_gltf(write_json(dir / "asset" / "c.gltf",
                           triangle_doc("data:application/gltf-buffer;base64," + base64(bin))))
          .meshes.size(),
      1u);
  json doc = triangle_doc(data_uri(bin));
  doc["images"] = json::array({{{"uri", "data:image/gif;base64,R0lGODlhAQABAAAAACw="}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "d.gltf", doc)),
                  ": images[0].uri: data: URI of media type \"image/gif\" is not allowed for an "
                  "image (only base64 image/png or image/jpeg)");
}

TEST(GltfHostile, NoRetryRelativeToTheCurrentDirectory) {
  const fs::path dir = scratch("cwd");
  write_bytes(dir / "outside" / "secret.bin", bytes_of(kTriangle));
  const std::string path = write_json(dir / "asset" / "a.gltf", triangle_doc("secret.bin"));
  const fs::path previous = fs::current_path();
  fs::current_path(dir / "outside");  // where tinygltf's FindFile looked next
  const std::string message = load_error(path);
  fs::current_path(previous);
  EXPECT_CONTAINS(message, ": buffers[0].uri: file \"secret.bin\" not found");
}

TEST(GltfHostile, OnlyRegularFilesOfTheDeclaredSizeAreRead) {
  const fs::path dir = scratch("regular");
  ASSERT_EQ(::mkfifo((dir / "asset" / "fifo.bin").c_str(), 0600), 0);
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", triangle_doc("fifo.bin"))),
                  ": buffers[0].uri: \"fifo.bin\" is not a regular file");
  fs::create_directories(dir / "asset" / "sub");
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "b.gltf", triangle_doc("sub"))),
                  ": buffers[0].uri: \"sub\" is not a regular file");
  std::vector<unsigned char> big = bytes_of(kTriangle);
  big.resize(4096);
  write_bytes(dir / "asset" / "big.bin", big);
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "c.gltf", triangle_doc("big.bin"))),
                  ": buffers[0].uri: file holds 4096 bytes but byteLength is 36");
  // A symlink that stays inside the folder is followed.
  write_bytes(dir / "asset" / "sub" / "tri.bin", bytes_of(kTriangle));
  fs::create_symlink("sub/tri.bin", dir / "asset" / "link.bin");
  EXPECT_EQ(load_gltf(write_json(dir / "asset" / "d.gltf", triangle_doc("link.bin"))).meshes.size(),
            1u);
}

// ---------------------------------------------------------------------------------------------
// One memory budget per load

LoadOptions with_budget(std::size_t bytes) {
  LoadOptions o;
  o.memory_limit = bytes;
  return o;
}

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(GltfHostile, ZeroFilledAccessorsShareOneBudget) {
  // Five primitives each with its own zero-filled POSITION accessor of 3 x 2^18 vertices (9 MiB
  // as V3f, and 3 MiB of generated indices): each is within every per-accessor limit; together
  // they cross 40 MiB at the fourth.
  const fs::path dir = scratch("zero_filled");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  json primitives = json::array();
  for (int i = 0; i < 5; ++i) {
    doc["accessors"].push_back({{"componentType", 5126}, {"count", 3 << 18}, {"type", "VEC3"}});
    primitives.push_back({{"attributes", {{"POSITION", i + 1}}}});
  }
  doc["meshes"][0]["primitives"] = primitives;
  const std::string path = write_json(dir / "asset" / "a.gltf", doc);
  EXPECT_CONTAINS(load_error(path, with_budget(40 * kMiB)),
                  ": accessors[4]: needs 9.0 MiB, which takes the load past its memory budget of "
                  "40.0 MiB (36.0 MiB already used; see --memory-limit)");
  // The same file within a larger budget loads.
  EXPECT_EQ(load_gltf(path, with_budget(256 * kMiB)).meshes.size(), 1u);
}

TEST(GltfHostile, PrimitivesSharingAnAccessorAreChargedPerCopy) {
  const fs::path dir = scratch("shared_accessor");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["accessors"].push_back({{"componentType", 5126}, {"count", 3 << 18}, {"type", "VEC3"}});
  json primitives = json::array();
  // 12 MiB each (positions and generated indices): the ninth crosses 100 MiB.
  for (int i = 0; i < 16; ++i) primitives.push_back({{"attributes", {{"POSITION", 1}}}});
  doc["meshes"][0]["primitives"] = primitives;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc), with_budget(100 * kMiB)),
                  ": accessors[1]: needs 9.0 MiB, which takes the load past its memory budget of "
                  "100.0 MiB (96.0 MiB already used");
}

TEST(GltfHostile, MorphWeightSetsAreChargedPerMeshCopy) {
  // 64 nodes place one morphed mesh with 64 distinct weights: 64 converted copies.
  const fs::path dir = scratch("morph");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["accessors"].push_back({{"componentType", 5126}, {"count", 3 << 16}, {"type", "VEC3"}});
  doc["meshes"][0]["primitives"][0] = {{"attributes", {{"POSITION", 1}}},
                                       {"targets", json::array({{{"POSITION", 1}}})}};
  doc["nodes"] = json::array();
  doc["scenes"][0]["nodes"] = json::array();
  for (int i = 0; i < 64; ++i) {
    doc["nodes"].push_back({{"mesh", 0}, {"weights", {0.01 * (i + 1)}}});
    doc["scenes"][0]["nodes"].push_back(i);
  }
  const std::string message =
      load_error(write_json(dir / "asset" / "a.gltf", doc), with_budget(64 * kMiB));
  // Per copy: positions, indices, the morph sums in double and the target's deltas (18.75
  // MiB); the fourth copy's sums cross 64 MiB.
  EXPECT_CONTAINS(message,
                  ": meshes[0].primitives[0].targets: needs 13.5 MiB, which takes the "
                  "load past its memory budget of 64.0 MiB");
}

TEST(GltfHostile, SkinMatricesAreChargedBeforeTheyAreRead) {
  // One joint, but 2^22 zero-filled inverse bind matrices (512 MiB as double matrices).
  const fs::path dir = scratch("skin");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["accessors"].push_back({{"componentType", 5126}, {"count", 1 << 22}, {"type", "MAT4"}});
  doc["skins"] = json::array({{{"joints", {0}}, {"inverseBindMatrices", 1}}});
  doc["nodes"][0]["skin"] = 0;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc), with_budget(64 * kMiB)),
                  ": accessors[1]: needs 512.0 MiB, which takes the load past its memory budget "
                  "of 64.0 MiB");
}

TEST(GltfHostile, OneBinReferencedByManyBuffersIsChargedEachTime) {
  const fs::path dir = scratch("many_buffers");
  std::vector<unsigned char> bin = bytes_of(kTriangle);
  bin.resize(kMiB);
  write_bytes(dir / "asset" / "one.bin", bin);
  json doc = triangle_doc("one.bin");
  doc["buffers"] = json::array();
  for (int i = 0; i < 256; ++i)
    doc["buffers"].push_back({{"byteLength", kMiB}, {"uri", "one.bin"}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc), with_budget(64 * kMiB)),
                  ": buffers[63].uri: needs 1.0 MiB, which takes the load past its memory budget");
}

TEST(GltfHostile, TexelsAreSharedBetweenSamplersAndEncodings) {
  // One 512 x 512 PNG read by five material slots through four samplers: one decoded copy,
  // so the load fits a budget that a copy per sampler and encoding would cross.
  const fs::path dir = scratch("shared_texels");
  const std::vector<unsigned char> png = encoded_image("shared.png", 512, 512);
  json doc = textured_doc({{"bufferView", 1}, {"mimeType", "image/png"}}, png);
  doc["samplers"] =
      json::array({json::object(), {{"wrapS", 33071}}, {{"wrapT", 33648}}, {{"magFilter", 9728}}});
  doc["textures"] = json::array();
  for (int i = 0; i < 4; ++i) doc["textures"].push_back({{"source", 0}, {"sampler", i}});
  doc["materials"][0] = {
      {"pbrMetallicRoughness",
       {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 1}}}}},
      {"normalTexture", {{"index", 2}}},
      {"occlusionTexture", {{"index", 3}}},
      {"emissiveTexture", {{"index", 1}}}};
  // 0.75 MiB of 8-bit texels, the PNG's bytes and the buffer: under 3 MiB, where five
  // copies (3.75 MiB) would not fit.
  const SceneDescription s =
      load_gltf(write_json(dir / "asset" / "a.gltf", doc), with_budget(3 * kMiB));
  ASSERT_EQ(s.textures.size(), 5u);
  for (const TextureImage& t : s.textures) {
    ASSERT_TRUE(t.shared_codes);
    EXPECT_EQ(t.shared_codes.get(), s.textures[0].shared_codes.get());
    EXPECT_EQ(t.value_count(), 512u * 512u * 3u);
  }
}

TEST(GltfHostile, DefaultBudgetSuitsA24GiBMachine) {
  EXPECT_EQ(LoadOptions().memory_limit, std::size_t{8} << 30);
}

// ---------------------------------------------------------------------------------------------
// Numbers in the renderer's float, integers before tinygltf truncates them

TEST(GltfHostile, ValuesFiniteAsDoublesMustBeFiniteAsFloats) {
  const fs::path dir = scratch("floats");
  const auto with_light = [&](const json& light) {
    json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
    doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({light});
    doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    doc["scenes"][0]["nodes"].push_back(1);
    return write_json(dir / "asset" / "light.gltf", doc);
  };
  EXPECT_CONTAINS(load_error(with_light({{"type", "point"}, {"intensity", 1e300}})),
                  ": extensions.KHR_lights_punctual.lights[0].intensity: must be >= 0, and finite "
                  "as a float times the colour");
  EXPECT_CONTAINS(load_error(with_light({{"type", "point"}, {"color", {1e300, 1, 1}}})),
                  ": extensions.KHR_lights_punctual.lights[0].color[0]: must be >= 0 and finite");
  // 1e20 x 1e20 overflows in the product only.
  EXPECT_CONTAINS(
      load_error(with_light({{"type", "point"}, {"color", {1e20, 1, 1}}, {"intensity", 1e20}})),
      "lights[0].intensity: must be >= 0, and finite as a float times the colour");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["materials"] = json::array(
      {{{"emissiveFactor", {1, 1, 1}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e300}}}}}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "e.gltf", doc)),
                  ": materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: "
                  "strength 1e+300 times the emissive factor is not finite as a float");
  doc["materials"] = json::array({{{"extensions", {{"KHR_materials_ior", {{"ior", 1e300}}}}}}});
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "i.gltf", doc)),
                  ": materials[0].extensions.KHR_materials_ior.ior: index of refraction 1e+300 "
                  "exceeds 1000");
  // KHR_materials_volume: the spec's ranges, finite as floats.
  const auto volume_error = [&](const json& volume) {
    doc["materials"] = json::array({{{"extensions", {{"KHR_materials_volume", volume}}}}});
    return load_error(write_json(dir / "asset" / "vol.gltf", doc));
  };
  EXPECT_CONTAINS(volume_error({{"thicknessFactor", -1}}),
                  ": materials[0].extensions.KHR_materials_volume.thicknessFactor: expected a "
                  "number >= 0, finite as a float");
  EXPECT_CONTAINS(
      volume_error({{"thicknessFactor", 1e300}}),
      "KHR_materials_volume.thicknessFactor: expected a number >= 0, finite as a float");
  EXPECT_CONTAINS(volume_error({{"attenuationDistance", 0}}),
                  ": materials[0].extensions.KHR_materials_volume.attenuationDistance: expected a "
                  "number > 0, finite as a float");
  EXPECT_CONTAINS(volume_error({{"attenuationDistance", 1e39}}),
                  "KHR_materials_volume.attenuationDistance: expected a number > 0");
  EXPECT_CONTAINS(volume_error({{"attenuationColor", {1, 1.5, 1}}}),
                  ": materials[0].extensions.KHR_materials_volume.attenuationColor[1]: value 1.5 "
                  "is outside [0, 1]");
  EXPECT_CONTAINS(volume_error({{"attenuationColor", {1, 1}}}),
                  "KHR_materials_volume.attenuationColor");
  EXPECT_CONTAINS(volume_error({{"attenuationColor", {1, "red", 1}}}),
                  "KHR_materials_volume.attenuationColor");
  EXPECT_CONTAINS(volume_error({{"thicknessFactor", "thick"}}),
                  "KHR_materials_volume.thicknessFactor");
  doc.erase("materials");
  doc["nodes"][0]["scale"] = {1e39, 1, 1};
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "s.gltf", doc)),
                  ": nodes[0]: world transform is not finite as a float");
  // 1e30 is a float, but places the triangle's vertex at 1e30 x ... only finite values: fine.
  // A vertex at 1e10 scaled by 1e30 is not.
  doc["nodes"][0]["scale"] = {1e30, 1, 1};
  doc["buffers"][0]["uri"] = data_uri(bytes_of({0, 0, 0, 1e10f, 0, 0, 0, 1, 0}));
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "v.gltf", doc)),
                  ": nodes[0]: the world transform places mesh vertices beyond float's range");
  // A scale of 0 flattens the mesh: a warning naming the node.
  doc["buffers"][0]["uri"] = data_uri(bytes_of(kTriangle));
  doc["nodes"][0]["scale"] = {0, 1, 1};
  const SceneDescription s = load_gltf(write_json(dir / "asset" / "z.gltf", doc));
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_CONTAINS(s.warnings[0], "nodes[0]: the world transform's scale flattens the node's mesh");
}

TEST(GltfHostile, IntegersPastIntAreRefusedBeforeTruncation) {
  const fs::path dir = scratch("ints");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["meshes"][0]["primitives"][0]["mode"] = (std::uint64_t{1} << 32) + 4;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "a.gltf", doc)),
                  ": meshes[0].primitives[0].mode: expected an integer in [0, 2^31 - 1], got "
                  "4294967300");
  doc["meshes"][0]["primitives"][0].erase("mode");
  doc["accessors"][0]["componentType"] = (std::uint64_t{1} << 32) + 5126;
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "b.gltf", doc)),
                  ": accessors[0].componentType: expected an integer in [0, 2^31 - 1]");
}

// ---------------------------------------------------------------------------------------------
// Messages: one bounded line, control characters escaped, the file named once

TEST(GltfHostile, MessagesAreBoundedAndEscaped) {
  const fs::path dir = scratch("messages");
  // An 8 MB data URI of a type that is not allowed: the message quotes a bounded part.
  const std::string huge = "data:" + std::string(8 << 20, 'A') + ";base64,AAAA";
  const std::string message = load_error(write_json(dir / "asset" / "a.gltf", triangle_doc(huge)));
  EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
  EXPECT_CONTAINS(message, "(8388608 bytes) is not allowed for a buffer");
  // A camera and a node named with terminal escape codes.
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["cameras"] = json::array({{{"name", "\x1b[2J\x1b[Hcam\n"},
                                 {"type", "perspective"},
                                 {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}});
  doc["nodes"][0]["camera"] = 0;
  doc["nodes"][0]["name"] = "n\x07";
  const SceneDescription s = load_gltf(write_json(dir / "asset" / "b.gltf", doc));
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].name, "\\x1B[2J\\x1B[Hcam\\x0A");
  EXPECT_EQ(s.instances.at(0).node_name, "n\\x07");
  // An unknown type in an error is escaped as well.
  doc["cameras"][0]["type"] = "\x1b]0;owned\x07";
  EXPECT_CONTAINS(load_error(write_json(dir / "asset" / "c.gltf", doc)),
                  ": cameras[0].type: unknown camera type \"\\x1B]0;owned\\x07\"");
}

TEST(GltfHostile, WarningsDoNotRepeatTheFile) {
  const fs::path dir = scratch("warnings");
  json doc = triangle_doc(data_uri(bytes_of(kTriangle)));
  doc["extensionsUsed"] = {"EXT_unknown"};
  const std::string path = write_json(dir / "asset" / "a.gltf", doc);
  const SceneDescription s = load_gltf(path);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            "extensionsUsed: extension \"EXT_unknown\" is not supported and is ignored");
}

}  // namespace
}  // namespace prism
