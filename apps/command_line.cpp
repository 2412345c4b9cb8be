#include "apps/command_line.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>

#include "distributed/world.h"

namespace prism {

void add_scene_options(CLI::App* cmd, SceneOptions* o) {
  cmd->add_option("scene", o->scene_path, "Scene file (.gltf or .glb)")->required();
  cmd->add_option("--res", o->resolution,
                  "Image size WIDTHxHEIGHT (default 640x480, or 480 high at the camera's aspect "
                  "ratio or xmag/ymag)");
  add_scene_select_option(cmd, &o->scene);
  cmd->add_option("--camera", o->camera,
                  "Camera name or index (default: the first), or auto: one framing the scene's "
                  "bounds as the default camera does");
  cmd->add_option("--look-from", o->look_from, "X,Y,Z: move the camera there");
  cmd->add_option("--look-at", o->look_at, "X,Y,Z: turn the camera to look at this point");
  cmd->add_option("--up", o->up,
                  "X,Y,Z: the camera's up direction with --look-from/--look-at "
                  "(default 0,1,0)");
  cmd->add_option("--fov", o->fov, "Degrees: the camera's vertical field of view (perspective)");
  cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
      ->check(whole_number(0, 1024))
      ->capture_default_str();
  cmd->add_option("--working-space", o->working_space, enum_choices<WorkingSpace>(" | "))
      ->capture_default_str();
  cmd->add_option("--background", o->background,
                  "Uniform environment L or R,G,B: radiance of rays that leave the scene, which "
                  "also lights it (docs/lights.md)")
      ->capture_default_str();
  cmd->add_option("--environment", o->environment.path,
                  "Equirectangular environment map (.exr or .hdr) that lights the scene and is "
                  "seen where rays leave it (docs/lights.md)");
  cmd->add_option("--environment-rotation", o->environment.rotation_degrees,
                  "Turn the environment by DEGREES about +Y (counter-clockwise from above)")
      ->capture_default_str();
  cmd->add_option("--environment-intensity", o->environment.intensity,
                  "Scale the environment map's (or --background's) radiance")
      ->capture_default_str();
  cmd->add_flag("--hide-environment", o->environment.hidden,
                "Camera rays that leave the scene see black (alpha 0); the environment still "
                "lights the scene and shows in reflections");
  cmd->add_option("--brdf", o->brdf,
                  "Glossy lobe: gltf (glTF's GGX, Appendix B) | lecture (the lecture's Phong "
                  "(R.V)^n, docs/materials.md)")
      ->capture_default_str();
  // One flag per integrator parameter, from the integrators' own tables.
  // Integrators that share a parameter may differ in its range and default (whitted's
  // max-depth is 0 to 64, default 5; path's 0 to 1024, default 16): each says its own.
  for (const ParameterInfo* p : all_integrator_parameters()) {
    // "whitted: 0 to 64, default 5; path: 0 to 1024, default 16", integrators that agree
    // named together.
    std::vector<std::pair<std::string, std::string>> specs;  // names, their range and default
    for (const IntegratorInfo* info : integrator_registry())
      for (const ParameterInfo& own : info->parameters) {
        if (std::string(own.name) != p->name) continue;
        char text[96];
        if (own.max >= 1e30)
          std::snprintf(text, sizeof text, ">= %g, default %g", own.min, own.default_value);
        else
          std::snprintf(text, sizeof text, "%g to %g, default %g", own.min, own.max,
                        own.default_value);
        auto same = std::find_if(specs.begin(), specs.end(),
                                 [&](const auto& spec) { return spec.second == text; });
        if (same != specs.end())
          same->first += std::string(", ") + info->name;
        else
          specs.emplace_back(info->name, text);
      }
    std::string takers;
    for (const auto& [names, spec] : specs)
      takers += (takers.empty() ? "" : "; ") + names + ": " + spec;
    const std::string name = p->name;
    cmd->add_option_function<double>(
           "--" + name, [o, name](double v) { o->integrator_parameters[name] = v; },
           std::string(p->description) + " (" + takers + ")")
        ->type_name(p->type == ParameterType::integer ? "INT" : "FLOAT");
  }
  add_allow_external_paths_flag(cmd, &o->allow_external_paths);
  add_memory_limit_option(cmd, &o->memory_limit_gib);
}

CLI::Validator whole_number(int lo, int hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(text.c_str(), &end, 10);
        if (end == text.c_str() || *end != '\0' || errno != 0 || v < lo || v > hi)
          return "must be a whole number from " + range + ", not " + text;
        return "";
      },
      "whole number " + range);
}

