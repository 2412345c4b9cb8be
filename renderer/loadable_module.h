// Prism's own shared-library modules (OpenImageIO's, Draco's, MPI's), opened the first time a
// command needs them so that every other command starts without their dependencies.
//
// A module lives in ../lib/prism beside the executable (the build tree and `cmake --install`)
// or beside the binary itself (the Python package), and must come from the same build: it
// exports `build_symbol`, a function returning "<version> <commit>", and a module from
// another build is refused rather than called through a mismatched interface.
#pragma once

#include <string>

namespace prism {

enum class SymbolScope {
  // The module's dependencies stay out of the global namespace, so nothing else in the
  // process binds to them by accident.
  local,
  // For libraries whose own plugins look their symbols up globally (OpenMPI's components).
  global,
};

struct LoadedModule {
  void* entry = nullptr;  // the address of the entry symbol, or null with `error` set
  std::string error;      // "needs <what>, whose module <path> cannot be loaded: ...", ...
};

// Opens `file_name` (e.g. "libprism_oiio.so"), checks its build and returns the address of
// `entry_symbol`. `what` names the library for messages ("OpenImageIO"). The handle stays
// open for the life of the process: the module's objects live as long.
LoadedModule load_module(const char* file_name, const char* what, const char* build_symbol,
                         const char* entry_symbol, SymbolScope scope);

template <typename Module>
struct ModuleOnce {
  const Module* module = nullptr;  // what the entry symbol returned, or null with `error` set
  std::string error;
};

// load_module the first time any thread asks for `Module`, then the same answer every time:
// a module that failed to load is not retried (the reason would not change). The entry
// symbol is a function returning the module's one `const Module*`.
template <typename Module>
const ModuleOnce<Module>& load_module_once(const char* file_name, const char* what,
                                           const char* build_symbol, const char* entry_symbol,
                                           SymbolScope scope) {
  static const ModuleOnce<Module> once = [&] {
    const LoadedModule loaded = load_module(file_name, what, build_symbol, entry_symbol, scope);
    using Entry = const Module* (*)();
    if (!loaded.entry) return ModuleOnce<Module>{nullptr, loaded.error};
    return ModuleOnce<Module>{reinterpret_cast<Entry>(loaded.entry)(), {}};
  }();
  return once;
}

}  // namespace prism
