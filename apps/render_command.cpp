#include "apps/render_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "apps/progress_bar.h"
#include "integrators/integrators.h"
#include "renderer/camera.h"
#include "renderer/colour.h"
#include "renderer/image_metrics.h"
#include "renderer/image_output.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "renderer/scene_defaults.h"
#include "renderer/sphere_geometry.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

// Thrown for problems with what the user asked, printed as one line.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

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

// Checked before any work, so a typo in -o costs nothing and overwrites nothing.
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

std::string with_commas(uint64_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<size_t>(i), ",");
  return s;
}

// The error after one pass, against --reference.
struct QuickError {
  double rmse = 0.0;
  double relmse = 0.0;
};

// Six significant digits, as `prism diff` and idiff print.
std::string format_error(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

int run(const RenderOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  IntegratorKind integrator_kind;
  if (!parse_integrator(o.integrator, &integrator_kind))
    throw UsageError("--integrator " + o.integrator + ": expected phong, shadow or whitted");
  GeometryOptions geometry_options;
  std::string sphere_error;
  if (!parse_sphere_options(o.spheres, &geometry_options.spheres, &sphere_error))
    throw UsageError("--spheres " + o.spheres + ": " + sphere_error);
  geometry_options.robust = o.robust;
  WorkingSpace working_space;
  if (!parse_working_space(o.working_space, &working_space))
    throw UsageError("--working-space " + o.working_space + ": expected linear-rec709 or acescg");
  RenderSettings settings;
  const bool explicit_resolution = !o.resolution.empty();
  if (explicit_resolution && !parse_resolution(o.resolution, &settings.width, &settings.height))
    throw UsageError("--res " + o.resolution + ": expected WIDTHxHEIGHT, each 1 to 32768");
  check_output_path(o.output_path, ".exr", "-o");
  if (!o.preview_path.empty()) check_output_path(o.preview_path, ".png", "--preview");
  if (!std::isfinite(o.ambient) || o.ambient < 0.0f)
    throw UsageError("--ambient: must be a finite radiance >= 0");
  if (!std::isfinite(o.background) || o.background < 0.0f)
    throw UsageError("--background: must be a finite radiance >= 0");
  // Read before the scene, so a wrong path costs nothing.
  Image reference;
  if (!o.reference_path.empty()) {
    try {
      reference = read_exr(o.reference_path);
    } catch (const std::exception& e) {
      throw UsageError(std::string("--reference ") + e.what());
    }
  }

  std::unique_ptr<tbb::global_control> thread_limit;
  if (o.threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, static_cast<size_t>(o.threads));

  const ColourPipeline colour(working_space);
  const auto load_start = std::chrono::steady_clock::now();
  SceneDescription scene = load_gltf(o.scene_path);
  add_scene_defaults(&scene);
  for (const std::string& w : scene.warnings)
    std::fprintf(stderr, "prism: warning: %s: %s\n", o.scene_path.c_str(), w.c_str());

  const int camera_index = select_camera(scene, o.camera);
  const CameraDescription& camera_description = scene.cameras[static_cast<size_t>(camera_index)];
  if (!explicit_resolution && camera_description.aspect_ratio > 0.0) {
    settings.height = 480;
    settings.width =
        std::max(1, static_cast<int>(std::lround(480.0 * camera_description.aspect_ratio)));
  }
  if (!o.reference_path.empty() &&
      (reference.width != settings.width || reference.height != settings.height)) {
    throw UsageError("--reference " + o.reference_path + " is " + std::to_string(reference.width) +
                     "x" + std::to_string(reference.height) + " but the render is " +
                     std::to_string(settings.width) + "x" + std::to_string(settings.height));
  }
  settings.spp = o.spp;
  settings.max_depth = o.max_depth;
  settings.threads = o.threads;
  settings.ambient = V3f(o.ambient);
  settings.background = V3f(o.background);

  // Rebased on the camera so rays, hits and lights stay near 0 in float wherever the scene
  // sits in the world (docs/stress-shading.md, huge coordinates).
  geometry_options.world_origin = camera_position(camera_description);
  const RenderScene render_scene(scene, geometry_options, colour);
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
  const Camera camera = render_scene.camera(camera_description, settings.width, settings.height);
  const std::unique_ptr<Integrator> integrator = make_integrator(integrator_kind);
  const GeometryStatistics& stats = render_scene.geometry().statistics();
  if (o.verbose) {
    std::fprintf(stderr,
                 "prism: %s: %zu triangles (%zu meshes baked, %zu instances), %zu spheres (%s), "
                 "%zu lights, camera '%s', %dx%d, %d spp, loaded and built in %.3f s\n",
                 o.scene_path.c_str(), stats.triangles, stats.meshes_baked, stats.mesh_instances,
                 stats.spheres, to_string(geometry_options.spheres).c_str(),
                 render_scene.lights().size(), camera_description.name.c_str(), settings.width,
                 settings.height, settings.spp, load_seconds);
  }

  // With a reference, the per-pass lines report progress, and a bar would garble them.
  ProgressBar progress(!o.quiet && o.reference_path.empty());
  Image image;
  const RenderContext context{render_scene, camera, settings};
  std::vector<QuickError> pass_errors;
  PassCallback after_pass;
  if (!o.reference_path.empty()) {
    after_pass = [&](int samples, const Image& so_far) {
      const ImageError e = compare_images(so_far, reference);
      pass_errors.push_back({e.overall.rmse, e.overall.relmse});
      if (!o.quiet)
        std::fprintf(stderr, "prism: pass %d/%d: RMSE %.6g relMSE %.6g\n", samples, settings.spp,
                     e.overall.rmse, e.overall.relmse);
    };
  }
  const RenderResult result = render(
      *integrator, context, &image, [&](int done, int total) { progress.update(done, total); },
      after_pass);
  progress.finish();

  RenderMetadata metadata;
  metadata.integrator = integrator->name();
  metadata.spp = settings.spp;
  metadata.render_seconds = result.seconds;
  metadata.world_to_camera = camera.world_to_camera();
  metadata.world_to_ndc = camera.world_to_ndc();
  metadata.scene_path = o.scene_path;
  metadata.extra = {{"camera", camera_description.name},
                    {"spheres", to_string(geometry_options.spheres)},
                    {"maxDepth", std::to_string(settings.max_depth)},
                    {"raysCamera", std::to_string(result.rays.camera)},
                    {"raysShadow", std::to_string(result.rays.shadow)},
                    {"raysReflection", std::to_string(result.rays.reflection)},
                    {"raysRefraction", std::to_string(result.rays.refraction)},
                    {"discardedSamples", std::to_string(result.rays.discarded_samples)}};
  if (!pass_errors.empty()) {
    std::string rmse, relmse;
    for (const QuickError& e : pass_errors) {
      rmse += (rmse.empty() ? "" : ",") + format_error(e.rmse);
      relmse += (relmse.empty() ? "" : ",") + format_error(e.relmse);
    }
    metadata.extra.insert(metadata.extra.end(),
                          {{"reference", o.reference_path},
                           {"referenceRMSE", format_error(pass_errors.back().rmse)},
                           {"referenceRelMSE", format_error(pass_errors.back().relmse)},
                           {"referenceRMSEPerPass", rmse},
                           {"referenceRelMSEPerPass", relmse}});
  }
  write_exr(o.output_path, image, colour, metadata,
            o.half ? ExrPixelType::half : ExrPixelType::float32);
  if (!o.preview_path.empty()) write_png_preview(o.preview_path, image, colour);

  if (!o.quiet) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const RayCounters& r = result.rays;
    std::printf("rendered %s with %s, %dx%d, %d spp, spheres %s\n", o.scene_path.c_str(),
                integrator->name(), settings.width, settings.height, settings.spp,
                to_string(geometry_options.spheres).c_str());
    std::printf("render time  %.3f s (load + build %.3f s, total %.3f s)\n", result.seconds,
                load_seconds, wall);
    std::printf("rays         camera %s, shadow %s, reflection %s, refraction %s, total %s\n",
                with_commas(r.camera).c_str(), with_commas(r.shadow).c_str(),
                with_commas(r.reflection).c_str(), with_commas(r.refraction).c_str(),
                with_commas(r.total()).c_str());
    std::printf("rays/second  %.3g\n", result.seconds > 0.0 ? r.total() / result.seconds : 0.0);
    std::printf("discarded    %s non-finite samples\n", with_commas(r.discarded_samples).c_str());
    if (!pass_errors.empty())
      std::printf("reference    RMSE %s, relMSE %s against %s\n",
                  format_error(pass_errors.back().rmse).c_str(),
                  format_error(pass_errors.back().relmse).c_str(), o.reference_path.c_str());
    std::printf("wrote        %s\n", o.output_path.c_str());
    if (!o.preview_path.empty()) std::printf("wrote        %s\n", o.preview_path.c_str());
  }
  return 0;
}

}  // namespace

