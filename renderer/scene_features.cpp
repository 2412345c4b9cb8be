#include "renderer/scene_features.h"

#include <algorithm>
#include <cmath>

#include <Imath/ImathBox.h>

#include "renderer/material.h"

namespace prism {
namespace {

// Relative tolerance of the planarity test: float positions placed by a double transform
// stay far inside it, while a mesh bent by more would be bent by more than the integrators'
// shadow-ray offset, so it is not called flat.
constexpr double kPlanarTolerance = 1e-6;

const TextureImage* texture_at(const SceneDescription& scene, int index) {
  return index >= 0 && static_cast<size_t>(index) < scene.textures.size()
             ? &scene.textures[static_cast<size_t>(index)]
             : nullptr;
}

// The smallest roughness a material reaches anywhere. Bilinear filtering only blends texels,
// so the smallest green texel bounds every sample from below.
float smallest_roughness(const SceneDescription& scene, const MaterialDescription& m) {
  const float factor = std::clamp(m.roughness, 0.0f, 1.0f);
  const TextureImage* t = texture_at(scene, m.metallic_roughness_texture);
  if (!t) return factor;
  // An sRGB-encoded roughness map would be converted to the working space, which may mix
  // channels; rather than model that, assume it can reach 0.
  if (t->encoding == TextureEncoding::srgb || t->channels < 1) return 0.0f;
  const size_t count = static_cast<size_t>(t->width) * static_cast<size_t>(t->height);
  const size_t c = static_cast<size_t>(t->channels);
  if (t->texels.size() < count * c || count == 0) return 0.0f;
  // Texture broadcasts grey images, so green is channel 0 below three channels.
  const size_t green = c >= 3 ? 1 : 0;
  float lowest = 1.0f;
  for (size_t i = 0; i < count; ++i) lowest = std::min(lowest, t->texels[i * c + green]);
  return factor * std::max(lowest, 0.0f);
}

void add_material(const SceneDescription& scene, int index, SceneFeatures* f) {
  // -1 and anything out of range is glTF's default material, which RenderScene uses too:
  // white, metallic 1, roughness 1, untextured, opaque, not emissive.
  if (index < 0 || static_cast<size_t>(index) >= scene.materials.size()) return;
  const MaterialDescription& m = scene.materials[static_cast<size_t>(index)];
  const bool mr_texture = texture_at(scene, m.metallic_roughness_texture) != nullptr;
  if (texture_at(scene, m.base_colour_texture))
    f->textures = f->textures | TextureSlot::base_colour;
  if (mr_texture) f->textures = f->textures | TextureSlot::metallic_roughness;
  if (texture_at(scene, m.emissive_texture)) f->textures = f->textures | TextureSlot::emissive;
  if (smallest_roughness(scene, m) <= kMirrorRoughness) f->mirror = true;
  // The texture's blue channel scales metallic down, so with one the surface may be partly
  // dielectric and refract even when the factor says metal.
  if (std::clamp(m.transmission, 0.0f, 1.0f) > 0.0f && (m.metallic < 1.0f || mr_texture))
    f->transmission = true;
  // The emissive texture only scales the factor, so a zero factor never emits.
  if (m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f) f->emission = true;
}

size_t triangle_count(const Mesh& mesh) {
  size_t n = 0;
  for (const Primitive& p : mesh.primitives) n += p.indices.size() / 3;
  return n;
}

// True when the placed mesh lies in one plane that no point or spot light lies in and no
// directional light travels along: then a shadow ray leaving one of its points meets the
// plane only where it starts, whatever the shading normals say.
bool flat_and_lit_off_plane(const SceneDescription& scene, const MeshInstance& instance) {
  const Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
  std::vector<V3d> points;
  for (const Primitive& p : mesh.primitives)
    for (uint32_t i : p.indices) {
      V3d world;
      instance.object_to_world.multVecMatrix(V3d(p.positions[i]), world);
      points.push_back(world);
    }
  Imath::Box3d box;
  for (const V3d& p : points) box.extendBy(p);
  const double extent = box.isEmpty() ? 0.0 : (box.max - box.min).length();
  if (!(extent > 0.0) || !std::isfinite(extent)) return false;
  const double tolerance = kPlanarTolerance * extent;
  // The plane of the largest triangle, whose normal is the most accurate.
  V3d normal(0.0), origin(0.0);
  double largest = 0.0;
  for (size_t i = 0; i + 2 < points.size(); i += 3) {
    const V3d n = (points[i + 1] - points[i]).cross(points[i + 2] - points[i]);
    if (n.length() > largest) {
      largest = n.length();
      normal = n;
      origin = points[i];
    }
  }
  if (!(largest > tolerance * tolerance)) return false;
  normal /= largest;
  for (const V3d& p : points)
    if (std::abs((p - origin).dot(normal)) > tolerance) return false;
  for (const Light& light : scene.lights) {
    if (light.type == LightType::directional) {
      const double length = light.direction.length();
      if (!(length > 0.0) || std::abs(light.direction.dot(normal)) <= kPlanarTolerance * length)
        return false;
    } else if (std::abs((light.position - origin).dot(normal)) <= tolerance) {
      return false;
    }
  }
  return true;
}

// The shadow rule. A shadow ray is only ever blocked by geometry between a lit point and a
// light, so:
//   - no light, or no geometry: nothing to block;
//   - two or more objects (mesh instances with triangles, spheres): one may block another;
//   - one sphere rendered exactly (analytic or Embree points): a convex surface with its
//     true normal, so a point facing a light sees it (from outside, the whole sphere lies
//     behind the tangent plane; from inside, the segment stays inside) and a point facing
//     away is dark before any shadow ray;
//   - one sphere as an icosphere: its interpolated normals face some lights its flat faces
//     do not, so near the terminator its own faces block shadow rays;
//   - one flat mesh (all triangles in one plane) with no light in that plane: cannot block
//     itself (flat_and_lit_off_plane);
//   - one mesh of any other shape: may shadow itself. Convex closed meshes are not
//     recognised, as interpolated normals would make them shadow themselves too.
// Whether the shadow falls where the camera looks is not considered: always conservative.
bool can_shadow(const SceneDescription& scene, const SphereOptions& spheres,
                const SceneFeatures& f) {
  if (f.lights == LightKinds::none || f.objects == 0) return false;
  if (f.objects >= 2) return true;
  if (f.spheres == 1) return spheres.mode == SphereMode::mesh;
  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= scene.meshes.size()) continue;
    if (triangle_count(scene.meshes[static_cast<size_t>(instance.mesh)]) == 0) continue;
    return !flat_and_lit_off_plane(scene, instance);
  }
  return true;
}

