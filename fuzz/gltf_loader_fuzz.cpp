// libFuzzer target over prism::load_gltf: every input is written to a file (the loader reads
// files, and resolves buffers and images relative to them) and loaded. LoadError is the
// expected answer to bad input; any other exception, crash, leak or sanitizer report is a bug.
// Built by fuzz/build.sh; see docs/fuzzing.md.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "scene_io/gltf_loader.h"

namespace {

// One private directory per process, so that parallel fuzzing jobs never share files and a
// relative URI in the input can only find what this target put there (nothing but the input).
const std::string& work_dir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/prism_fuzz_XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    return pattern;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  // The loader picks the format by the GLB magic, not the name; the extension only mirrors
  // what a user's file would be called.
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = work_dir() + (glb ? "/input.glb" : "/input.gltf");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror("fopen");
    std::abort();
  }
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    // A smaller budget than the default 8 GiB, so that the fuzzer's RSS limit (4 GiB) is never
    // what stops a run: an input needing more is a LoadError like any other.
    prism::LoadOptions options;
    options.memory_limit = std::size_t{1} << 30;
    const prism::SceneDescription scene = prism::load_gltf(path, options);
    // Touch what was loaded so that a bad size or pointer shows up under ASan here.
    std::size_t sum = 0;
    for (const auto& mesh : scene.meshes) {
      for (const auto& p : mesh.primitives) {
        for (uint32_t i : p.indices) sum += i < p.positions.size() ? 0 : 1;
      }
    }
    if (sum != 0) std::abort();  // an index out of range got past the loader
  } catch (const prism::LoadError&) {
  }
  std::remove(path.c_str());
  return 0;
}
