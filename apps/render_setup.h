// What `prism render` and `prism compare` share: the options that describe the scene and the
// image (scene, resolution, camera, threads, depth, working space, ambient, background), their
// checks, loading the scene with its defaults, and the small formatting helpers of their
// summaries. One place, so the two commands accept and refuse exactly the same input.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "integrators/integrators.h"
#include "renderer/camera.h"
#include "renderer/image/colour.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/image/image.h"
#include "renderer/image/image_output.h"
#include "renderer/integrator.h"
#include "renderer/render.h"
#include "renderer/scene_description.h"
#include "scene_passes/sphere_detection.h"
#include "renderer/geometry/sphere_geometry.h"
#include "scene_io/gltf_loader.h"

namespace prism {

// A problem with what the user asked: one line on stderr and exit code 2 (a scene that cannot
// be rendered is any other exception, exit code 1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SceneOptions {
  std::string scene_path;
  std::string resolution;  // "WxH", empty = 640x480 or 480 high at the camera's aspect ratio
  std::string camera;      // name or index, empty = the first
  std::string scene;       // glTF scene name or index, empty = the file's default
  int threads = 0;
  int max_depth = 5;
  std::string working_space = "linear-rec709";
  float ambient = 0.0f;
  float background = 0.0f;
  bool allow_external_paths = false;  // buffers and images from outside the scene's folder
};

// Adds --scene NAME|INDEX (every command that reads a scene file offers it).
// Accepts a finite number above 0 (CLI11's PositiveNumber accepts NaN and prints DBL_MAX in
// its message):
// --target-error, --time-limit, compare's --target-errors.
inline const CLI::Validator kPositiveFinite(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v <= 0.0)
        return "must be a finite number > 0, not " + text;
      return "";
    },
    "POSITIVE");

void add_scene_select_option(CLI::App* cmd, std::string* scene);
// load_gltf, with a --scene the file does not have reported as a UsageError (exit code 2).
SceneDescription load_selected_scene(const std::string& path, const LoadOptions& options);

// Adds --allow-external-paths (every command that reads a scene file offers it).
void add_allow_external_paths_flag(CLI::App* cmd, bool* allow);

// Adds the scene positional argument and --scene, --res, --camera, --threads, --max-depth,
// --working-space, --ambient and --background to `cmd`.
void add_scene_options(CLI::App* cmd, SceneOptions* options);

// The scene options checked (no file is read), then the scene loaded into it.
struct SceneSetup {
  WorkingSpace working_space = WorkingSpace::linear_rec709;
  RenderSettings settings;  // width and height final only after load_scene
  bool explicit_resolution = false;
  SceneDescription scene;
  int camera_index = 0;

  const CameraDescription& camera() const {
    return scene.cameras[static_cast<size_t>(camera_index)];
  }
  // Geometry rebased on the camera, so rays, hits and lights stay near 0 in float wherever
  // the scene sits in the world (docs/stress-shading.md, huge coordinates).
  GeometryOptions geometry_options(const SphereOptions& spheres, bool robust,
                                   BuildQuality quality = GeometryOptions().build_quality) const;
};

// Checks every option that needs no file; throws UsageError naming the option.
SceneSetup check_scene_options(const SceneOptions& options);

// Loads the glTF file, adds the default camera and light if missing (printing each warning on
// stderr), selects --camera and settles the resolution on its aspect ratio.
void load_scene(const SceneOptions& options, SceneSetup* setup);

// "phong" -> IntegratorKind; `option` names the flag in the error ("--integrator").
IntegratorKind parse_integrator_option(const std::string& text, const std::string& option);
// "low" | "medium" | "high" -> BuildQuality; `option` names the flag in the error.
BuildQuality parse_build_quality_option(const std::string& text, const std::string& option);
// "analytic", "mesh:3", ... -> SphereOptions; `option` names the flag in the error.
SphereOptions parse_spheres_option(const std::string& text, const std::string& option);

// --detect-spheres (render only: `replace`) and --sphere-tolerance (docs/spheres.md).
struct SphereDetectionFlags {
  bool replace = false;
  double tolerance = SphereDetectionOptions().tolerance;
};
void add_sphere_detection_options(CLI::App* cmd, SphereDetectionFlags* flags, bool with_replace);
// The options, or a UsageError naming --sphere-tolerance.
SphereDetectionOptions check_sphere_detection_flags(const SphereDetectionFlags& flags);
// "mesh [2] 'Ball' (node 'Ball'): centre (x, y, z), radius r, deviation d", as info and render
// print a candidate.
std::string describe_sphere_candidate(const SceneDescription& scene, const SphereCandidate& c);
// Replaces the scene's sphere-shaped meshes by analytic spheres, printing on stderr one line
// per mesh replaced and per candidate kept as a mesh (with the reason).
void replace_detected_spheres(const SphereDetectionOptions& options, const std::string& scene_path,
                              SceneDescription* scene);

// Checked before any work, so a typo in an output path costs nothing and overwrites nothing.
void check_output_path(const std::string& path, const char* extension, const char* option);

// Reads --reference REF (UsageError naming it when it cannot be read), and checks it has the
// render's size once that is known.
Image read_reference(const std::string& path);
void check_reference_size(const Image& reference, const std::string& path,
                          const RenderSettings& settings);

// What the EXR of a finished render records: integrator, spp, time, camera matrices, scene,
// sphere mode, BVH build quality and robustness, depth, the rays cast by kind and the
// scene's feature set (scene_features.h).
RenderMetadata render_metadata(const SceneOptions& options, const SceneSetup& setup,
                               const Camera& camera, const std::string& integrator,
                               const GeometryOptions& geometry, const RenderResult& result);

// Runs a command, turning what it throws into one line on stderr and an exit code: 2 for a
// UsageError, 1 for anything else (a scene that cannot be rendered, a file not written).
int run_reporting_errors(const std::function<int()>& command);

// Limits TBB to `threads` workers while the returned object lives; 0 = every core (null).
std::unique_ptr<tbb::global_control> limit_threads(int threads);

// 1234567 -> "1,234,567".
std::string with_commas(uint64_t n);
// Six significant digits, as `prism diff` and idiff print.
std::string format_error(double v);

}  // namespace prism
