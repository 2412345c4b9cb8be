// KHR_draco_mesh_compression's decoder, Debian's libdraco, behind a module of its own
// (libprism_draco.so, from draco/draco_module.cpp) opened by the first Draco-compressed
// primitive: linking libdraco into prism would cost every command its start-up (about 1 ms
// of loading and relocating a 3 MiB library), and most scenes are not compressed.
//
// The interface is the decoded mesh and nothing more; every check against the glTF file
// (counts, component counts, types) stays in gltf_draco.cpp, which knows the elements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace prism::gltf_detail {

// glTF's accessor component types that Draco can convert an attribute to.
enum class DracoComponent { int8, uint8, int16, uint16, uint32, float32 };

class DracoMesh {
 public:
  virtual ~DracoMesh() = default;
  virtual uint32_t faces() const = 0;
  virtual uint32_t points() const = 0;
  // The three point indices of every face, 3 × faces() values.
  virtual void indices(uint32_t* out) const = 0;
  // The component count of the attribute with this unique id, or -1 when there is none.
  virtual int attribute_components(uint32_t id) const = 0;
  // Every point's value of attribute `id`, converted to `type`, `components` per point, into
  // `out` (points() × components values); false when Draco cannot convert a value.
  virtual bool attribute_values(uint32_t id, DracoComponent type, int components,
                                unsigned char* out) const = 0;
};

class DracoModule {
 public:
  virtual ~DracoModule() = default;
  // The mesh in `size` bytes of a Draco stream, or null with `error` set to Draco's reason.
  virtual std::unique_ptr<DracoMesh> decode(const unsigned char* bytes, std::size_t size,
                                            std::string& error) const = 0;
};

// The module, loaded on the first call; null with `error` set ("needs Draco, whose module
// <path> cannot be loaded: ...") when it cannot be.
const DracoModule* draco_module(std::string& error);

// What the module exports, in C so that dlsym finds it by name: a function returning the
// module's one DracoModule, and one returning its build (renderer/loadable_module.h).
inline constexpr const char* kDracoModuleEntry = "prism_draco_module";
inline constexpr const char* kDracoModuleBuild = "prism_draco_module_build";

}  // namespace prism::gltf_detail
