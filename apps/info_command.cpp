#include "apps/info_command.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/command_line.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/geometry/sphere_geometry.h"
#include "renderer/scene_features.h"
#include "scene_io/gltf_loader.h"
#include "scene_io/gltf_scene_select.h"
#include "scene_passes/scene_defaults.h"
#include "session/session.h"

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
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  if (size <= 0) return nlohmann::json();
  std::string bytes(static_cast<size_t>(std::min<std::streamoff>(size, 20)), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) {
    const size_t head = bytes.size();
    bytes.resize(static_cast<size_t>(size));
    in.read(bytes.data() + head, static_cast<std::streamsize>(bytes.size() - head));
    return nlohmann::json::parse(bytes, nullptr, false);
  }
  // A GLB's JSON is its first chunk: the binary buffer after it is not read.
  const auto byte = [&](size_t at) {
    return static_cast<uint32_t>(static_cast<unsigned char>(bytes[at]));
  };
  const size_t length = byte(12) | byte(13) << 8 | byte(14) << 16 | byte(15) << 24;
  if (length > static_cast<size_t>(size) - 20) return nlohmann::json();
  bytes.resize(20 + length);
  in.read(bytes.data() + 20, static_cast<std::streamsize>(length));
  return nlohmann::json::parse(bytes.begin() + 20, bytes.end(), nullptr, false);
}

std::string extension_list(const nlohmann::json& root, const char* key) {
  if (!root.is_object() || !root.contains(key) || !root[key].is_array()) return "none";
  std::string s;
  for (const auto& name : root[key])
    if (name.is_string()) s += (s.empty() ? "" : ", ") + name.get<std::string>();
  return s.empty() ? "none" : s;
}

// Every scene of the file, marking the default and the one loaded (`--scene`).
void print_scenes(const nlohmann::json& root, const InfoOptions& o) {
  if (!root.is_object() || !root.contains("scenes") || !root["scenes"].is_array() ||
      root["scenes"].empty()) {
    std::printf("scenes: 0 (every root node loaded)\n");
    return;
  }
  const nlohmann::json& scenes = root["scenes"];
  std::vector<std::string> names;
  for (const auto& s : scenes) names.push_back(s.value("name", std::string()));
  const size_t default_scene = root.contains("scene") ? root["scene"].get<size_t>() : size_t{0};
  // The loader accepted the file with this --scene, so the selection cannot fail here.
  const size_t loaded =
      o.scene.empty() ? default_scene : gltf_detail::select_scene(names, o.scene, o.scene_path);
  std::printf("scenes: %zu (loaded: %zu)\n", scenes.size(), loaded);
  for (size_t i = 0; i < scenes.size(); ++i) {
    const size_t roots = scenes[i].contains("nodes") ? scenes[i]["nodes"].size() : 0;
    std::printf("  [%zu] %s: %zu root node%s%s%s\n", i,
                names[i].empty() ? "(unnamed)" : names[i].c_str(), roots, roots == 1 ? "" : "s",
                i == default_scene ? ", default" : "", i == loaded ? ", loaded" : "");
  }
}

// How the meshes are placed: what the text and the JSON both report.
struct Placements {
  std::vector<size_t> per_mesh;  // nodes placing each mesh
  size_t placed_triangles = 0;   // each instance counted, as the file holds them
  size_t instanced = 0;          // meshes placed more than once
  size_t placed_meshes = 0;
};

Placements placements(const SceneDescription& scene) {
  Placements out;
  out.per_mesh.assign(scene.meshes.size(), 0);
  for (const MeshInstance& i : scene.instances)
    if (i.mesh >= 0 && static_cast<size_t>(i.mesh) < out.per_mesh.size())
      ++out.per_mesh[static_cast<size_t>(i.mesh)];
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    size_t triangles = 0;
    for (const Primitive& p : scene.meshes[m].primitives) triangles += p.indices.size() / 3;
    out.placed_triangles += triangles * out.per_mesh[m];
    if (out.per_mesh[m] > 1) ++out.instanced;
    if (out.per_mesh[m] > 0) ++out.placed_meshes;
  }
  return out;
}

