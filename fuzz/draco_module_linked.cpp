// The fuzzers link the Draco module's code in (compiled from scene_io/draco/ with the same
// sanitizers) instead of opening libprism_draco.so, so that a fuzzed Draco stream runs through
// instrumented code and the fuzzer needs no module beside it.
#include "scene_io/draco_module.h"

extern "C" const prism::gltf_detail::DracoModule* prism_draco_module();

namespace prism::gltf_detail {

const DracoModule* draco_module(std::string&) {
  return prism_draco_module();
}

}  // namespace prism::gltf_detail
