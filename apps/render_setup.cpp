#include "apps/render_setup.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "renderer/image/image_metrics.h"
#include "scene_passes/scene_defaults.h"
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
  add_scene_select_option(cmd, &o->scene);
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

void add_scene_select_option(CLI::App* cmd, std::string* scene) {
  cmd->add_option("--scene", *scene,
                  "glTF scene to load, by name or index (default: the file's `scene`, else 0)");
}

// --memory-limit, shared by every command that loads a scene (all of them add
// --allow-external-paths and load through load_selected_scene).
static double g_memory_limit_gib = double(LoadOptions().memory_limit) / double(1u << 30);

SceneDescription load_selected_scene(const std::string& path, const LoadOptions& options) {
  LoadOptions limited = options;
  limited.memory_limit = static_cast<std::size_t>(g_memory_limit_gib * double(1u << 30));
  try {
    return load_gltf(path, limited);
  } catch (const SceneSelectionError& e) {
    throw UsageError(std::string("--scene ") + e.what());
  }
}

void add_allow_external_paths_flag(CLI::App* cmd, bool* allow) {
  // Untrusted files must not read anything outside their own folder (docs/gltf.md).
  cmd->add_flag("--allow-external-paths", *allow,
                "Let the scene's buffers and images come from outside its folder");
  cmd->add_option("--memory-limit", g_memory_limit_gib,
                  "GiB the scene's loading may allocate (geometry, texels, buffers)")
      ->check(CLI::Range(1.0 / 1024, 1024.0))
      ->capture_default_str();
}

GeometryOptions SceneSetup::geometry_options(const SphereOptions& spheres, bool robust,
                                             BuildQuality quality) const {
  GeometryOptions g;
  g.spheres = spheres;
  g.robust = robust;
  g.build_quality = quality;
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
  load_options.scene = o.scene;
  setup->scene = load_selected_scene(o.scene_path, load_options);
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

BuildQuality parse_build_quality_option(const std::string& text, const std::string& option) {
  BuildQuality quality;
  if (!parse_build_quality(text, &quality))
    throw UsageError(option + " " + text + ": expected low, medium or high");
  return quality;
}

SphereOptions parse_spheres_option(const std::string& text, const std::string& option) {
  SphereOptions spheres;
  std::string error;
  if (!parse_sphere_options(text, &spheres, &error))
    throw UsageError(option + " " + text + ": " + error);
  return spheres;
}

void add_sphere_detection_options(CLI::App* cmd, SphereDetectionFlags* flags, bool with_replace) {
  if (with_replace)
    cmd->add_flag(
        "--detect-spheres", flags->replace,
        "Render meshes whose vertices lie on a sphere as analytic spheres (and say which)");
  cmd->add_option(
         "--sphere-tolerance", flags->tolerance,
         "Largest distance of a vertex from the fitted sphere, relative to its radius, for "
         "a mesh to count as a sphere")
      ->capture_default_str();
}

SphereDetectionOptions check_sphere_detection_flags(const SphereDetectionFlags& flags) {
  if (!std::isfinite(flags.tolerance) || flags.tolerance <= 0.0 || flags.tolerance >= 0.1)
    throw UsageError("--sphere-tolerance: must be a relative deviation above 0 and below 0.1");
  SphereDetectionOptions options;
  options.tolerance = flags.tolerance;
  return options;
}

std::string describe_sphere_candidate(const SceneDescription& scene, const SphereCandidate& c) {
  const std::string& mesh = scene.meshes[static_cast<size_t>(c.mesh)].name;
  const std::string& node = scene.instances[c.instance].node_name;
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, ": centre (%.6g, %.6g, %.6g), radius %.6g, deviation %.3g",
                c.centre.x, c.centre.y, c.centre.z, c.radius, c.deviation);
  return "mesh [" + std::to_string(c.mesh) + "] '" + mesh + "' (node '" + node + "')" + numbers;
}

void replace_detected_spheres(const SphereDetectionOptions& options, const std::string& scene_path,
                              SceneDescription* scene) {
  const std::vector<SphereCandidate> candidates = find_sphere_meshes(*scene, options);
  // Described before the replacement removes their instances.
  std::vector<std::string> lines;
  for (const SphereCandidate& c : candidates)
    lines.push_back(c.blocker == SphereReplaceBlocker::none
                        ? "replaced " + describe_sphere_candidate(*scene, c) +
                              " by an analytic sphere"
                        : "kept " + describe_sphere_candidate(*scene, c) +
                              " as a mesh: " + to_string(c.blocker));
  const size_t replaced = replace_sphere_meshes(scene, candidates).size();
  for (const std::string& line : lines)
    std::fprintf(stderr, "prism: --detect-spheres: %s: %s\n", scene_path.c_str(), line.c_str());
  std::fprintf(stderr, "prism: --detect-spheres: %s: %zu mesh%s replaced\n", scene_path.c_str(),
               replaced, replaced == 1 ? "" : "es");
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
                               const GeometryOptions& geometry, const RenderResult& result) {
  const SphereOptions& spheres = geometry.spheres;
  RenderMetadata metadata;
  metadata.integrator = integrator;
  metadata.spp = setup.settings.spp;
  metadata.render_seconds = result.seconds;
  metadata.world_to_camera = camera.world_to_camera();
  metadata.world_to_ndc = camera.world_to_ndc();
  metadata.scene_path = options.scene_path;
  metadata.extra = {{"camera", setup.camera().name},
                    {"spheres", to_string(spheres)},
                    {"buildQuality", to_string(geometry.build_quality)},
                    {"robust", geometry.robust ? "1" : "0"},
                    {"maxDepth", std::to_string(setup.settings.max_depth)},
                    {"raysCamera", std::to_string(result.rays.camera)},
                    {"raysShadow", std::to_string(result.rays.shadow)},
                    {"raysReflection", std::to_string(result.rays.reflection)},
                    {"raysRefraction", std::to_string(result.rays.refraction)},
                    {"discardedSamples", std::to_string(result.rays.discarded_samples)}};
  const RenderSettings& s = setup.settings;
  if (s.adaptive()) {  // docs/sampling.md: spp above is then the most a pixel took
    char mean[32];
    std::snprintf(mean, sizeof mean, "%.6g", result.mean_spp(s));
    metadata.extra.insert(metadata.extra.end(),
                          {{"adaptiveTargetError", format_error(s.target_error)},
                           {"adaptiveTimeLimit", format_error(s.time_limit_seconds)},
                           {"adaptiveMinSpp", std::to_string(s.min_spp)},
                           {"adaptiveRounds", std::to_string(result.rounds)},
                           {"adaptiveTimeLimitReached", result.time_limit_reached ? "1" : "0"},
                           {"samplesTaken", std::to_string(result.rays.camera)},
                           {"meanSpp", mean}});
  }
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
