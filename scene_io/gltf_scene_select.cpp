#include "scene_io/gltf_scene_select.h"

#include "scene_io/gltf_error.h"
#include "scene_io/gltf_loader.h"

namespace prism::gltf_detail {

std::size_t select_scene(const std::vector<std::string>& names, const std::string& wanted,
                         const std::string& file) {
  const std::size_t count = names.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (names[i] == wanted) return i;
  }
  // Digits only, no sign or spaces, and compared digit by digit so that no value overflows.
  bool is_index = !wanted.empty() && wanted.size() <= 19;
  std::size_t index = 0;
  for (char c : wanted) {
    if (c < '0' || c > '9') {
      is_index = false;
      break;
    }
    index = index * 10 + std::size_t(c - '0');
  }
  if (is_index && index < count) return index;
  std::string listed;
  for (std::size_t i = 0; i < count && i < 10; ++i) {
    const std::string& name = names[i];
    listed += (i ? ", " : "") + std::to_string(i) +
              (name.empty() ? " (unnamed)"
                            : " '" + (name.size() > 40 ? name.substr(0, 40) + "..." : name) + "'");
  }
  if (count > 10) listed += ", ...";
  const std::string shown = wanted.size() > 40 ? wanted.substr(0, 40) + "..." : wanted;
  // What is allowed too: a name, or an index in range (an unnamed scene has only its index).
  throw SceneSelectionError(
      one_line(file + ": scenes: no scene '" + shown + "' (the file has " + std::to_string(count) +
               (count == 1 ? " scene: " : " scenes: ") + listed + "; give a name or an index " +
               (count == 1 ? "0" : "from 0 to " + std::to_string(count - 1)) + ")"));
}

}  // namespace prism::gltf_detail
