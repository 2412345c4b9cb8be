#include "scene_io/gltf_glb.h"

#include <cstdint>
#include <cstring>
#include <limits>

#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

constexpr uint32_t kMagic = 0x46546C67u;  // "glTF"
constexpr uint32_t kJson = 0x4E4F534Au;   // "JSON"
constexpr uint32_t kBin = 0x004E4942u;    // "BIN\0"

uint32_t le32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

void put32(unsigned char* p, std::size_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}

}  // namespace

GlbChunks parse_glb(const std::vector<unsigned char>& bytes, const std::string& file) {
  const std::size_t size = bytes.size();
  if (size < 12) fail(file, "GLB header", std::to_string(size) + " bytes, shorter than 12");
  if (le32(bytes.data()) != kMagic) fail(file, "GLB header", "magic is not \"glTF\"");
  const uint32_t version = le32(bytes.data() + 4);
  if (version != 2) fail(file, "GLB header", "version " + std::to_string(version) + ", not 2");
  const uint32_t length = le32(bytes.data() + 8);
  if (length != size) {
    fail(file, "GLB header",
         "declared length " + std::to_string(length) + " differs from the file size " +
             std::to_string(size));
  }
  GlbChunks out;
  std::size_t offset = 12;
  for (std::size_t index = 0; offset < size; ++index) {
    const std::string element = "GLB chunk " + std::to_string(index);
    if (size - offset < 8) {
      fail(file, element,
           "header at byte " + std::to_string(offset) + " is cut short by the end of the file");
    }
    const std::size_t chunk_length = le32(bytes.data() + offset);
    const uint32_t type = le32(bytes.data() + offset + 4);
    const std::size_t data = offset + 8;
    if (chunk_length > size - data) {
      fail(file, element,
           "length " + std::to_string(chunk_length) + " at byte " + std::to_string(offset) +
               " runs " + std::to_string(chunk_length - (size - data)) +
               " bytes past the end of the file");
    }
    if (chunk_length % 4 != 0) {
      fail(file, element,
           "length " + std::to_string(chunk_length) + " is not a multiple of 4 (chunks are " +
               "4-byte aligned)");
    }
    if (index == 0) {
      if (type != kJson) fail(file, element, "the first chunk is not JSON");
      if (chunk_length == 0) fail(file, element, "the JSON chunk is empty");
      out.json_offset = data;
      out.json_length = chunk_length;
    } else if (type == kJson) {
      fail(file, element, "a second JSON chunk");
    } else if (type == kBin) {
      if (index != 1) fail(file, element, "a BIN chunk that does not follow the JSON chunk");
      out.has_bin = true;
      out.bin_offset = data;
      out.bin_length = chunk_length;
    } else {
      out.has_other_chunks = true;
    }
    offset = data + chunk_length;
  }
  if (out.json_length == 0) fail(file, "GLB", "no JSON chunk");
  return out;
}

std::vector<unsigned char> make_glb(const std::string& json, const unsigned char* bin,
                                    std::size_t bin_length, const std::string& file) {
  const std::size_t json_padded = (json.size() + 3) / 4 * 4;
  const std::size_t bin_padded = (bin_length + 3) / 4 * 4;
  const std::size_t length = 12 + 8 + json_padded + (bin ? 8 + bin_padded : 0);
  if (length > std::numeric_limits<uint32_t>::max()) fail(file, "GLB", "larger than 4 GiB");
  charge(length, 1, "GLB");
  std::vector<unsigned char> out(length, 0);
  put32(out.data(), kMagic);
  put32(out.data() + 4, 2);
  put32(out.data() + 8, length);
  put32(out.data() + 12, json_padded);
  put32(out.data() + 16, kJson);
  std::memcpy(out.data() + 20, json.data(), json.size());
  std::memset(out.data() + 20 + json.size(), ' ', json_padded - json.size());
  if (bin) {
    unsigned char* chunk = out.data() + 20 + json_padded;
    put32(chunk, bin_padded);
    put32(chunk + 4, kBin);
    if (bin_length > 0) std::memcpy(chunk + 8, bin, bin_length);
  }
  return out;
}

}  // namespace prism::gltf_detail