void print_meshes(const SceneDescription& scene) {
  const Placements placed = placements(scene);
  const std::vector<size_t>& placements = placed.per_mesh;
  std::printf("meshes: %zu (%zu placed by %zu nodes, %zu instanced), %s triangles as placed\n",
              scene.meshes.size(), placed.placed_meshes, scene.instances.size(), placed.instanced,
              with_commas(placed.placed_triangles).c_str());
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
                t.channels == 1 ? "" : "s", encoding_name(t.encoding), to_string(t.wrap_s),
                to_string(t.wrap_t));
  }
}

void print_lights(const SceneDescription& scene) {
  std::printf("lights: %zu\n", scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    // glTF's units: directional lights in lux, point and spot lights in candela.
    std::string line = "  [" + std::to_string(i) + "] " + (l.name.empty() ? "(unnamed)" : l.name) +
                       ": " + to_string(l.type) + ", " + number(l.intensity) +
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

// Meshes that `prism render --detect-spheres` would render as analytic spheres.
void print_sphere_meshes(const SceneDescription& scene, const SphereDetectionOptions& options) {
  const std::vector<SphereCandidate> found = find_sphere_meshes(scene, options);
  std::printf("sphere-shaped meshes (tolerance %g): %zu\n", options.tolerance, found.size());
  for (const SphereCandidate& c : found)
    std::printf("  %s%s%s\n", describe_sphere_candidate(scene, c).c_str(),
                c.blocker == SphereReplaceBlocker::none ? "" : "; --detect-spheres keeps it: ",
                to_string(c.blocker));
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

// The displays and views of the OCIO config in use ($OCIO's, else the shipped one), for
// render's --view.
void print_views() {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  std::printf("OCIO config: %s\n", colour.config_source().c_str());
  for (const DisplayView& v : colour.views())
    std::printf("  %s / %s%s\n", v.display.c_str(), v.view.c_str(),
                v.is_default ? " (default)" : "");
}

struct Timing {
  double load_seconds = 0.0, build_seconds = 0.0, peak_bytes = 0.0;
  GeometryStatistics built;
};

// The render scene as `prism render` builds it (BVH, materials, textures). No ray follows,
// so the quality is the cheapest to build: MEDIUM, as LOW built no faster
// (docs/benchmarks.md).
Timing measure(Session* session, const SphereOptions& spheres) {
  RenderJob job;
  job.spheres = spheres;
  job.build_quality = BuildQuality::medium;
  Timing t;
  const RenderScene& built = session->render_scene(job, &t.build_seconds);
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  t.built = built.geometry().statistics();
  t.peak_bytes = static_cast<double>(usage.ru_maxrss) * 1024.0;  // Linux: KiB
  t.load_seconds = session->load_seconds();
  return t;
}

nlohmann::json vector_json(const V3d& v) {
  return nlohmann::json::array({v.x, v.y, v.z});
}
nlohmann::json colour_json(const C3f& c) {
  return nlohmann::json::array({c.x, c.y, c.z});
}
nlohmann::json strings_json(const nlohmann::json& root, const char* key) {
  nlohmann::json out = nlohmann::json::array();
  if (root.is_object() && root.contains(key) && root[key].is_array())
    for (const auto& name : root[key])
      if (name.is_string()) out.push_back(name);
  return out;
}
size_t array_size(const nlohmann::json& object, const char* key) {
  return object.is_object() && object.contains(key) && object[key].is_array() ? object[key].size()
                                                                              : 0;
}

// docs/info.md has the schema; "version" changes when a field changes meaning or goes.
nlohmann::json info_json(const InfoOptions& o, Session* session, const nlohmann::json& root,
                         const SphereOptions& spheres) {
  using nlohmann::json;
  const SceneDescription& scene = session->scene();
  json out = {{"version", 1}, {"file", o.scene_path}};
  std::vector<std::string> names;
  if (root.is_object() && root.contains("scenes") && root["scenes"].is_array())
    for (const auto& s : root["scenes"])
      names.push_back(s.is_object() ? s.value("name", std::string()) : std::string());
  const size_t default_scene =
      root.is_object() && root.contains("scene") ? root["scene"].get<size_t>() : size_t{0};
  json scenes = {{"count", names.size()}, {"names", names}};
  if (!names.empty()) {
    scenes["default"] = default_scene;
    scenes["loaded"] =
        o.scene.empty() ? default_scene : gltf_detail::select_scene(names, o.scene, o.scene_path);
  }
  out["scenes"] = scenes;
  const Imath::Box3d box = world_bounds(scene);
  out["bounds"] = box.isEmpty()
                      ? json(nullptr)
                      : json{{"min", vector_json(box.min)}, {"max", vector_json(box.max)}};
  const Placements placed = placements(scene);
  out["meshes"] = {{"count", scene.meshes.size()},
                   {"placed", placed.placed_meshes},
                   {"nodes", scene.instances.size()},
                   {"instanced", placed.instanced},
                   {"triangles_as_placed", placed.placed_triangles}};
  json materials = json::array();
  for (const MaterialDescription& m : scene.materials)
    materials.push_back(
        {{"name", m.name},
         {"base_colour", colour_json(m.base_colour)},
         {"alpha", m.alpha},
         {"metallic", m.metallic},
         {"roughness", m.roughness},
         {"emissive", colour_json(m.emissive)},
         {"transmission", m.transmission},
         {"ior", m.ior},
         {"double_sided", m.double_sided},
         {"textured", m.base_colour_texture >= 0 || m.metallic_roughness_texture >= 0 ||
                          m.emissive_texture >= 0}});
  out["materials"] = materials;
  out["textures"] = scene.textures.size();
  json lights = json::array();
  for (const Light& l : scene.lights) {
    json light = {{"name", l.name},
                  {"type", to_string(l.type)},
                  {"intensity", l.intensity},
                  {"unit", l.type == LightType::directional ? "lx" : "cd"},
                  {"colour", colour_json(l.colour)}};
    if (l.type != LightType::directional) light["position"] = vector_json(l.position);
    if (l.type != LightType::point) light["direction"] = vector_json(l.direction);
    lights.push_back(light);
  }
  out["lights"] = lights;
  json cameras = json::array();
  for (const CameraDescription& c : scene.cameras) {
    const M44d& m = c.camera_to_world;
    json camera = {
        {"name", c.name},
        {"projection", c.projection == Projection::perspective ? "perspective" : "orthographic"},
        {"position", vector_json(V3d(m[3][0], m[3][1], m[3][2]))},
        {"direction", vector_json(-V3d(m[2][0], m[2][1], m[2][2]).normalized())}};
    if (c.projection == Projection::perspective)
      camera["yfov_degrees"] = c.yfov * kDegreesPerRadian;
    else
      camera["xmag"] = c.xmag, camera["ymag"] = c.ymag;
    cameras.push_back(camera);
  }
  out["cameras"] = cameras;
  out["spheres"] = scene.spheres.size();
  size_t morph_targets = 0;
  if (root.is_object() && root.contains("meshes") && root["meshes"].is_array())
    for (const auto& mesh : root["meshes"])
      if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
        for (const auto& p : mesh["primitives"]) morph_targets += array_size(p, "targets");
  out["animations"] = array_size(root, "animations");
  out["morph_targets"] = morph_targets;
  out["skins"] = array_size(root, "skins");
  out["extensions"] = {{"used", strings_json(root, "extensionsUsed")},
                       {"required", strings_json(root, "extensionsRequired")}};
  session->add_defaults();
  out["features"] = {{"spheres", to_string(spheres)},
                     {"set", to_string(derive_scene_features(scene, spheres))}};
  out["warnings"] = scene.warnings;
  if (o.timing || o.verbose) {
    const Timing t = measure(session, spheres);
    out["timing"] = {{"load_seconds", t.load_seconds},
                     {"build_seconds", t.build_seconds},
                     {"triangles_built", t.built.triangles},
                     {"triangles_degenerate", t.built.degenerate_triangles},
                     {"triangles_nonfinite", t.built.nonfinite_triangles},
                     {"peak_memory_bytes", t.peak_bytes}};
  }
  return out;
}

int run(const InfoOptions& o) {
  if (o.views) {
    if (!o.quiet) print_views();
    if (o.scene_path.empty()) return 0;
  }
  if (o.scene_path.empty()) throw UsageError("a scene file is required (or --views)");
  const SphereOptions spheres = parse_spheres_option(o.spheres, "--spheres");
  SphereDetectionFlags detection_flags = o.sphere_detection;
  detection_flags.replace = false;
  SceneOptions scene_options;
  scene_options.scene_path = o.scene_path;
  scene_options.scene = o.scene;
  scene_options.allow_external_paths = o.allow_external_paths;
  scene_options.memory_limit_gib = o.memory_limit_gib;
  SceneRequest request = scene_request(scene_options, detection_flags);
  // The file's own cameras and lights first; the defaults a render adds come after.
  request.add_defaults = false;
  Session session(request, session_options(scene_options));
  if (o.quiet) return 0;
  const SceneDescription& scene = session.scene();
  const nlohmann::json root = read_gltf_json(o.scene_path);
  if (o.json) {
    std::printf("%s\n", info_json(o, &session, root, spheres).dump(2).c_str());
    return 0;
  }
  std::printf("file: %s\n", o.scene_path.c_str());
  print_scenes(root, o);
  print_meshes(scene);
  print_materials(scene);
  print_textures(scene);
  print_lights(scene);
  print_cameras(scene);
  print_spheres(scene);
  // On request: the search welds every mesh's vertices, which on a big mesh costs several
  // times its load and BVH build (docs/benchmarks.md).
  if (o.find_sphere_meshes)
    print_sphere_meshes(scene, request.sphere_detection);
  else
    std::printf("sphere-shaped meshes: not looked for (--detect-spheres lists them)\n");
  std::printf("extensions: used %s; required %s\n", extension_list(root, "extensionsUsed").c_str(),
              extension_list(root, "extensionsRequired").c_str());
  // The feature set as `prism render` derives it: with the default camera and light that a
  // scene without them gets (their warnings follow).
  session.add_defaults();
  std::printf("features (spheres %s): %s\n", to_string(spheres).c_str(),
              to_string(derive_scene_features(scene, spheres)).c_str());
  std::printf("warnings: %zu\n", scene.warnings.size());
  for (const std::string& w : scene.warnings) std::printf("  %s\n", w.c_str());
  if (o.timing || o.verbose) {
    const Timing t = measure(&session, spheres);
    const size_t triangles = t.built.triangles;
    // Built and dropped add up to the meshes line's triangles as placed (analytic spheres).
    std::printf(
        "timing: load %.3f s, BVH build %.3f s, total %.3f s; %s triangles built (%s degenerate "
        "and %s non-finite dropped); peak memory %.1f MiB (%.0f bytes per triangle built)\n",
        t.load_seconds, t.build_seconds, t.load_seconds + t.build_seconds,
        with_commas(triangles).c_str(), with_commas(t.built.degenerate_triangles).c_str(),
        with_commas(t.built.nonfinite_triangles).c_str(), t.peak_bytes / (1024.0 * 1024.0),
        triangles > 0 ? t.peak_bytes / static_cast<double>(triangles) : 0.0);
  }
  return 0;
}

}  // namespace

CLI::App* add_info_command(CLI::App& app, InfoOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "info", "Print what a glTF file holds, its feature set and the loader's warnings");
  cmd->add_option("scene", o->scene_path, "Scene file (.gltf or .glb)");
  cmd->add_flag("--json", o->json, "Print it as one JSON object instead (docs/info.md)");
  cmd->add_flag("--views", o->views,
                "List the OCIO config's displays and views (render's --view), $OCIO's if set");
  cmd->add_option("--spheres", o->spheres,
                  "Sphere mode the feature set assumes: analytic | mesh[:LEVEL] | embree-points")
      ->capture_default_str();
  add_allow_external_paths_flag(cmd, &o->allow_external_paths);
  add_memory_limit_option(cmd, &o->memory_limit_gib);
  cmd->add_flag("--detect-spheres", o->find_sphere_meshes,
                "Also list the meshes whose vertices lie on a sphere, which render "
                "--detect-spheres would replace (takes longer than loading on big meshes)");
  add_sphere_detection_options(cmd, &o->sphere_detection, false);
  add_scene_select_option(cmd, &o->scene);
  cmd->add_flag("--timing", o->timing,
                "Also time loading and the BVH build, and report peak memory per triangle");
  add_verbosity_flags(cmd, &o->quiet, &o->verbose,
                      "Print nothing but errors: the exit code says whether the file loads",
                      "Everything, with --timing's line");
  return cmd;
}

int run_info(const InfoOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
