#include "scene_io/gltf_specular_glossiness.h"

#include <algorithm>
#include <cmath>

#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

constexpr float kDielectricF0 = 0.04f;
constexpr float kEpsilon = 1e-6f;

float unit_number(const tinygltf::Value& v, const std::string& element, const std::string& file) {
  if (!v.IsNumber()) fail(file, element, "expected a number");
  const double x = v.GetNumberAsDouble();
  if (!std::isfinite(x) || x < 0.0 || x > 1.0) {
    fail(file, element, "value " + std::to_string(x) + " is outside [0, 1]");
  }
  return static_cast<float>(x);
}

}  // namespace

tinygltf::TextureInfo texture_info(const tinygltf::Value& ext, const char* key,
                                   const std::string& element, const std::string& file) {
  tinygltf::TextureInfo info;
  if (!ext.Has(key)) return info;
  const tinygltf::Value& t = ext.Get(key);
  const std::string e = element + "." + key;
  if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsInt() ||
      t.Get("index").GetNumberAsInt() < 0) {
    fail(file, e + ".index", "expected a texture index");
  }
  info.index = t.Get("index").GetNumberAsInt();
  if (t.Has("texCoord")) {
    if (!t.Get("texCoord").IsInt() || t.Get("texCoord").GetNumberAsInt() < 0) {
      fail(file, e + ".texCoord", "expected a non-negative integer");
    }
    info.texCoord = t.Get("texCoord").GetNumberAsInt();
  }
  if (t.Has("extensions") && t.Get("extensions").IsObject()) {
    const tinygltf::Value& extensions = t.Get("extensions");
    for (const std::string& name : extensions.Keys()) info.extensions[name] = extensions.Get(name);
  }
  return info;
}

namespace {

// sqrt(0.299 r² + 0.587 g² + 0.114 b²): the brightness weights of Khronos' converter.
float perceived_brightness(const C3f& c) {
  return std::sqrt(0.299f * c.x * c.x + 0.587f * c.y * c.y + 0.114f * c.z * c.z);
}

// The metallic m for which a metallic-roughness material's diffuse part, diffuse·(1 - F0)(1 - m),
// and specular part, F0(1 - m) + specular·m, match the given ones: a quadratic in m.
float solve_metallic(float diffuse, float specular, float one_minus_specular_strength) {
  if (specular < kDielectricF0) return 0.0f;
  const float a = kDielectricF0;
  const float b = diffuse * one_minus_specular_strength / (1.0f - kDielectricF0) + specular -
                  2.0f * kDielectricF0;
  const float c = kDielectricF0 - specular;
  const float discriminant = std::max(b * b - 4.0f * a * c, 0.0f);
  return std::clamp((-b + std::sqrt(discriminant)) / (2.0f * a), 0.0f, 1.0f);
}

}  // namespace

SpecularGlossiness read_specular_glossiness(const tinygltf::Value& ext, const std::string& element,
                                            const std::string& file) {
  SpecularGlossiness s;
  if (ext.Has("diffuseFactor")) {
    const tinygltf::Value& v = ext.Get("diffuseFactor");
    if (!v.IsArray() || v.ArrayLen() != 4)
      fail(file, element + ".diffuseFactor", "expected 4 numbers");
    for (int i = 0; i < 3; ++i)
      s.diffuse[i] = unit_number(v.Get(i), indexed(element + ".diffuseFactor", i), file);
    s.alpha = unit_number(v.Get(3), element + ".diffuseFactor[3]", file);
  }
  if (ext.Has("specularFactor")) {
    const tinygltf::Value& v = ext.Get("specularFactor");
    if (!v.IsArray() || v.ArrayLen() != 3)
      fail(file, element + ".specularFactor", "expected 3 numbers");
    for (int i = 0; i < 3; ++i)
      s.specular[i] = unit_number(v.Get(i), indexed(element + ".specularFactor", i), file);
  }
  if (ext.Has("glossinessFactor")) {
    s.glossiness = unit_number(ext.Get("glossinessFactor"), element + ".glossinessFactor", file);
  }
  s.diffuse_texture = texture_info(ext, "diffuseTexture", element, file);
  s.specular_glossiness_texture = texture_info(ext, "specularGlossinessTexture", element, file);
  return s;
}

MetallicRoughness to_metallic_roughness(const C3f& diffuse, const C3f& specular, float glossiness) {
  const float one_minus_specular_strength = 1.0f - std::max({specular.x, specular.y, specular.z});
  MetallicRoughness out;
  out.metallic = solve_metallic(perceived_brightness(diffuse), perceived_brightness(specular),
                                one_minus_specular_strength);
  const float m = out.metallic;
  const C3f from_diffuse = diffuse * (one_minus_specular_strength / (1.0f - kDielectricF0) /
                                      std::max(1.0f - m, kEpsilon));
  const C3f from_specular = (specular - C3f(kDielectricF0 * (1.0f - m))) / std::max(m, kEpsilon);
  const float t = m * m;
  for (int i = 0; i < 3; ++i) {
    out.base_colour[i] =
        std::clamp(from_diffuse[i] + (from_specular[i] - from_diffuse[i]) * t, 0.0f, 1.0f);
  }
  out.roughness = 1.0f - glossiness;
  return out;
}

}  // namespace prism::gltf_detail
