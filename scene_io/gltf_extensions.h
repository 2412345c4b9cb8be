// The one table of glTF extensions Prism knows: each one's name, whether a file may require
// it, and the handler that reads it. The supported list (extensionsRequired, extensionsUsed) is
// derived from it, and the loader applies material extensions by walking it.
#pragma once

#include <span>
#include <string>

#include <tiny_gltf.h>

#include "renderer/scene_description.h"

namespace prism::gltf_detail {

// What a material extension's handler may ask of the loader.
class MaterialExtensionReader {
 public:
  // A number of the extension object, `fallback` when absent; LoadError when not finite.
  virtual double number(const tinygltf::Value& ext, const char* key, double fallback,
                        const std::string& element) const = 0;
  // `value` in [0, 1] as a float; LoadError otherwise.
  virtual float unit(double value, const std::string& element) const = 0;
  // The texture a textureInfo reads (-1 for none), with its mapping.
  virtual int texture(const tinygltf::TextureInfo& info, TextureEncoding encoding,
                      const std::string& element, TextureMapping* mapping) = 0;
  virtual void warn(const std::string& element, const std::string& what) = 0;
  [[noreturn]] virtual void error(const std::string& element, const std::string& what) const = 0;
  virtual const std::string& file() const = 0;

 protected:
  ~MaterialExtensionReader() = default;
};

using MaterialHandler = void (*)(MaterialExtensionReader& reader, const tinygltf::Value& ext,
                                 const std::string& element, MaterialDescription& material);

struct ExtensionHandler {
  const char* name;
  bool supported;
  // Applied to every material carrying the extension, in table order after the core material;
  // null for extensions on other objects.
  MaterialHandler material;
  // Where the loader reads extensions that are not on materials (for docs and messages).
  const char* read_by;
};

std::span<const ExtensionHandler> extension_handlers();

// The table's entry for `name`, or null.
const ExtensionHandler* find_extension_handler(const std::string& name);

inline bool is_supported_extension(const std::string& name) {
  const ExtensionHandler* h = find_extension_handler(name);
  return h && h->supported;
}

}  // namespace prism::gltf_detail
