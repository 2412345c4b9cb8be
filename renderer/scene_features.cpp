#include "renderer/scene_features.h"

#include <algorithm>
#include <cmath>

#include <Imath/ImathBox.h>

#include "renderer/camera.h"
#include "renderer/shading/material.h"

namespace prism {
namespace {

// Relative tolerance of the planarity test: float positions placed by a double transform
// stay far inside it, while a mesh bent by more would be bent by more than the integrators'
// shadow-ray offset, so it is not called flat.
constexpr double kPlanarTolerance = 1e-6;
// A flat mesh with vertex normals: how far (sine of the angle) those normals may lean off the
// plane, and how far every light must stay off it as seen from each vertex. The normals
// then bend the shading normal, and move the shadow ray's start (Hanika's offset), by far
// less than the light's angle to the plane, so the ray still leaves on the light's side.
constexpr double kNormalLean = 1e-6;
constexpr double kLightClearance = 1e-4;

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
  if (t->value_count() < count * c || count == 0) return 0.0f;
  // Texture broadcasts grey images, so green is channel 0 below three channels.
  const size_t green = c >= 3 ? 1 : 0;
  float lowest = 1.0f;
  for (size_t i = 0; i < count; ++i) lowest = std::min(lowest, t->value(i * c + green));
  return factor * std::max(lowest, 0.0f);
}

const MaterialDescription* material_at(const SceneDescription& scene, int index) {
  // -1 and anything out of range is glTF's default material, which RenderScene uses too:
  // white, metallic 1, roughness 1, untextured, opaque, not emissive.
  return index >= 0 && static_cast<size_t>(index) < scene.materials.size()
             ? &scene.materials[static_cast<size_t>(index)]
             : nullptr;
}

// The texture's blue channel scales metallic down, so with one the surface may be partly
// dielectric and refract even when the factor says metal.
bool refracts(const SceneDescription& scene, const MaterialDescription& m) {
  return std::clamp(m.transmission, 0.0f, 1.0f) > 0.0f &&
         (m.metallic < 1.0f || texture_at(scene, m.metallic_roughness_texture) != nullptr);
}

// A normal map bends the shading normal away from the geometric one, so a point can face a
// light the surface itself hides.
bool normal_mapped(const SceneDescription& scene, int material) {
  const MaterialDescription* m = material_at(scene, material);
  return m && texture_at(scene, m->normal_texture) != nullptr;
}

void add_material(const SceneDescription& scene, int index, SceneFeatures* f) {
  const MaterialDescription* found = material_at(scene, index);
  if (!found) return;
  const MaterialDescription& m = *found;
  const bool mr_texture = texture_at(scene, m.metallic_roughness_texture) != nullptr;
  if (texture_at(scene, m.base_colour_texture))
    f->textures = f->textures | TexturedSlots::base_colour;
  if (mr_texture) f->textures = f->textures | TexturedSlots::metallic_roughness;
  if (texture_at(scene, m.emissive_texture)) f->textures = f->textures | TexturedSlots::emissive;
  if (smallest_roughness(scene, m) <= kMirrorRoughness) f->mirror = true;
  // A smooth clearcoat is a mirror for whitted too; its roughness texture may reach 0.
  if (m.clearcoat > 0.0f && (texture_at(scene, m.clearcoat_roughness_texture) ||
                             m.clearcoat_roughness <= kMirrorRoughness))
    f->mirror = true;
  if (refracts(scene, m)) f->transmission = true;
  // The emissive texture only scales the factor, so a zero factor never emits.
  if (m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f) f->emission = true;
  if (m.unlit) f->emission = true;  // its base colour is its emission
}

size_t triangle_count(const Mesh& mesh) {
  size_t n = 0;
  for (const Primitive& p : mesh.primitives) n += p.indices.size() / 3;
  return n;
}

// The object-space vertex normal shared by every vertex that has one, in `*normal` (zero when
// no primitive has normals): false when two differ, so that the normals bend the shading.
bool one_vertex_normal(const Mesh& mesh, V3f* normal) {
  *normal = V3f(0.0f);
  for (const Primitive& p : mesh.primitives) {
    // Normals not one per vertex are dropped: the primitive is shaded flat (mesh_preparation.h).
    if (p.normals.size() != p.positions.size()) continue;
    for (const V3f& n : p.normals) {
      // A zero or non-finite normal is rebuilt from the faces around it.
      if (!(n.length2() > 0.0f) || !std::isfinite(n.length2())) return false;
      if (*normal == V3f(0.0f))
        *normal = n;
      else if (n != *normal)
        return false;
    }
  }
  return true;
}

// True when the placed mesh lies in one plane that no point or spot light lies in and no
// directional light travels along: then a shadow ray leaving one of its points meets the
// plane only where it starts. Without vertex normals the shading normal is the plane's, so
// the ray leaves on the light's side exactly. With them, they must all be the same normal
// leaning by at most kNormalLean off the plane's, and every light must be kLightClearance
// off the plane as seen from every vertex (so from every point, as the plane's points lie in
// their convex hull): otherwise a shading normal bent towards a light behind the plane, or
// the shadow ray's start moved by Hanika's offset, lets the ray cross the plane.
bool flat_and_lit_off_plane(const SceneDescription& scene, const MeshInstance& instance) {
  const Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
  V3f vertex_normal;
  if (!one_vertex_normal(mesh, &vertex_normal)) return false;
  for (const Primitive& p : mesh.primitives)
    if (normal_mapped(scene, p.material)) return false;
  // Every index's placed point, visited in order and never stored: at 24 bytes each, a
  // copy of a mesh of 10^8 indices would need more memory than the mesh itself.
  const auto for_each_point = [&](const auto& visit) {
    for (const Primitive& p : mesh.primitives)
      for (uint32_t i : p.indices) {
        V3d world;
        instance.object_to_world.multVecMatrix(V3d(p.positions[i]), world);
        if (!visit(world)) return false;
      }
    return true;
  };
  Imath::Box3d box;
  for_each_point([&](const V3d& p) {
    box.extendBy(p);
    return true;
  });
  const double extent = box.isEmpty() ? 0.0 : (box.max - box.min).length();
  if (!(extent > 0.0) || !std::isfinite(extent)) return false;
  const double tolerance = kPlanarTolerance * extent;
  // The plane of the largest triangle, whose normal is the most accurate.
  V3d normal(0.0), origin(0.0);
  double largest = 0.0;
  V3d corner[3];
  int corners = 0;
  for_each_point([&](const V3d& p) {
    corner[corners++] = p;
    if (corners < 3) return true;
    corners = 0;
    const V3d n = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
    if (n.length() > largest) {
      largest = n.length();
      normal = n;
      origin = corner[0];
    }
    return true;
  });
  if (!(largest > tolerance * tolerance)) return false;
  normal /= largest;
  if (!for_each_point(
          [&](const V3d& p) { return std::abs((p - origin).dot(normal)) <= tolerance; }))
    return false;
  if (vertex_normal != V3f(0.0f)) {
    // Normals move with the inverse transpose (mesh_preparation.cpp, embree_scene.cpp).
    V3d placed;
    instance.object_to_world.inverse().transposed().multDirMatrix(V3d(vertex_normal), placed);
    const double length = placed.length();
    if (!(length > 0.0) || placed.cross(normal).length() > kNormalLean * length) return false;
    for (const Light& light : scene.lights) {
      // A directional light arrives the same way at every point (the mesh has some: its
      // extent is above 0).
      const auto clear_of = [&](const V3d& to_light) {
        return std::abs(to_light.dot(normal)) > kLightClearance * to_light.length();
      };
      const bool clear =
          light.type == LightType::directional
              ? clear_of(light.direction)
              : for_each_point([&](const V3d& p) { return clear_of(light.position - p); });
      if (!clear) return false;
    }
  }
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

// Whether any ray can reach the inside of the sphere: a refracting material lets rays in,
// and a camera inside starts them there. An orthographic camera's rays start anywhere on
// its image plane, whose width depends on the image's aspect, so it always counts. A scene
// without a camera gets add_scene_defaults' camera, which frames the scene from outside.
bool sphere_inside_seen(const SceneDescription& scene, const Sphere& sphere) {
  const MaterialDescription* m = material_at(scene, sphere.material);
  if (m && refracts(scene, *m)) return true;
  for (const CameraDescription& camera : scene.cameras) {
    if (camera.projection != Projection::perspective) return true;
    if (!((camera_position(camera) - sphere.centre).length() >
          sphere.radius * (1.0 + kPlanarTolerance)))
      return true;
  }
  return false;
}

bool light_outside(const Sphere& sphere, const Light& light) {
  return light.type == LightType::directional ||
         !((light.position - sphere.centre).length() < sphere.radius * (1.0 - kPlanarTolerance));
}

// The shadow rule. A shadow ray is only ever blocked by geometry between a lit point and a
// light, so:
//   - no geometry, or no light (neither punctual nor emissive): nothing to block;
//   - an emissive surface: it lights the other objects, and a curved one itself, as an area
//     light (every integrator samples it with shadow rays): not analysed further;
//   - two or more objects (mesh instances with triangles, spheres): one may block another;
//   - one sphere rendered exactly (analytic or Embree points): a convex surface with its
//     true normal. Seen from outside, a point facing a light sees it (the whole sphere lies
//     behind the tangent plane) and a point facing away is dark before any shadow ray. Seen
//     from inside, a light inside is seen too (the segment stays inside), but the far wall
//     blocks a light outside: so it may shadow when some light is outside and its inside
//     can be seen (sphere_inside_seen);
//   - one sphere as an icosphere: its interpolated normals face some lights its flat faces
//     do not, so near the terminator its own faces block shadow rays;
//   - one flat mesh (all triangles in one plane) with no light in that plane: cannot block
//     itself (flat_and_lit_off_plane);
//   - one mesh of any other shape: may shadow itself. Convex closed meshes are not
//     recognised, as interpolated normals would make them shadow themselves too.
// Whether the shadow falls where the camera looks is not considered: always conservative.
bool can_shadow(const SceneDescription& scene, const SphereOptions& spheres,
                const SceneFeatures& f) {
  if (f.objects == 0) return false;
  if (f.emission) return true;
  if (f.lights == LightKinds::none) return false;
  if (f.objects >= 2) return true;
  if (f.spheres == 1) {
    if (spheres.mode == SphereMode::mesh) return true;
    const Sphere& sphere = scene.spheres.front();
    if (normal_mapped(scene, sphere.material)) return true;
    if (!sphere_inside_seen(scene, sphere)) return false;
    return std::any_of(scene.lights.begin(), scene.lights.end(),
                       [&](const Light& light) { return light_outside(sphere, light); });
  }
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

std::string alpha_modes(const SceneFeatures& f) {
  return f.alpha_mask && f.alpha_blend ? "mask+blend"
         : f.alpha_mask                ? "mask"
         : f.alpha_blend               ? "blend"
                                       : "none";
}

}  // namespace

SceneFeatures derive_scene_features(const SceneDescription& scene, const SphereOptions& spheres) {
  SceneFeatures f;
  // A material's features once, however many primitives use it: finding its smallest
  // roughness reads its whole metallic-roughness texture.
  std::vector<bool> added(scene.materials.size() + 1, false);
  const auto add_once = [&](int material) {
    const size_t slot = material >= 0 && static_cast<size_t>(material) < scene.materials.size()
                            ? static_cast<size_t>(material)
                            : scene.materials.size();  // every default-material index
    if (added[slot]) return;
    added[slot] = true;
    add_material(scene, material, &f);
  };
  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[static_cast<size_t>(instance.mesh)];
    const size_t triangles = triangle_count(mesh);
    if (triangles == 0) continue;
    f.triangles += triangles;
    ++f.objects;
    for (const Primitive& p : mesh.primitives)
      if (p.indices.size() >= 3) {
        add_once(p.material);
        const MaterialDescription* m = material_at(scene, p.material);
        if (m && m->alpha_mode == AlphaMode::mask) f.alpha_mask = true;
        if (m && m->alpha_mode == AlphaMode::blend) f.alpha_blend = true;
      }
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
  for (const Sphere& s : scene.spheres) add_once(s.material);

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

std::string to_string(TexturedSlots textures) {
  std::string s;
  const auto add = [&](TexturedSlots slot, const char* name) {
    if (has(textures, slot)) s += (s.empty() ? "" : "+") + std::string(name);
  };
  add(TexturedSlots::base_colour, "base-colour");
  add(TexturedSlots::metallic_roughness, "metallic-roughness");
  add(TexturedSlots::emissive, "emissive");
  return s.empty() ? "none" : s;
}

std::string to_string(const SceneFeatures& f) {
  return "geometry=" + to_string(f.geometry) + " lights=" + to_string(f.lights) +
         " textures=" + to_string(f.textures) + " mirror=" + yes_no(f.mirror) +
         " transmission=" + yes_no(f.transmission) + " emission=" + yes_no(f.emission) +
         " alpha=" + alpha_modes(f) + " shadows=" + yes_no(f.shadows);
}

std::vector<std::pair<std::string, std::string>> feature_metadata(const SceneFeatures& f) {
  return {{"features", to_string(f)},
          {"featureGeometry", to_string(f.geometry)},
          {"featureLights", to_string(f.lights)},
          {"featureTextures", to_string(f.textures)},
          {"featureMirror", yes_no(f.mirror)},
          {"featureTransmission", yes_no(f.transmission)},
          {"featureEmission", yes_no(f.emission)},
          {"featureShadows", yes_no(f.shadows)},
          {"featureAlpha", alpha_modes(f)}};
}

}  // namespace prism
