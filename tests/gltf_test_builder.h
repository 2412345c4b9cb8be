// A small builder of glTF documents with one data-URI buffer, for tests that pin down one
// loader rule each with a hand-made file.
#pragma once

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/strutil.h>
#include <nlohmann/json.hpp>
#include "tests/scratch_dir.h"

namespace prism::test {

using nlohmann::json;

// Library base64 (OpenImageIO's), for the data URIs of hand-made files.
inline std::string base64(const std::vector<unsigned char>& data) {
  return OIIO::Strutil::base64_encode(
      OIIO::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

// Builds a glTF document with one data-URI buffer.
class Builder {
 public:
  Builder() {
    doc["asset"] = {{"version", "2.0"}};
    doc["scene"] = 0;
    doc["scenes"] = json::array({json{{"nodes", json::array()}}});
  }

  template <typename T>
  int view(const std::vector<T>& values) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    const std::size_t offset = bin_.size();
    bin_.resize(offset + values.size() * sizeof(T));
    std::memcpy(bin_.data() + offset, values.data(), values.size() * sizeof(T));
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    return static_cast<int>(doc["bufferViews"].size() - 1);
  }

  int accessor(int view, int component_type, std::size_t count, const char* type,
               bool normalized = false) {
    json a = {
        {"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size() - 1);
  }

  int positions(const std::vector<float>& xyz) {
    return accessor(view(xyz), 5126, xyz.size() / 3, "VEC3");
  }

  // A unit quad in the XY plane: 4 vertices.
  int quad_positions() { return positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}); }

  int mesh(json primitive) {
    doc["meshes"].push_back({{"primitives", json::array({primitive})}});
    return static_cast<int>(doc["meshes"].size() - 1);
  }

  int node(json n, bool root = true) {
    doc["nodes"].push_back(n);
    const int index = static_cast<int>(doc["nodes"].size() - 1);
    if (root) doc["scenes"][0]["nodes"].push_back(index);
    return index;
  }

  std::string write(const std::string& name) {
    if (!bin_.empty()) {
      doc["buffers"] =
          json::array({{{"byteLength", bin_.size()},
                        {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
    }
    const auto dir = scratch_dir("gltf_loader_test");
    const std::string path = (dir / name).string();
    std::ofstream(path) << doc.dump(1);
    return path;
  }

  json doc;

 private:
  std::vector<unsigned char> bin_;
};

}  // namespace prism::test