void add_verbosity_flags(CLI::App* cmd, bool* quiet, bool* verbose, const std::string& quiet_help,
                         const std::string& verbose_help) {
  cmd->add_flag("-q,--quiet", *quiet, quiet_help);
  cmd->add_flag("-v,--verbose", *verbose, verbose_help);
}

void add_memory_limit_option(CLI::App* cmd, double* gib) {
  cmd->add_option("--memory-limit", *gib,
                  "GiB that loading the scene (geometry, texels, buffers) and the render's film "
                  "may allocate")
      ->check(CLI::Range(1.0 / 1024, 1024.0))
      ->capture_default_str();
}

void add_seed_option(CLI::App* cmd, int* seed, const std::string& help) {
  cmd->add_option("--seed", *seed, help)
      ->check(whole_number(0, RenderSettings::kMaxSeed))
      ->capture_default_str();
}

void add_scene_select_option(CLI::App* cmd, std::string* scene) {
  cmd->add_option("--scene", *scene,
                  "glTF scene to load, by name or index (default: the file's `scene`, else 0)");
}

void add_allow_external_paths_flag(CLI::App* cmd, bool* allow) {
  // Untrusted files must not read anything outside their own folder (docs/gltf.md).
  cmd->add_flag("--allow-external-paths", *allow,
                "Let the scene's buffers and images come from outside its folder");
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

SceneRequest scene_request(const SceneOptions& o, const SphereDetectionFlags& spheres) {
  if (!std::isfinite(spheres.tolerance) || spheres.tolerance <= 0.0 || spheres.tolerance >= 0.1)
    throw UsageError("--sphere-tolerance: must be a relative deviation above 0 and below 0.1");
  SceneRequest request;
  request.path = o.scene_path;
  request.scene = o.scene;
  request.allow_external_paths = o.allow_external_paths;
  request.detect_spheres = spheres.replace;
  request.sphere_detection.tolerance = spheres.tolerance;
  return request;
}

SessionOptions session_options(const SceneOptions& o) {
  SessionOptions options;
  options.threads = o.threads;
  options.memory_budget_bytes =
      static_cast<uint64_t>(o.memory_limit_gib * double(uint64_t{1} << 30));
  return options;
}

bool parse_background(const std::string& text, Imath::V3f* radiance) {
  std::vector<float> v;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    const std::string piece = text.substr(start, end - start);
    char* stop = nullptr;
    const float c = std::strtof(piece.c_str(), &stop);
    if (piece.empty() || *stop != '\0' || !std::isfinite(c) || c < 0.0f) return false;
    v.push_back(c);
    start = end + 1;
  }
  if (v.size() == 1) v.assign(3, v[0]);
  if (v.size() != 3) return false;
  *radiance = Imath::V3f(v[0], v[1], v[2]);
  return true;
}

RenderJob base_job(const SceneOptions& o) {
  RenderJob job;
  job.working_space = parse_choice<WorkingSpace>(o.working_space, "--working-space");
  job.brdf = parse_choice<BrdfModel>(o.brdf, "--brdf");
  if (!o.resolution.empty() && !parse_resolution(o.resolution, &job.width, &job.height))
    throw UsageError("--res " + o.resolution + ": expected WIDTHxHEIGHT, each 1 to " +
                     std::to_string(kMaxImageSide));
  if (!parse_background(o.background, &job.background))
    throw UsageError("--background " + o.background +
                     ": expected a radiance L or R,G,B, each finite and >= 0");
  if (!std::isfinite(o.environment.intensity) || o.environment.intensity < 0.0f)
    throw UsageError("--environment-intensity: must be a finite number >= 0");
  if (!std::isfinite(o.environment.rotation_degrees))
    throw UsageError("--environment-rotation: must be a finite angle in degrees");
  job.environment = o.environment;
  if (o.camera == "auto")
    job.frame_scene = true;
  else
    job.camera = o.camera;
  if (!o.look_from.empty() || !o.look_at.empty() || !o.up.empty() || o.fov != 0.0) {
    CameraPlacement place;
    if (!o.look_from.empty()) place.look_from = parse_vector_option(o.look_from, "--look-from");
    if (!o.look_at.empty()) place.look_at = parse_vector_option(o.look_at, "--look-at");
    if (!o.up.empty()) place.up = parse_vector_option(o.up, "--up");
    if (o.fov != 0.0) {
      if (!(o.fov > 0.0 && o.fov < 180.0))
        throw UsageError("--fov " + format_error(o.fov) +
                         ": must be above 0 and below 180 degrees");
      place.yfov_degrees = o.fov;
    }
    job.placement = place;
  }
  job.integrator_parameters = o.integrator_parameters;
  return job;
}

