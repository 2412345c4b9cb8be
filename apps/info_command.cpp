#include "apps/info_command.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/render_setup.h"
#include "renderer/scene_defaults.h"
#include "renderer/scene_features.h"
#include "renderer/sphere_geometry.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

constexpr double kDegreesPerRadian = 57.29577951308232;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

std::string triple(double x, double y, double z) {
  return "(" + number(x) + ", " + number(y) + ", " + number(z) + ")";
}
std::string triple(const C3f& c) {
  return triple(c.x, c.y, c.z);
}
std::string triple(const V3d& v) {
  return triple(v.x, v.y, v.z);
}

const char* encoding_name(TextureEncoding e) {
  return e == TextureEncoding::srgb ? "sRGB" : "linear";
}

const char* wrap_name(TextureWrap w) {
  switch (w) {
    case TextureWrap::repeat:
      return "repeat";
    case TextureWrap::clamp_to_edge:
      return "clamp-to-edge";
    case TextureWrap::mirrored_repeat:
      return "mirrored-repeat";
  }
  return "repeat";
}

const char* light_type_name(LightType t) {
  switch (t) {
    case LightType::directional:
      return "directional";
    case LightType::point:
      return "point";
    case LightType::spot:
      return "spot";
  }
  return "point";
}

std::string texture_name(const SceneDescription& scene, int index) {
  if (index < 0 || static_cast<size_t>(index) >= scene.textures.size()) return "";
  const TextureImage& t = scene.textures[static_cast<size_t>(index)];
  return "[" + std::to_string(index) + "] " + (t.name.empty() ? "(unnamed)" : t.name) + " (" +
         encoding_name(t.encoding) + ")";
}

std::string material_name(const SceneDescription& scene, int index) {
  if (index < 0 || static_cast<size_t>(index) >= scene.materials.size()) return "default";
  const std::string& name = scene.materials[static_cast<size_t>(index)].name;
  return name.empty() ? "[" + std::to_string(index) + "]" : name;
}

// extensionsUsed and extensionsRequired are not part of SceneDescription (the loader acts on
// them and forgets them), so they are read from the file's JSON, after the loader has
// accepted it. A .glb holds its JSON in the first chunk.
nlohmann::json read_gltf_json(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {
    const auto u32 = [&](size_t at) {
      return static_cast<uint32_t>(static_cast<unsigned char>(bytes[at])) |
             static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 8 |
             static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 16 |
             static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 3])) << 24;
    };
    const size_t length = u32(12);
    if (length > bytes.size() - 20) return nlohmann::json();
    return nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + length, nullptr, false);
  }
  return nlohmann::json::parse(bytes, nullptr, false);
}

std::string extension_list(const nlohmann::json& root, const char* key) {
  if (!root.is_object() || !root.contains(key) || !root[key].is_array()) return "none";
  std::string s;
  for (const auto& name : root[key])
    if (name.is_string()) s += (s.empty() ? "" : ", ") + name.get<std::string>();
  return s.empty() ? "none" : s;
}

void print_meshes(const SceneDescription& scene) {
  std::vector<size_t> placements(scene.meshes.size(), 0);
  for (const MeshInstance& i : scene.instances)
    if (i.mesh >= 0 && static_cast<size_t>(i.mesh) < placements.size())
      ++placements[static_cast<size_t>(i.mesh)];
  size_t placed_triangles = 0, instanced = 0;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    size_t triangles = 0;
    for (const Primitive& p : scene.meshes[m].primitives) triangles += p.indices.size() / 3;
    placed_triangles += triangles * placements[m];
    if (placements[m] > 1) ++instanced;
  }
  std::printf("meshes: %zu (%zu placed by %zu nodes, %zu instanced), %s triangles as placed\n",
              scene.meshes.size(),
              scene.meshes.size() - std::count(placements.begin(), placements.end(), size_t{0}),
              scene.instances.size(), instanced, with_commas(placed_triangles).c_str());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    size_t triangles = 0;
    bool normals = true, uvs = true;
    std::string materials;
    for (const Primitive& p : mesh.primitives) {
      triangles += p.indices.size() / 3;
      normals = normals && !p.normals.empty();
      uvs = uvs && !p.uv0.empty();
      const std::string name = material_name(scene, p.material);
      if (materials.find(name) == std::string::npos)
        materials += (materials.empty() ? "" : ", ") + name;
    }
    // Placed once, a mesh is baked into world space; several times, each node is an
    // Embree instance of one copy.
    std::printf(
        "  [%zu] %s: %zu primitive%s, %s triangles, placed %zux (%s), normals %s, uv %s, "
        "materials %s\n",
        m, mesh.name.empty() ? "(unnamed)" : mesh.name.c_str(), mesh.primitives.size(),
        mesh.primitives.size() == 1 ? "" : "s", with_commas(triangles).c_str(), placements[m],
        placements[m] > 1    ? "instanced"
        : placements[m] == 1 ? "baked"
                             : "unused",
        normals ? "yes" : "no (flat)", uvs ? "yes" : "no",
        materials.empty() ? "none" : materials.c_str());
  }
}

