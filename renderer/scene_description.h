// The scene as the renderer sees it, independent of any file format.
//
// scene_io fills this from glTF; the renderer builds its Embree scene, materials and lights
// from it. Everything is plain data in glTF's conventions (metres, right-handed, +Y up,
// cameras looking down -Z, colours as linear Rec.709 factors) so that a loader for another
// format only has to produce this struct.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Imath/ImathColor.h>
#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>

#include "renderer/enum_names.h"

namespace prism {

using Imath::C3f;
using Imath::M44d;
using Imath::V2f;
using Imath::V3d;
using Imath::V3f;

// How the texel values of an image are encoded. glTF encodes only base colour and emissive
// textures in sRGB; every other slot holds linear data that must not be colour-converted.
enum class TextureEncoding { srgb, linear_data };

enum class TextureWrap { repeat, clamp_to_edge, mirrored_repeat };
inline constexpr EnumName<TextureWrap> kTextureWrapNames[] = {
    {TextureWrap::repeat, "repeat"},
    {TextureWrap::clamp_to_edge, "clamp-to-edge"},
    {TextureWrap::mirrored_repeat, "mirrored-repeat"}};
constexpr std::span<const EnumName<TextureWrap>> enum_names(TextureWrap) {
  return kTextureWrapNames;
}

// glTF's magFilter, and minFilter's filter within one mip level.
enum class TextureFilter { nearest, linear };
// minFilter's choice between mip levels: none (the full image only), the nearest level, or
// a blend of the two nearest (with TextureFilter::linear: trilinear filtering).
enum class MipMode { none, nearest, linear };

// A decoded image, values normalised to [0, 1] as stored in the file (not yet linearised).
struct TextureImage {
  std::string name;
  int width = 0;
  int height = 0;
  int channels = 0;           // 1..4
  std::vector<float> texels;  // width * height * channels, row 0 at the top (glTF's UV origin)
  // Set instead of `texels` by the loader: one decoded image shared by every texture reading it,
  // whatever its sampler or encoding. An 8-bit image keeps its codes (value v stands for
  // v * (1.0f / 255.0f)), a quarter of the floats' size; a 16-bit one arrives as floats.
  std::shared_ptr<const std::vector<float>> shared_texels;
  std::shared_ptr<const std::vector<uint8_t>> shared_codes;
  static float code_value(uint8_t code) { return static_cast<float>(code) * (1.0f / 255.0f); }
  // The number of channel values, and the i-th as a float, whichever storage holds them.
  size_t value_count() const {
    return shared_codes    ? shared_codes->size()
           : shared_texels ? shared_texels->size()
                           : texels.size();
  }
  float value(size_t i) const {
    return shared_codes    ? code_value((*shared_codes)[i])
           : shared_texels ? (*shared_texels)[i]
                           : texels[i];
  }
  TextureEncoding encoding = TextureEncoding::srgb;
  TextureWrap wrap_s = TextureWrap::repeat;
  TextureWrap wrap_t = TextureWrap::repeat;
  // A sampler without filters leaves the choice to the renderer: bilinear and trilinear.
  TextureFilter mag_filter = TextureFilter::linear;
  TextureFilter min_filter = TextureFilter::linear;
  MipMode mip_mode = MipMode::linear;
  int image = -1;  // the glTF image decoded into `texels`; textures of one image share it
};

// How a material slot reads its texture: glTF's textureInfo.texCoord and
// KHR_texture_transform, uv' = T(offset) R(rotation) S(scale) uv.
struct TextureMapping {
  int texcoord = 0;  // TEXCOORD_0 or TEXCOORD_1
  V2f offset{0.0f, 0.0f};
  float rotation = 0.0f;  // radians, as the extension defines it
  V2f scale{1.0f, 1.0f};
};

// glTF's alphaMode. OPAQUE ignores alpha; MASK keeps a surface point where its alpha is at
// least alpha_cutoff and removes it elsewhere; BLEND makes it partly transparent (alpha is
// the fraction of light it stops). renderer/geometry/alpha_filter.h implements both for every ray.
enum class AlphaMode { opaque, mask, blend };

// glTF metallic-roughness material, unmapped. renderer/shading/material.h maps it onto the
// lecture's ambient + Lambert + Phong + mirror + refraction model (see docs/materials.md).
struct MaterialDescription {
  std::string name;
  C3f base_colour{1.0f, 1.0f, 1.0f};
  float alpha = 1.0f;  // baseColorFactor[3]; with the texture's and COLOR_0's alpha
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;     // MASK only
  int base_colour_texture = -1;  // index into SceneDescription::textures, -1 = none
  float metallic = 1.0f;
  float roughness = 1.0f;
  int metallic_roughness_texture = -1;  // G = roughness, B = metallic (linear data)
  C3f emissive{0.0f, 0.0f, 0.0f};
  int emissive_texture = -1;
  // Tangent-space normals (x, y times normal_scale) and ambient occlusion (red), linear data.
  int normal_texture = -1;
  float normal_scale = 1.0f;
  int occlusion_texture = -1;
  float occlusion_strength = 1.0f;
  // The texture coordinates each slot reads: texCoord and KHR_texture_transform.
  TextureMapping base_colour_mapping, metallic_roughness_mapping, emissive_mapping;
  TextureMapping normal_mapping, occlusion_mapping;
  float transmission = 0.0f;  // KHR_materials_transmission
  float ior = 1.5f;           // KHR_materials_ior
  // KHR_materials_volume: 0 thickness is thin-walled (no volume); light inside is absorbed
  // as attenuation_colour^(distance / attenuation_distance).
  float thickness = 0.0f;
  float attenuation_distance = std::numeric_limits<float>::infinity();
  C3f attenuation_colour{1.0f, 1.0f, 1.0f};
  float specular = 1.0f;                  // KHR_materials_specular: specularFactor
  C3f specular_colour{1.0f, 1.0f, 1.0f};  // KHR_materials_specular: specularColorFactor
  // KHR_materials_clearcoat: weight (x texture R), roughness (x texture G) and the coat's own
  // normal map (x, y times clearcoat_normal_scale); the textures linear data.
  float clearcoat = 0.0f;
  float clearcoat_roughness = 0.0f;
  int clearcoat_texture = -1, clearcoat_roughness_texture = -1, clearcoat_normal_texture = -1;
  float clearcoat_normal_scale = 1.0f;
  TextureMapping clearcoat_mapping, clearcoat_roughness_mapping, clearcoat_normal_mapping;
  // KHR_materials_sheen: colour (x texture RGB, sRGB) and roughness (x texture A, linear).
  C3f sheen_colour{0.0f, 0.0f, 0.0f};
  float sheen_roughness = 0.0f;
  int sheen_colour_texture = -1, sheen_roughness_texture = -1;
  TextureMapping sheen_colour_mapping, sheen_roughness_mapping;
  // false (glTF's default): camera rays do not see the back face (docs/materials.md).
  bool double_sided = false;
  // KHR_materials_unlit: the surface shows its base colour as emitted radiance and scatters
  // nothing.
  bool unlit = false;
};

// One triangle list with one material. Strips and fans are already converted to lists, and
// winding is counter-clockwise for the front face in object space.
struct Primitive {
  std::vector<V3f> positions;
  std::vector<V3f> normals;  // per vertex, or empty: the geometric (flat) normal is used
  std::vector<V2f> uv0;      // per vertex, or empty
  std::vector<V2f> uv1;      // TEXCOORD_1, per vertex, or empty
  // Per vertex, or empty: COLOR_0 as linear Rec.709 RGBA (VEC3: alpha 1), and TANGENT (xyz
  // unit, w = +-1 the bitangent's sign), which the loader generates for normal-mapped
  // primitives that lack it.
  std::vector<Imath::V4f> colours;
  std::vector<Imath::V4f> tangents;
  std::vector<uint32_t> indices;  // 3 per triangle, every index < positions.size()
  int material = -1;              // -1 = the default material
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
};

// A node that places a mesh in the world. A mesh placed by several nodes becomes one Embree
// instance per node; a mesh placed once is baked into world space.
struct MeshInstance {
  int mesh = -1;
  M44d object_to_world;  // Imath convention: row vectors, p_world = p_object * object_to_world
  std::string node_name;
};

// An analytic sphere (the PRISM_sphere node extension, docs/spheres.md), in world space.
struct Sphere {
  V3d centre{0.0, 0.0, 0.0};
  double radius = 1.0;
  int material = -1;
  std::string node_name;
};

enum class LightType { directional, point, spot };
inline constexpr EnumName<LightType> kLightTypeNames[] = {{LightType::directional, "directional"},
                                                          {LightType::point, "point"},
                                                          {LightType::spot, "spot"}};
constexpr std::span<const EnumName<LightType>> enum_names(LightType) {
  return kLightTypeNames;
}

// KHR_lights_punctual in glTF units: point and spot intensity in candela (W/sr for us),
// directional in lux (W/m^2). Position and direction are in world space.
struct Light {
  std::string name;
  LightType type = LightType::point;
  C3f colour{1.0f, 1.0f, 1.0f};
  float intensity = 1.0f;
  V3d position{0.0, 0.0, 0.0};
  V3d direction{0.0, 0.0, -1.0};  // the direction the light travels (node's -Z)
  double range = 0.0;             // 0 = infinite
  double inner_cone_angle = 0.0;
  double outer_cone_angle = 0.7853981633974483;  // pi / 4, glTF's default
};

enum class Projection { perspective, orthographic };

struct CameraDescription {
  std::string name;
  Projection projection = Projection::perspective;
  M44d camera_to_world;           // the camera looks down its local -Z with +Y up
  double yfov = 0.8;              // radians, perspective
  double aspect_ratio = 0.0;      // 0 = take it from the image resolution
  double xmag = 1.0, ymag = 1.0;  // half extents, orthographic
  double znear = 1e-3;
};

// Light from beyond the scene for a file that brings no light of its own
// (scene_passes/scene_defaults.h): a grey sky whose radiance runs linearly in the height of
// the direction (its +Y component), from `nadir` straight down to `zenith` straight up.
struct SkyDescription {
  float zenith = 0.0f;
  float nadir = 0.0f;
};

struct SceneDescription {
  std::string source_path;
  // Every file the scene was read from: source_path first, then its buffers and images. What
  // a cache must hash to know whether a render of the scene is still up to date.
  std::vector<std::string> source_files;
  std::vector<Mesh> meshes;
  std::vector<MeshInstance> instances;
  std::vector<Sphere> spheres;
  std::vector<MaterialDescription> materials;
  std::vector<TextureImage> textures;
  std::vector<Light> lights;
  std::vector<CameraDescription> cameras;
  // Set by scene_passes/scene_defaults.h for a file without lights or emissive surfaces:
  // lights[0] is then the default key light, placed for the camera a render uses, and
  // default_sky lights a render whose job names no environment (never seen by the camera).
  bool default_lighting = false;
  std::optional<SkyDescription> default_sky;
  std::vector<std::string> warnings;  // for the user: skipped primitives, defaults added, ...
};

// Bytes the description's arrays hold (geometry, texels; not the small per-object fields).
uint64_t description_bytes(const SceneDescription& scene);

}  // namespace prism