V3d parse_vector_option(const std::string& text, const std::string& option) {
  double v[3] = {};
  size_t at = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t end = i < 2 ? text.find(',', at) : text.size();
    const std::string part = end == std::string::npos ? std::string() : text.substr(at, end - at);
    char* stop = nullptr;
    v[i] = std::strtod(part.c_str(), &stop);
    if (part.empty() || *stop != '\0' || !std::isfinite(v[i]) || (i == 2 && at > text.size()))
      throw UsageError(option + " " + text + ": expected X,Y,Z, three finite numbers");
    at = end + 1;
  }
  return V3d(v[0], v[1], v[2]);
}

TileRect parse_region_option(const std::string& text, const std::string& option) {
  long v[4] = {};
  size_t at = 0;
  for (int i = 0; i < 4; ++i) {
    const size_t end = i < 3 ? text.find(',', at) : text.size();
    const std::string part =
        end == std::string::npos || at > text.size() ? std::string() : text.substr(at, end - at);
    char* stop = nullptr;
    errno = 0;
    v[i] = std::strtol(part.c_str(), &stop, 10);
    if (part.empty() || *stop != '\0' || errno != 0 || v[i] < 0 || v[i] > kMaxImageSide)
      throw UsageError(option + " " + text + ": expected X0,Y0,X1,Y1, four whole numbers of " +
                       "pixels from 0 to " + std::to_string(kMaxImageSide));
    at = end + 1;
  }
  if (v[0] >= v[2] || v[1] >= v[3])
    throw UsageError(option + " " + text + ": expected X0 < X1 and Y0 < Y1 (X1 and Y1 are the " +
                     "first column and row after the region)");
  return TileRect{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]),
                  static_cast<int>(v[3])};
}

SphereOptions parse_spheres_option(const std::string& text, const std::string& option) {
  SphereOptions spheres;
  std::string error;
  if (!parse_sphere_options(text, &spheres, &error))
    throw UsageError(option + " " + text + ": " + error);
  return spheres;
}

const IntegratorInfo& parse_integrator_option(const std::string& text, const std::string& option) {
  const IntegratorInfo* info = find_integrator(text);
  if (!info) throw UsageError(option + " " + text + ": expected " + integrator_choices());
  return *info;
}

void print_warnings(const std::string& scene_path, const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings)
    std::fprintf(stderr, "prism: warning: %s: %s\n", scene_path.c_str(), w.c_str());
}

int run_reporting_errors(const std::function<int()>& command) {
  // Under mpirun, a usage error is the same on every rank (same arguments, same scene): rank
  // 0 reports it and all exit alike. Anything else may be one rank's alone, and its peers
  // would wait for it in the next collective: it ends them all.
  // Asked after the command: it is what makes the world (the session does).
  const auto quiet = [] {
    const distributed::World* world = distributed::World::existing();
    return world && !world->root();
  };
  try {
    return command();
  } catch (const UsageError& e) {
    if (!quiet()) std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 2;
  } catch (const RequestError& e) {
    if (!quiet()) std::fprintf(stderr, "prism: error: --%s %s\n", e.field.c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    const distributed::World* world = distributed::World::existing();
    if (world && world->size() > 1) world->abort(e.what());
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 1;
  }
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