void print_materials(const SceneDescription& scene) {
  std::printf("materials: %zu\n", scene.materials.size());
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const MaterialDescription& m = scene.materials[i];
    std::string line = "  [" + std::to_string(i) + "] " + (m.name.empty() ? "(unnamed)" : m.name) +
                       ": base colour " + triple(m.base_colour);
    if (m.alpha != 1.0f) line += " alpha " + number(m.alpha);
    line += ", metallic " + number(m.metallic) + ", roughness " + number(m.roughness);
    if (m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f)
      line += ", emissive " + triple(m.emissive);
    if (m.transmission > 0.0f)
      line += ", transmission " + number(m.transmission) + " ior " + number(m.ior);
    if (m.specular != 1.0f || m.specular_colour != C3f(1.0f, 1.0f, 1.0f))
      line += ", specular " + number(m.specular) + " " + triple(m.specular_colour);
    if (m.double_sided) line += ", double-sided";
    std::printf("%s\n", line.c_str());
    const auto slot = [&](const char* what, int index) {
      if (index >= 0)
        std::printf("      %s texture %s\n", what, texture_name(scene, index).c_str());
    };
    slot("base colour", m.base_colour_texture);
    slot("metallic-roughness", m.metallic_roughness_texture);
    slot("emissive", m.emissive_texture);
  }
}

void print_textures(const SceneDescription& scene) {
  std::printf("textures: %zu\n", scene.textures.size());
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const TextureImage& t = scene.textures[i];
    std::printf("  [%zu] %s: %dx%d, %d channel%s, %s, wrap %s/%s\n", i,
                t.name.empty() ? "(unnamed)" : t.name.c_str(), t.width, t.height, t.channels,
                t.channels == 1 ? "" : "s", encoding_name(t.encoding), wrap_name(t.wrap_s),
                wrap_name(t.wrap_t));
  }
}

void print_lights(const SceneDescription& scene) {
  std::printf("lights: %zu\n", scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    // glTF's units: directional lights in lux, point and spot lights in candela.
    std::string line = "  [" + std::to_string(i) + "] " + (l.name.empty() ? "(unnamed)" : l.name) +
                       ": " + light_type_name(l.type) + ", " + number(l.intensity) +
                       (l.type == LightType::directional ? " lx" : " cd") + ", colour " +
                       triple(l.colour);
    if (l.type != LightType::directional) line += ", at " + triple(l.position);
    if (l.type != LightType::point) line += ", direction " + triple(l.direction);
    if (l.type == LightType::spot)
      line += ", cone " + number(l.inner_cone_angle * kDegreesPerRadian) + "-" +
              number(l.outer_cone_angle * kDegreesPerRadian) + " deg";
    if (l.range > 0.0) line += ", range " + number(l.range) + " m";
    std::printf("%s\n", line.c_str());
  }
}

void print_cameras(const SceneDescription& scene) {
  std::printf("cameras: %zu\n", scene.cameras.size());
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    const CameraDescription& c = scene.cameras[i];
    std::string line = "  [" + std::to_string(i) + "] " + (c.name.empty() ? "(unnamed)" : c.name);
    if (c.projection == Projection::perspective)
      line += ": perspective, yfov " + number(c.yfov * kDegreesPerRadian) + " deg";
    else
      line += ": orthographic, xmag " + number(c.xmag) + " ymag " + number(c.ymag);
    line += ", aspect " + (c.aspect_ratio > 0.0 ? number(c.aspect_ratio) : std::string("image"));
    std::printf("%s\n", line.c_str());
  }
}

void print_spheres(const SceneDescription& scene) {
  std::printf("spheres: %zu\n", scene.spheres.size());
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    const Sphere& s = scene.spheres[i];
    std::printf("  [%zu] %s: centre %s, radius %s, material %s\n", i, s.node_name.c_str(),
                triple(s.centre).c_str(), number(s.radius).c_str(),
                material_name(scene, s.material).c_str());
  }
}

int run(const InfoOptions& o) {
  const SphereOptions spheres = parse_spheres_option(o.spheres, "--spheres");
  SceneDescription scene;
  try {
    LoadOptions load_options;
    load_options.allow_external_paths = o.allow_external_paths;
    scene = load_gltf(o.scene_path, load_options);
  } catch (const LoadError&) {
    throw;  // already "<file>: <element>: <what>"
  } catch (const std::exception& e) {
    throw std::runtime_error(o.scene_path + ": " + e.what());
  }
  std::printf("file: %s\n", o.scene_path.c_str());
  print_meshes(scene);
  print_materials(scene);
  print_textures(scene);
  print_lights(scene);
  print_cameras(scene);
  print_spheres(scene);
  const nlohmann::json root = read_gltf_json(o.scene_path);
  std::printf("extensions: used %s; required %s\n", extension_list(root, "extensionsUsed").c_str(),
              extension_list(root, "extensionsRequired").c_str());
  // The feature set as `prism render` derives it: with the default camera and light that a
  // scene without them gets (their warnings follow).
  add_scene_defaults(&scene);
  std::printf("features (spheres %s): %s\n", to_string(spheres).c_str(),
              to_string(derive_scene_features(scene, spheres)).c_str());
  std::printf("warnings: %zu\n", scene.warnings.size());
  for (const std::string& w : scene.warnings) std::printf("  %s\n", w.c_str());
  return 0;
}

}  // namespace

CLI::App* add_info_command(CLI::App& app, InfoOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "info", "Print what a glTF file holds, its feature set and the loader's warnings");
  cmd->add_option("scene", o->scene_path, "Scene file (.gltf or .glb)")->required();
  cmd->add_option("--spheres", o->spheres,
                  "Sphere mode the feature set assumes: analytic | mesh[:LEVEL] | embree-points")
      ->capture_default_str();
  add_allow_external_paths_flag(cmd, &o->allow_external_paths);
  return cmd;
}

int run_info(const InfoOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
