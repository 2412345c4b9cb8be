#include "apps/render_setup.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "renderer/image_metrics.h"
#include "renderer/scene_defaults.h"
#include "renderer/scene_features.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

bool parse_resolution(const std::string& text, int* width, int* height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    return false;
  if (w < 1 || h < 1 || w > 32768 || h > 32768) return false;
  *width = w;
  *height = h;
  return true;
}

bool has_extension(const std::string& path, const char* extension) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == extension;
}

int select_camera(const SceneDescription& scene, const std::string& wanted) {
  if (wanted.empty()) return 0;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    if (scene.cameras[i].name == wanted) return static_cast<int>(i);
  char* end = nullptr;
  const long index = std::strtol(wanted.c_str(), &end, 10);
  if (end && *end == '\0' && index >= 0 && index < static_cast<long>(scene.cameras.size()))
    return static_cast<int>(index);
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  throw UsageError("--camera " + wanted + ": " + scene.source_path +
                   " has no such camera (it has " + names + ")");
}

}  // namespace

void add_scene_options(CLI::App* cmd, SceneOptions* o) {
  cmd->add_option("scene", o->scene_path, "Scene file (.gltf or .glb)")->required();
  cmd->add_option(
      "--res", o->resolution,
      "Image size WIDTHxHEIGHT (default 640x480, or 480 high at the camera's aspect ratio)");
  cmd->add_option("--camera", o->camera, "Camera name or index (default: the first)");
  cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--max-depth", o->max_depth,
                  "Longest chain of reflection/refraction rays (whitted)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_option("--working-space", o->working_space, "linear-rec709 | acescg")
      ->capture_default_str();
  cmd->add_option("--ambient", o->ambient, "Ambient radiance I_a (lecture's ambient term)")
      ->capture_default_str();
  cmd->add_option("--background", o->background, "Radiance of rays that leave the scene")
      ->capture_default_str();
  add_allow_external_paths_flag(cmd, &o->allow_external_paths);
}

void add_allow_external_paths_flag(CLI::App* cmd, bool* allow) {
  // Untrusted files must not read anything outside their own folder (docs/gltf.md).
  cmd->add_flag("--allow-external-paths", *allow,
                "Let the scene's buffers and images come from outside its folder");
}

GeometryOptions SceneSetup::geometry_options(const SphereOptions& spheres, bool robust) const {
  GeometryOptions g;
  g.spheres = spheres;
  g.robust = robust;
  g.world_origin = camera_position(camera());
  return g;
}

SceneSetup check_scene_options(const SceneOptions& o) {
  SceneSetup setup;
  if (!parse_working_space(o.working_space, &setup.working_space))
    throw UsageError("--working-space " + o.working_space + ": expected linear-rec709 or acescg");
  RenderSettings& s = setup.settings;
  setup.explicit_resolution = !o.resolution.empty();
  if (setup.explicit_resolution && !parse_resolution(o.resolution, &s.width, &s.height))
    throw UsageError("--res " + o.resolution + ": expected WIDTHxHEIGHT, each 1 to 32768");
  if (!std::isfinite(o.ambient) || o.ambient < 0.0f)
    throw UsageError("--ambient: must be a finite radiance >= 0");
  if (!std::isfinite(o.background) || o.background < 0.0f)
    throw UsageError("--background: must be a finite radiance >= 0");
  s.max_depth = o.max_depth;
  s.threads = o.threads;
  s.ambient = Imath::V3f(o.ambient);
  s.background = Imath::V3f(o.background);
  return setup;
}

void load_scene(const SceneOptions& o, SceneSetup* setup) {
  LoadOptions load_options;
  load_options.allow_external_paths = o.allow_external_paths;
  setup->scene = load_gltf(o.scene_path, load_options);
  add_scene_defaults(&setup->scene);
  for (const std::string& w : setup->scene.warnings)
    std::fprintf(stderr, "prism: warning: %s: %s\n", o.scene_path.c_str(), w.c_str());
  setup->camera_index = select_camera(setup->scene, o.camera);
  const double aspect = setup->camera().aspect_ratio;
  if (!setup->explicit_resolution && aspect > 0.0) {
    setup->settings.height = 480;
    setup->settings.width = std::max(1, static_cast<int>(std::lround(480.0 * aspect)));
  }
}

IntegratorKind parse_integrator_option(const std::string& text, const std::string& option) {
  IntegratorKind kind;
  if (!parse_integrator(text, &kind))
    throw UsageError(option + " " + text + ": expected phong, shadow or whitted");
  return kind;
}

SphereOptions parse_spheres_option(const std::string& text, const std::string& option) {
  SphereOptions spheres;
  std::string error;
  if (!parse_sphere_options(text, &spheres, &error))
    throw UsageError(option + " " + text + ": " + error);
  return spheres;
}

void check_output_path(const std::string& path, const char* extension, const char* option) {
  if (!has_extension(path, extension))
    throw UsageError(std::string(option) + " " + path + ": the file name must end in " + extension);
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw UsageError(std::string(option) + " " + path + ": directory " + parent.string() +
                     " does not exist");
  if (fs::is_directory(path))
    throw UsageError(std::string(option) + " " + path + ": is a directory");
}

Image read_reference(const std::string& path) {
  try {
    return read_exr(path);
  } catch (const std::exception& e) {
    throw UsageError(std::string("--reference ") + e.what());
  }
}

void check_reference_size(const Image& reference, const std::string& path,
                          const RenderSettings& settings) {
  if (reference.width != settings.width || reference.height != settings.height)
    throw UsageError("--reference " + path + " is " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height) + " but the render is " +
                     std::to_string(settings.width) + "x" + std::to_string(settings.height));
}

RenderMetadata render_metadata(const SceneOptions& options, const SceneSetup& setup,
                               const Camera& camera, const std::string& integrator,
                               const SphereOptions& spheres, const RenderResult& result) {
  RenderMetadata metadata;
  metadata.integrator = integrator;
  metadata.spp = setup.settings.spp;
  metadata.render_seconds = result.seconds;
  metadata.world_to_camera = camera.world_to_camera();
  metadata.world_to_ndc = camera.world_to_ndc();
  metadata.scene_path = options.scene_path;
  metadata.extra = {{"camera", setup.camera().name},
                    {"spheres", to_string(spheres)},
                    {"maxDepth", std::to_string(setup.settings.max_depth)},
                    {"raysCamera", std::to_string(result.rays.camera)},
                    {"raysShadow", std::to_string(result.rays.shadow)},
                    {"raysReflection", std::to_string(result.rays.reflection)},
                    {"raysRefraction", std::to_string(result.rays.refraction)},
                    {"discardedSamples", std::to_string(result.rays.discarded_samples)}};
  // Derived again rather than passed in, so `prism compare` records it too: it is cheap
  // next to a render.
  const auto features = feature_metadata(derive_scene_features(setup.scene, spheres));
  metadata.extra.insert(metadata.extra.end(), features.begin(), features.end());
  return metadata;
}

int run_reporting_errors(const std::function<int()>& command) {
  try {
    return command();
  } catch (const UsageError& e) {
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 1;
  }
}

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<size_t>(threads));
}

std::string with_commas(uint64_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<size_t>(i), ",");
  return s;
}

std::string format_error(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace prism
