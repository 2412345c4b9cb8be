// Building the one-line LoadError messages shared by the glTF loader's parts.
#pragma once

#include <cstdio>
#include <string>

#include "scene_io/gltf_loader.h"

namespace prism::gltf_detail {

// Longest message a LoadError or warning carries: a hostile file must not be able to print an
// 8 MB data URI (or any other value) to the user's terminal.
inline constexpr std::size_t kMaxMessageLength = 1024;

// `text` with every control character shown as \xNN, so that a name or value taken from a file
// cannot move the cursor, clear the screen or start a new line in a terminal.
inline std::string printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", u);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

// A value from the file quoted in a message, at most `limit` bytes of it.
inline std::string shown(const std::string& value, std::size_t limit = 64) {
  if (value.size() <= limit) return "\"" + printable(value) + "\"";
  return "\"" + printable(value.substr(0, limit)) + "...\" (" + std::to_string(value.size()) +
         " bytes)";
}

// Messages from tinygltf and nlohmann span several lines and end in newlines; a LoadError must
// fit on one line so that a command-line user sees it whole next to the file name. Whitespace
// runs become one space, other control characters are escaped, and the result is cut at
// kMaxMessageLength.
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
    out += printable(std::string(1, c));
    if (out.size() > kMaxMessageLength) {
      out.resize(kMaxMessageLength);
      return out + "... (message cut)";
    }
  }
  return out;
}

// "file: element: what", with the file exactly as the user wrote it.
[[noreturn]] inline void fail(const std::string& file, const std::string& element,
                              const std::string& what) {
  throw LoadError(one_line(file + ": " + element + ": " + what));
}

// A number from the file in a message: "1e+300", not std::to_string's 301 digits.
inline std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// A warning: "element: what". The file is not repeated: whoever prints the warnings names the
// file they came from once.
inline std::string warning(const std::string& element, const std::string& what) {
  return one_line(element + ": " + what);
}

inline std::string indexed(const std::string& array, std::size_t i) {
  return array + "[" + std::to_string(i) + "]";
}

}  // namespace prism::gltf_detail
