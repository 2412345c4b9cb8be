// Building the one-line LoadError messages shared by the glTF loader's parts.
#pragma once

#include <string>

#include "scene_io/gltf_loader.h"

namespace prism::gltf_detail {

// Messages from tinygltf and nlohmann span several lines and end in newlines; a LoadError must
// fit on one line so that a command-line user sees it whole next to the file name.
inline std::string one_line(const std::string& text) {
  std::string out;
  bool pending_space = false;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      pending_space = !out.empty();
      continue;
    }
    if (pending_space) out += ' ';
    pending_space = false;
    out += c;
  }
  return out;
}

// "file: element: what", with the file exactly as the user wrote it.
[[noreturn]] inline void fail(const std::string& file, const std::string& element,
                              const std::string& what) {
  throw LoadError(one_line(file + ": " + element + ": " + what));
}

inline std::string indexed(const std::string& array, std::size_t i) {
  return array + "[" + std::to_string(i) + "]";
}

}  // namespace prism::gltf_detail