std::string yes_no(bool b) {
  return b ? "yes" : "no";
}

}  // namespace

SceneFeatures derive_scene_features(const SceneDescription& scene, const SphereOptions& spheres) {
  SceneFeatures f;
  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
    const size_t triangles = triangle_count(mesh);
    if (triangles == 0) continue;
    f.triangles += triangles;
    ++f.objects;
    for (const Primitive& p : mesh.primitives)
      if (p.indices.size() >= 3) add_material(scene, p.material, &f);
  }
  if (f.triangles > 0) f.geometry = f.geometry | GeometryKind::triangles;
  f.spheres = scene.spheres.size();
  f.objects += f.spheres;
  if (f.spheres > 0) {
    switch (spheres.mode) {
      case SphereMode::analytic:
        f.geometry = f.geometry | GeometryKind::analytic_spheres;
        break;
      case SphereMode::embree_points:
        f.geometry = f.geometry | GeometryKind::point_spheres;
        break;
      case SphereMode::mesh:
        f.geometry = f.geometry | GeometryKind::sphere_meshes;
        break;
    }
  }
  for (const Sphere& s : scene.spheres) add_material(scene, s.material, &f);

  for (const Light& light : scene.lights) {
    switch (light.type) {
      case LightType::directional:
        ++f.directional_lights;
        break;
      case LightType::point:
        ++f.point_lights;
        break;
      case LightType::spot:
        ++f.spot_lights;
        break;
    }
  }
  f.lights = f.point_lights + f.spot_lights > 0 ? LightKinds::positional
             : f.directional_lights > 0         ? LightKinds::directional_only
                                                : LightKinds::none;
  f.shadows = can_shadow(scene, spheres, f);
  return f;
}

std::string to_string(GeometryKind geometry) {
  std::string s;
  const auto add = [&](GeometryKind kind, const char* name) {
    if (has(geometry, kind)) s += (s.empty() ? "" : "+") + std::string(name);
  };
  add(GeometryKind::triangles, "triangles");
  add(GeometryKind::analytic_spheres, "analytic-spheres");
  add(GeometryKind::point_spheres, "point-spheres");
  add(GeometryKind::sphere_meshes, "sphere-meshes");
  return s.empty() ? "none" : s;
}

std::string to_string(LightKinds lights) {
  switch (lights) {
    case LightKinds::none:
      return "none";
    case LightKinds::directional_only:
      return "directional-only";
    case LightKinds::positional:
      return "positional";
  }
  return "none";
}

std::string to_string(TextureSlot textures) {
  std::string s;
  const auto add = [&](TextureSlot slot, const char* name) {
    if (has(textures, slot)) s += (s.empty() ? "" : "+") + std::string(name);
  };
  add(TextureSlot::base_colour, "base-colour");
  add(TextureSlot::metallic_roughness, "metallic-roughness");
  add(TextureSlot::emissive, "emissive");
  return s.empty() ? "none" : s;
}

std::string to_string(const SceneFeatures& f) {
  return "geometry=" + to_string(f.geometry) + " lights=" + to_string(f.lights) +
         " textures=" + to_string(f.textures) + " mirror=" + yes_no(f.mirror) +
         " transmission=" + yes_no(f.transmission) + " emission=" + yes_no(f.emission) +
         " shadows=" + yes_no(f.shadows);
}

std::vector<std::pair<std::string, std::string>> feature_metadata(const SceneFeatures& f) {
  return {{"features", to_string(f)},
          {"featureGeometry", to_string(f.geometry)},
          {"featureLights", to_string(f.lights)},
          {"featureTextures", to_string(f.textures)},
          {"featureMirror", yes_no(f.mirror)},
          {"featureTransmission", yes_no(f.transmission)},
          {"featureEmission", yes_no(f.emission)},
          {"featureShadows", yes_no(f.shadows)}};
}

}  // namespace prism
