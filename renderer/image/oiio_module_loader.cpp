#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

#include "renderer/image/oiio_module.h"
#include "renderer/version.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleFile = "libprism_oiio.so";

// The folder of the binary this code is linked into: the prism executable, or the Python
// extension module inside its package (not the Python interpreter, /proc/self/exe there).
fs::path binary_folder() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&binary_folder), &info) && info.dli_fname) {
    std::error_code ec;
    const fs::path binary = fs::canonical(info.dli_fname, ec);
    if (!ec) return binary.parent_path();
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path(".") : exe.parent_path();
}

// ../lib/prism beside an executable (the build tree and an installation); beside the binary
// itself in a Python package.
fs::path module_path() {
  const fs::path folder = binary_folder();
  const fs::path beside = folder / kModuleFile;
  std::error_code ec;
  if (fs::exists(beside, ec)) return beside;
  return folder.parent_path() / "lib" / "prism" / kModuleFile;
}

// The build this binary was made by: the module must have been made by the same one.
std::string this_build() {
  return std::string(kVersion) + " " + kBuildCommit;
}

struct Loaded {
  const OiioModule* module = nullptr;
  std::string error;
};

Loaded load() {
  const fs::path path = module_path();
  // RTLD_LOCAL: OpenImageIO's own dependencies stay out of the global namespace, so nothing
  // else in the process binds to them by accident.
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    return {nullptr, "needs OpenImageIO, whose module " + path.string() +
                         " cannot be loaded: " + (why ? why : "unknown error")};
  }
  const auto build = reinterpret_cast<OiioModuleBuild>(::dlsym(handle, kOiioModuleBuild));
  const auto entry = reinterpret_cast<OiioModuleEntry>(::dlsym(handle, kOiioModuleEntry));
  if (!build || !entry)
    return {nullptr, "the OpenImageIO module " + path.string() + " is not Prism's"};
  if (this_build() != build())
    return {nullptr, "the OpenImageIO module " + path.string() + " is from another build (" +
                         build() + ", this is " + this_build() + ")"};
  // The handle stays open for the life of the process: the module's objects live as long.
  return {entry(), {}};
}

}  // namespace

const OiioModule& oiio_module(const std::string& for_path) {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = load(); });
  if (!loaded.module) throw std::runtime_error(for_path + ": " + loaded.error);
  return *loaded.module;
}

}  // namespace prism
