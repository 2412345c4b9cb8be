#include "renderer/loadable_module.h"
#include "scene_io/draco_module.h"

namespace prism::gltf_detail {

const DracoModule* draco_module(std::string& error) {
  const ModuleOnce<DracoModule>& loaded = load_module_once<DracoModule>(
      "libprism_draco.so", "Draco", kDracoModuleBuild, kDracoModuleEntry, SymbolScope::local);
  if (!loaded.module) error = loaded.error;
  return loaded.module;
}

}  // namespace prism::gltf_detail
