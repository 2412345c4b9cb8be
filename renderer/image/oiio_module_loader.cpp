#include <stdexcept>
#include <string>

#include "renderer/image/oiio_module.h"
#include "renderer/loadable_module.h"

namespace prism {

const OiioModule& oiio_module(const std::string& for_path) {
  const ModuleOnce<OiioModule>& loaded = load_module_once<OiioModule>(
      "libprism_oiio.so", "OpenImageIO", kOiioModuleBuild, kOiioModuleEntry, SymbolScope::local);
  if (!loaded.module) throw std::runtime_error(for_path + ": " + loaded.error);
  return *loaded.module;
}

}  // namespace prism
