// The GLB container, validated completely before tinygltf sees it: tinygltf 2.7 checks the
// BIN chunk's length without its 8-byte header and reads past the end of a file cut short.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace prism::gltf_detail {

struct GlbChunks {
  std::size_t json_offset = 0, json_length = 0;
  bool has_bin = false;
  std::size_t bin_offset = 0, bin_length = 0;
  // Whether chunks of unknown types follow (the spec says to ignore them; they are dropped
  // before tinygltf reads the container).
  bool has_other_chunks = false;
};

// Checks the 12-byte header (magic "glTF", version 2, total length equal to the file's size)
// and every chunk: its 8-byte header and data inside the file, its length a multiple of 4,
// the first chunk JSON, at most one BIN and only right after it. Throws LoadError naming the
// header or chunk.
GlbChunks parse_glb(const std::vector<unsigned char>& bytes, const std::string& file);

// A GLB of exactly a JSON chunk (padded with spaces to 4 bytes) and, when bin is not null, a
// BIN chunk of bin_length bytes (padded with zeros).
std::vector<unsigned char> make_glb(const std::string& json, const unsigned char* bin,
                                    std::size_t bin_length, const std::string& file);

}  // namespace prism::gltf_detail
