// What a scene uses, derived once from its SceneDescription and the sphere mode, so that the
// renderer can skip work a scene does not need (issue 5: no shadow rays where nothing can
// occlude, no secondary rays without specular or transmissive materials, no texture lookups
// without textures, no user-geometry callbacks without analytic spheres).
//
// Every flag is conservative: "false" is a promise (skipping that work cannot change the
// image), "true" only means the work may matter. docs/info.md states each rule.
//
// Only what the scene's geometry references counts: a material no primitive or sphere uses
// cannot make the scene a mirror scene, and a texture no used material samples is not
// looked up.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "renderer/geometry/sphere_geometry.h"
#include "renderer/scene_description.h"

namespace prism {

// The kinds of geometry handed to Embree. Bit flags: a scene holds any combination.
enum class GeometryKind : uint8_t {
  none = 0,
  triangles = 1 << 0,         // glTF mesh triangles
  analytic_spheres = 1 << 1,  // spheres as user geometry (intersection callbacks)
  point_spheres = 1 << 2,     // spheres as Embree's built-in sphere points
  sphere_meshes = 1 << 3,     // spheres as icospheres (triangles in Embree too)
};

// Which material slots sample a texture. Bit flags.
enum class TexturedSlots : uint8_t {
  none = 0,
  base_colour = 1 << 0,
  metallic_roughness = 1 << 1,
  emissive = 1 << 2,
};

constexpr GeometryKind operator|(GeometryKind a, GeometryKind b) {
  return static_cast<GeometryKind>(static_cast<uint8_t>(a) | static_cast<uint8_t>(b));
}
constexpr bool has(GeometryKind set, GeometryKind kind) {
  return (static_cast<uint8_t>(set) & static_cast<uint8_t>(kind)) != 0;
}
constexpr TexturedSlots operator|(TexturedSlots a, TexturedSlots b) {
  return static_cast<TexturedSlots>(static_cast<uint8_t>(a) | static_cast<uint8_t>(b));
}
constexpr bool has(TexturedSlots set, TexturedSlots slot) {
  return (static_cast<uint8_t>(set) & static_cast<uint8_t>(slot)) != 0;
}

// What the lights need from the integrators: directional lights alone need no distance or
// falloff, and their shadow rays are unbounded.
enum class LightKinds : uint8_t {
  none,              // nothing but ambient and emission light the scene
  directional_only,  // every light is directional
  positional,        // at least one point or spot light
};

struct SceneFeatures {
  GeometryKind geometry = GeometryKind::none;
  LightKinds lights = LightKinds::none;
  TexturedSlots textures = TexturedSlots::none;
  // Some used material has roughness <= kMirrorRoughness somewhere (factor times the
  // metallic-roughness texture's smallest green value), or a clearcoat that smooth (any
  // with a clearcoat roughness texture): whitted traces mirror rays.
  bool mirror = false;
  // Some used material refracts: transmission > 0 and not wholly metallic.
  bool transmission = false;
  // Some used material has a non-zero emissive factor, or is unlit (KHR_materials_unlit).
  bool emission = false;
  // Some mesh primitive's material has alphaMode MASK, or BLEND: its triangles carry alpha
  // filters, for every kind of ray (renderer/geometry/alpha_filter.h). Spheres ignore alpha.
  bool alpha_mask = false;
  bool alpha_blend = false;
  // A shadow ray can be blocked somewhere (rule in scene_features.cpp and docs/info.md).
  bool shadows = false;

  // Counts behind the flags, for printing.
  size_t triangles = 0;  // mesh triangles as placed (each instance counted), spheres excluded
  size_t spheres = 0;
  size_t objects = 0;  // mesh instances with triangles, plus spheres
  size_t directional_lights = 0;
  size_t point_lights = 0;
  size_t spot_lights = 0;

  bool operator==(const SceneFeatures&) const = default;
};

// Derives the feature set of `scene` rendered with spheres in `spheres.mode`. Call it after
// add_scene_defaults when the default light should count (as the renderer sees the scene).
SceneFeatures derive_scene_features(const SceneDescription& scene, const SphereOptions& spheres);

// "triangles+analytic-spheres", "none", ...
std::string to_string(GeometryKind geometry);
// "none", "directional-only", "positional".
std::string to_string(LightKinds lights);
// "base-colour+emissive", "none", ...
std::string to_string(TexturedSlots textures);

// One line for the user: "geometry=triangles+analytic-spheres lights=positional
// textures=base-colour mirror=yes transmission=yes emission=no alpha=none shadows=yes"
// (alpha: none, mask, blend or mask+blend).
std::string to_string(const SceneFeatures& features);

// The same as EXR metadata pairs (prism:<key> once written): "features" holding the line
// above, and one key per flag ("featureGeometry", "featureShadows", ..., "featureAlpha").
std::vector<std::pair<std::string, std::string>> feature_metadata(const SceneFeatures& features);

}  // namespace prism