CLI::App* add_render_command(CLI::App& app, RenderOptions* o) {
  CLI::App* cmd = app.add_subcommand("render", "Render a glTF scene to an EXR image");
  cmd->add_option("scene", o->scene_path, "Scene file (.gltf or .glb)")->required();
  cmd->add_option("-o,--output", o->output_path, "Output image (.exr), scene-linear")->required();
  cmd->add_option("--integrator", o->integrator, "phong | shadow | whitted")->capture_default_str();
  cmd->add_option("--spp", o->spp, "Samples per pixel (1 = through pixel centres)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
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
  cmd->add_option("--spheres", o->spheres, "analytic | mesh[:LEVEL] | embree-points")
      ->capture_default_str();
  cmd->add_option("--preview", o->preview_path, "Also write a display-referred PNG preview");
  cmd->add_option("--working-space", o->working_space, "linear-rec709 | acescg")
      ->capture_default_str();
  cmd->add_option("--ambient", o->ambient, "Ambient radiance I_a (lecture's ambient term)")
      ->capture_default_str();
  cmd->add_option("--background", o->background, "Radiance of rays that leave the scene")
      ->capture_default_str();
  cmd->add_option("--reference", o->reference_path,
                  "Render one sample per pixel per pass and log each pass's RMSE and relMSE "
                  "(mean of (a-b)^2/(b^2+0.01)) against this EXR on stderr; they also go into the "
                  "output's metadata. The image itself is unchanged");
  cmd->add_flag("--half", o->half, "Write half-float EXR pixels instead of 32-bit float");
  cmd->add_flag("--robust", o->robust, "Watertight triangle intersection (RTC_SCENE_FLAG_ROBUST)");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("-v,--verbose", o->verbose, "Describe the scene before rendering");
  return cmd;
}

int run_render(const RenderOptions& options) {
  try {
    return run(options);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace prism
