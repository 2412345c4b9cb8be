#include "scene_io/gltf_clearcoat_sheen.h"

#include <cmath>
#include <limits>

#include "scene_io/gltf_specular_glossiness.h"

namespace prism::gltf_detail {

namespace {

int slot(MaterialExtensionReader& r, const tinygltf::Value& ext, const char* key,
         TextureEncoding encoding, const std::string& e, TextureMapping* mapping) {
  return r.texture(texture_info(ext, key, e, r.file()), encoding, e + "." + key, mapping);
}

}  // namespace

void read_clearcoat(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                    MaterialDescription& d) {
  d.clearcoat = r.unit(r.number(ext, "clearcoatFactor", 0.0, e), e + ".clearcoatFactor");
  d.clearcoat_roughness =
      r.unit(r.number(ext, "clearcoatRoughnessFactor", 0.0, e), e + ".clearcoatRoughnessFactor");
  d.clearcoat_texture =
      slot(r, ext, "clearcoatTexture", TextureEncoding::linear_data, e, &d.clearcoat_mapping);
  d.clearcoat_roughness_texture =
      slot(r, ext, "clearcoatRoughnessTexture", TextureEncoding::linear_data, e,
           &d.clearcoat_roughness_mapping);
  if (ext.Has("clearcoatNormalTexture")) {
    const std::string n = e + ".clearcoatNormalTexture";
    const double scale = r.number(ext.Get("clearcoatNormalTexture"), "scale", 1.0, n);
    // Multiplied into float normals: finite as a double is not enough.
    if (!(std::fabs(scale) <= double(std::numeric_limits<float>::max())))
      r.error(n + ".scale", "not finite as a float");
    d.clearcoat_normal_scale = static_cast<float>(scale);
  }
  d.clearcoat_normal_texture = slot(r, ext, "clearcoatNormalTexture", TextureEncoding::linear_data,
                                    e, &d.clearcoat_normal_mapping);
}

void read_sheen(MaterialExtensionReader& r, const tinygltf::Value& ext, const std::string& e,
                MaterialDescription& d) {
  if (ext.Has("sheenColorFactor")) {
    const tinygltf::Value& v = ext.Get("sheenColorFactor");
    const std::string element = e + ".sheenColorFactor";
    if (!v.IsArray() || v.ArrayLen() != 3) r.error(element, "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const tinygltf::Value& c = v.Get(i);
      const std::string ci = element + "[" + std::to_string(i) + "]";
      if (!c.IsNumber()) r.error(ci, "expected a number");
      d.sheen_colour[i] = r.unit(c.GetNumberAsDouble(), ci);
    }
  }
  d.sheen_roughness =
      r.unit(r.number(ext, "sheenRoughnessFactor", 0.0, e), e + ".sheenRoughnessFactor");
  d.sheen_colour_texture =
      slot(r, ext, "sheenColorTexture", TextureEncoding::srgb, e, &d.sheen_colour_mapping);
  d.sheen_roughness_texture = slot(r, ext, "sheenRoughnessTexture", TextureEncoding::linear_data, e,
                                   &d.sheen_roughness_mapping);
}

}  // namespace prism::gltf_detail
