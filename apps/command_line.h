// What the commands share: the options that describe a scene and a render (scene, --res,
// --camera, --threads, --working-space, --background and every integrator parameter, the
// latter from the integrator registry), turned into the job API's requests
// (session/job.h), and the reporting of its errors as one line and an exit code. One place,
// so every command accepts and refuses exactly the same input. No pipeline logic lives here.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "integrators/registry.h"
#include "renderer/enum_names.h"
#include "session/job.h"

namespace prism {

// A problem with what the user asked: one line on stderr and exit code 2 (a scene that cannot
// be rendered is any other exception, exit code 1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SceneOptions {
  std::string scene_path;
  std::string resolution;  // "WxH", empty = 640x480 or 480 high at the camera's aspect ratio
  std::string camera;      // name or index, empty = the first, "auto" = framing the scene
  std::string look_from, look_at, up;  // "X,Y,Z", empty = the camera's own
  double fov = 0.0;                    // degrees, 0 = the camera's own
  std::string scene;                   // glTF scene name or index, empty = the file's default
  int threads = 0;
  std::string working_space = "linear-rec709";
  std::string brdf = "gltf";
  std::string background = "0";       // L (grey) or R,G,B
  EnvironmentRequest environment;     // --environment and its --environment-* options
  bool allow_external_paths = false;  // buffers and images from outside the scene's folder
  double memory_limit_gib = 8.0;      // SessionOptions::memory_budget_bytes, in GiB
  // Every integrator parameter given on the command line, by its name in the registry.
  ParameterSettings integrator_parameters;
};

// Accepts a finite number above 0 (CLI11's PositiveNumber accepts NaN and prints DBL_MAX in
// its message): --target-error, --time-limit, compare's --target-errors.
inline const CLI::Validator kPositiveFinite(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v <= 0.0)
        return "must be a finite number > 0, not " + text;
      return "";
    },
    "POSITIVE");

// Accepts a whole number from `lo` to `hi` (CLI11's Range takes 1.5 for a number and calls it
// "not in range"): --spp, --min-spp, --threads, compare's --spp.
CLI::Validator whole_number(int lo, int hi);

// The heading `--help` lists the options for developers under (the Embree flags,
// --general-path), apart from those every user needs.
inline constexpr const char* kDeveloperGroup = "Developer options";

// Adds -q,--quiet and -v,--verbose (every command offers both). Together, each does what it
// does alone: `render -q -v` describes the scene and prints no progress.
void add_verbosity_flags(CLI::App* cmd, bool* quiet, bool* verbose, const std::string& quiet_help,
                         const std::string& verbose_help);

// Adds --scene NAME|INDEX (every command that reads a scene file offers it).
void add_scene_select_option(CLI::App* cmd, std::string* scene);
// Adds --allow-external-paths (every command that reads a scene file offers it).
void add_allow_external_paths_flag(CLI::App* cmd, bool* allow);
// Adds --memory-limit GIB (every command that reads a scene file offers it).
void add_memory_limit_option(CLI::App* cmd, double* gib);
// Adds --seed S (RenderSettings::seed), with what it selects in this command.
void add_seed_option(CLI::App* cmd, int* seed, const std::string& help);

// Adds the scene positional argument and --scene, --res, --camera, --threads,
// --working-space, --background, --allow-external-paths and one flag per integrator
// parameter of the registry (--ambient, --max-depth, ...) to `cmd`.
void add_scene_options(CLI::App* cmd, SceneOptions* options);

// --detect-spheres (render only: `replace`) and --sphere-tolerance (docs/spheres.md).
struct SphereDetectionFlags {
  bool replace = false;
  double tolerance = SphereDetectionOptions().tolerance;
};
void add_sphere_detection_options(CLI::App* cmd, SphereDetectionFlags* flags, bool with_replace);

// The scene to load and the thread count, checked (UsageError naming the option).
SceneRequest scene_request(const SceneOptions& options, const SphereDetectionFlags& spheres);
SessionOptions session_options(const SceneOptions& options);
// A job with the scene options' camera, resolution, working space and background; the
// caller sets integrator, samples and geometry. Throws UsageError naming the option.
RenderJob base_job(const SceneOptions& options);
// --background's text, "L" or "R,G,B", each finite and >= 0; false for anything else.
bool parse_background(const std::string& text, Imath::V3f* radiance);

// `text` as a value of enum E, or a UsageError "OPTION TEXT: expected a, b or c".
template <NamedEnum E>
E parse_choice(const std::string& text, const std::string& option) {
  E value{};
  if (!parse_enum(text, &value))
    throw UsageError(option + " " + text + ": expected " + enum_choices<E>());
  return value;
}
// "X,Y,Z" (three finite numbers) -> the vector; UsageError naming `option` otherwise.
V3d parse_vector_option(const std::string& text, const std::string& option);
// "X0,Y0,X1,Y1" (four whole numbers, X0 < X1 and Y0 < Y1) -> the pixel rectangle; the session
// checks it against the image's size. UsageError naming `option` otherwise.
TileRect parse_region_option(const std::string& text, const std::string& option);
// "analytic", "mesh:3", ... -> SphereOptions; `option` names the flag in the error.
SphereOptions parse_spheres_option(const std::string& text, const std::string& option);
// An integrator name of the registry; `option` names the flag in the error.
const IntegratorInfo& parse_integrator_option(const std::string& text, const std::string& option);

// Prints each of the session's warnings as "prism: warning: FILE: ..." (the file named once).
void print_warnings(const std::string& scene_path, const std::vector<std::string>& warnings);

// Runs a command, turning what it throws into one line on stderr and an exit code: 2 for a
// UsageError or the job API's RequestError (reported as "--FIELD ..."), 1 for anything else
// (a scene that cannot be rendered, a file not written).
int run_reporting_errors(const std::function<int()>& command);

// 1234567 -> "1,234,567".
std::string with_commas(uint64_t n);
// Six significant digits, as `prism diff` and idiff print.
std::string format_error(double v);

}  // namespace prism
