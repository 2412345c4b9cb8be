#include <mutex>
#include <stdexcept>
#include <string>

#include "renderer/image/oiio_module.h"
#include "renderer/loadable_module.h"

namespace prism {

const OiioModule& oiio_module(const std::string& for_path) {
  static std::once_flag once;
  static const OiioModule* module = nullptr;
  static std::string error;
  std::call_once(once, [] {
    const LoadedModule loaded = load_module("libprism_oiio.so", "OpenImageIO", kOiioModuleBuild,
                                            kOiioModuleEntry, SymbolScope::local);
    if (loaded.entry)
      module = reinterpret_cast<OiioModuleEntry>(loaded.entry)();
    else
      error = loaded.error;
  });
  if (!module) throw std::runtime_error(for_path + ": " + error);
  return *module;
}

}  // namespace prism
