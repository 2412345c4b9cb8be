// A folder of this test process's own under the system's temporary directory. CTest runs
// each test case in a process of its own, two at once, so a fixed name would be shared by
// cases that write the same file names; the folder goes, with what is in it, when the
// process exits, so runs leave nothing behind. (Not for use from several threads at once.)
#pragma once

#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>
#include <system_error>

namespace prism::test {

inline std::filesystem::path scratch_dir(const std::string& name) {
  struct Folders {
    std::map<std::string, std::filesystem::path> made;
    ~Folders() {
      for (const auto& [unused, path] : made) {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
      }
    }
  };
  static Folders folders;
  auto [it, added] = folders.made.try_emplace(name);
  if (added)
    it->second = std::filesystem::temp_directory_path() /
                 ("prism_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(it->second);
  return it->second;
}

}  // namespace prism::test
