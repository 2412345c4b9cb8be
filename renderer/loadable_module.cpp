#include "renderer/loadable_module.h"

#include <dlfcn.h>

#include <filesystem>
#include <system_error>

#include "renderer/version.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

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

fs::path module_path(const char* file_name) {
  const fs::path folder = binary_folder();
  const fs::path beside = folder / file_name;
  std::error_code ec;
  if (fs::exists(beside, ec)) return beside;
  return folder.parent_path() / "lib" / "prism" / file_name;
}

std::string this_build() {
  return std::string(kVersion) + " " + kBuildCommit;
}

}  // namespace

LoadedModule load_module(const char* file_name, const char* what, const char* build_symbol,
                         const char* entry_symbol, SymbolScope scope) {
  const fs::path path = module_path(file_name);
  const int flags = RTLD_NOW | (scope == SymbolScope::global ? RTLD_GLOBAL : RTLD_LOCAL);
  void* handle = ::dlopen(path.c_str(), flags);
  if (!handle) {
    const char* error = ::dlerror();
    std::string why = error ? error : "unknown error";
    // glibc names the file first ("PATH: cannot open shared object file: ..."), and the
    // message names it already.
    const std::string named = path.string() + ": ";
    if (why.compare(0, named.size(), named) == 0) why.erase(0, named.size());
    return {nullptr, std::string("needs ") + what + ", whose module " + path.string() +
                         " cannot be loaded: " + why};
  }
  using BuildFunction = const char* (*)();
  const auto build = reinterpret_cast<BuildFunction>(::dlsym(handle, build_symbol));
  void* entry = ::dlsym(handle, entry_symbol);
  // Every reason reads after the file or command that needed the module ("X: needs ...").
  const std::string module = std::string("needs ") + what + ", whose module " + path.string();
  if (!build || !entry) return {nullptr, module + " is not Prism's"};
  if (this_build() != build())
    return {nullptr,
            module + " is from another build (" + build() + ", this is " + this_build() + ")"};
  return {entry, {}};
}

}  // namespace prism
