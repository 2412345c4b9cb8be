#include "session/session.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "distributed/frame_split.h"
#include "renderer/camera.h"
#include "renderer/image/exr_file.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/oiio_module.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"

namespace prism {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string format_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// "max-depth" -> "maxDepth": metadata keys are camel case, as OpenEXR's own are.
std::string camel_case(const std::string& name) {
  std::string out;
  bool upper = false;
  for (char c : name) {
    if (c == '-') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

// Bytes a render of `film` allocates for its film and per-pixel sample state, with the
// sample-count image and a reference of the same size: an upper bound, checked before any
// of it is made.
uint64_t film_bytes(const RenderSettings& film, bool with_reference) {
  const uint64_t pixels = static_cast<uint64_t>(film.width) * static_cast<uint64_t>(film.height);
  uint64_t per_pixel = sizeof(float) * 4;  // the image
  per_pixel += sizeof(float) * 4;          // the sample-count image or a preview
  if (with_reference) per_pixel += 2 * sizeof(PixelSums) + sizeof(float) * 4;
  if (film.adaptive())
    per_pixel += 2 * sizeof(PixelSums) + sizeof(uint8_t) + sizeof(uint32_t) + sizeof(float);
  return pixels * per_pixel;
}

// The reference image of a job, refused unless it is a regular file: reading a device or a
// FIFO would never end.
Image read_reference(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw RequestError("reference", path + ": no such file");
  if (!S_ISREG(st.st_mode)) throw RequestError("reference", path + ": not a regular file");
  try {
    return read_exr(path);
  } catch (const std::exception& e) {
    throw RequestError("reference", e.what());
  }
}

// An environment map, refused unless it is a regular OpenEXR or Radiance HDR file of at most
// `max_pixels`: any other format would reach a decoder Prism does not vouch for with
// untrusted input, and a device or a FIFO would never end.
Image read_environment_map(const std::string& path, int64_t max_pixels) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw RequestError("environment", path + ": no such file");
  if (!S_ISREG(st.st_mode)) throw RequestError("environment", path + ": not a regular file");
  if (is_exr_file(path)) return read_exr_file(path, max_pixels);
  char magic[2] = {0, 0};
  std::FILE* f = std::fopen(path.c_str(), "rb");
  const bool hdr = f && std::fread(magic, 1, 2, f) == 2 && magic[0] == '#' && magic[1] == '?';
  if (f) std::fclose(f);
  if (!hdr)
    throw RequestError("environment",
                       path +
                           ": not an environment map (expected an OpenEXR or Radiance .hdr "
                           "file)");
  return oiio_module(path).read_image(path, max_pixels);
}

}  // namespace

bool parse_resolution(const std::string& text, int* width, int* height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    return false;
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide) return false;
  *width = w;
  *height = h;
  return true;
}

Session::Session(const SceneRequest& request, const SessionOptions& options)
    : request_(request),
      options_(options),
      world_(options.distribute_frames ? &distributed::World::process() : nullptr),
      arena_(options.arena
                 ? options.arena
                 : std::make_shared<tbb::task_arena>(
                       options.threads > 0 ? options.threads : int{tbb::task_arena::automatic})) {
  const auto start = Clock::now();
  LoadOptions load;
  load.allow_external_paths = request.allow_external_paths;
  load.scene = request.scene;
  load.memory_limit = static_cast<std::size_t>(options.memory_budget_bytes);
  arena_->execute([&] {
    try {
      scene_ = load_gltf(request.path, load);
    } catch (const SceneSelectionError& e) {
      throw RequestError("scene", request.scene + ": " + e.what());
    }
    file_cameras_ = scene_.cameras.size();
    if (request.add_defaults) add_defaults();
    if (request.detect_spheres) {
      const std::vector<SphereCandidate> candidates =
          find_sphere_meshes(scene_, request.sphere_detection);
      // Described before the replacement removes their instances.
      for (const SphereCandidate& c : candidates)
        sphere_report_.push_back(c.blocker == SphereReplaceBlocker::none
                                     ? "replaced " + describe_sphere_candidate(scene_, c) +
                                           " by an analytic sphere"
                                     : "kept " + describe_sphere_candidate(scene_, c) +
                                           " as a mesh: " + to_string(c.blocker));
      const size_t replaced = replace_sphere_meshes(&scene_, candidates).size();
      sphere_report_.push_back(std::to_string(replaced) + " mesh" + (replaced == 1 ? "" : "es") +
                               " replaced");
    }
  });
  load_seconds_ = seconds_since(start);
}

Session::~Session() {
  // The render scene's Embree objects are released on the session's threads too.
  arena_->execute([&] { built_.scene.reset(); });
}

uint64_t Session::memory_bytes() const {
  uint64_t bytes = description_bytes(scene_);
  if (device_) bytes += static_cast<uint64_t>(std::max(0LL, device_->bytes_in_use()));
  return bytes;
}

void Session::add_defaults() {
  if (defaults_added_) return;
  add_scene_defaults(&scene_);
  defaults_added_ = true;
}

const ColourPipeline& Session::colour(WorkingSpace space) {
  std::unique_ptr<ColourPipeline>& c = colours_[space];
  if (!c) c = std::make_unique<ColourPipeline>(space);
  return *c;
}

int Session::camera_index(const std::string& wanted) {
  add_defaults();
  return find_camera(wanted);
}

CameraDescription Session::camera(const RenderJob& job) {
  add_defaults();
  int index = 0;
  return placed_camera(job, &index);
}

CameraDescription Session::placed_camera(const RenderJob& job, int* index) const {
  if (job.frame_scene && !job.camera.empty())
    throw RequestError("camera", job.camera +
                                     ": a file's camera or the one framing the scene, "
                                     "not both");
  *index = job.frame_scene ? -1 : find_camera(job.camera);
  CameraDescription camera = job.frame_scene ? framing_camera(scene_, "auto")
                                             : scene_.cameras[static_cast<size_t>(*index)];
  if (!job.placement) return camera;
  const CameraPlacement& place = *job.placement;
  const M44d& m = camera.camera_to_world;
  const V3d position(m[3][0], m[3][1], m[3][2]);
  const V3d forward = -V3d(m[2][0], m[2][1], m[2][2]).normalized();
  const V3d eye = place.look_from.value_or(position);
  const V3d target = place.look_at ? *place.look_at : eye + forward;
  const V3d up = place.up.value_or(V3d(0, 1, 0));
  const V3d view = target - eye;
  const auto text = [](const V3d& v) {
    return format_number(v.x) + "," + format_number(v.y) + "," + format_number(v.z);
  };
  if (!(view.length() > 0.0))
    throw RequestError("look-at", text(target) +
                                      ": is where the camera stands; look at another "
                                      "point");
  if (!(up.length() > 0.0)) throw RequestError("up", "0,0,0: has no direction");
  if (view.normalized().cross(up.normalized()).length() < 1e-6)
    throw RequestError("up", text(up) + ": is along the direction of view; give another --up");
  camera.camera_to_world = look_at(eye, target, up);
  if (place.yfov_degrees) {
    const double degrees = *place.yfov_degrees;
    if (camera.projection != Projection::perspective)
      throw RequestError("fov", "camera '" + camera.name +
                                    "' is orthographic: it has no field "
                                    "of view");
    if (!(degrees > 0.0 && degrees < 180.0))
      throw RequestError("fov", format_number(degrees) + ": must be above 0 and below 180 degrees");
    camera.yfov = degrees * std::numbers::pi / 180.0;
  }
  if (!job.frame_scene) camera.name += " (moved)";
  return camera;
}

int Session::find_camera(const std::string& wanted) const {
  if (wanted.empty()) return 0;
  for (size_t i = 0; i < scene_.cameras.size(); ++i)
    if (scene_.cameras[i].name == wanted) return static_cast<int>(i);
  char* end = nullptr;
  const long index = std::strtol(wanted.c_str(), &end, 10);
  if (end != wanted.c_str() && *end == '\0' && index >= 0 &&
      index < static_cast<long>(scene_.cameras.size()))
    return static_cast<int>(index);
  // The default camera (the last, when added) is not the file's: it cannot be asked for.
  if (file_cameras_ == 0)
    throw RequestError("camera", wanted + ": " + scene_.source_path +
                                     " has no cameras; leave --camera out for the default one "
                                     "that frames the scene, or use --camera auto");
  std::string names;
  for (size_t i = 0; i < file_cameras_; ++i)
    names += (i ? ", " : "") + std::to_string(i) +
             (scene_.cameras[i].name.empty() ? " (unnamed)" : " '" + scene_.cameras[i].name + "'");
  throw RequestError("camera", wanted + ": " + scene_.source_path + " has no such camera; it has " +
                                   std::to_string(file_cameras_) +
                                   (file_cameras_ == 1 ? " camera: " : " cameras: ") + names +
                                   " (a name or an index), or use auto");
}

namespace {

// The film's sampling fields, which a command line's parser checks before the job exists
// but a job built in code (Python) does not.
void check_sampling(const RenderSettings& film) {
  const auto whole = [](const char* field, int v) {
    if (v < 1 || v > kMaxSamplesPerPixel)
      throw RequestError(field, std::to_string(v) + ": expected a whole number from 1 to " +
                                    std::to_string(kMaxSamplesPerPixel));
  };
  whole("spp", film.spp);
  whole("min-spp", film.min_spp);
  if (!std::isfinite(film.target_error) || film.target_error < 0.0f)
    throw RequestError("target-error", format_number(film.target_error) +
                                           ": expected a finite number > 0 (or 0: off)");
  if (!std::isfinite(film.time_limit_seconds) || film.time_limit_seconds < 0.0)
    throw RequestError("time-limit", format_number(film.time_limit_seconds) +
                                         ": expected a finite number of seconds > 0 (or 0: none)");
  if (film.error_goal != ErrorGoal::pixel && !(film.target_error > 0.0f))
    throw RequestError("error-goal", std::string(to_string(film.error_goal)) +
                                         ": bounds a --target-error, and none is set");
  // Rounded up to whole camera-ray packets by the renderer; past 4096 a tile is the image.
  if (film.tile_size < 1 || film.tile_size > 4096)
    throw RequestError("tile-size", std::to_string(film.tile_size) + ": expected 1 to 4096");
}

// The light and camera fields, for the same reason.
void check_light_and_camera(const RenderJob& job) {
  const Imath::V3f& b = job.background;
  for (float v : {b.x, b.y, b.z})
    if (!std::isfinite(v) || v < 0.0f)
      throw RequestError("background", format_number(v) + ": expected a radiance, finite and >= 0");
  const EnvironmentRequest& env = job.environment;
  if (!std::isfinite(env.intensity) || env.intensity < 0.0f)
    throw RequestError("environment-intensity",
                       format_number(env.intensity) + ": expected a finite number >= 0");
  if (!std::isfinite(env.rotation_degrees))
    throw RequestError("environment-rotation", format_number(env.rotation_degrees) +
                                                   ": expected a finite angle in degrees");
  if (!job.placement) return;
  const CameraPlacement& place = *job.placement;
  const auto finite = [](const char* field, const std::optional<V3d>& v) {
    if (v && !(std::isfinite(v->x) && std::isfinite(v->y) && std::isfinite(v->z)))
      throw RequestError(field, "expected three finite numbers X,Y,Z");
  };
  finite("look-from", place.look_from);
  finite("look-at", place.look_at);
  finite("up", place.up);
  if (place.yfov_degrees && !(*place.yfov_degrees > 0.0 && *place.yfov_degrees < 180.0))
    throw RequestError(
        "fov", format_number(*place.yfov_degrees) + ": expected above 0 and below 180 degrees");
}

}  // namespace

Session::Plan Session::plan(const RenderJob& job) const {
  Plan p;
  p.integrator = find_integrator(job.integrator);
  if (!p.integrator)
    throw RequestError("integrator", job.integrator + ": expected " + integrator_choices());
  try {
    p.parameters = ParameterValues(p.integrator->parameters, job.integrator_parameters);
  } catch (const ParameterError& e) {
    std::string takes;
    for (const ParameterInfo& info : p.integrator->parameters)
      takes += std::string(takes.empty() ? "" : ", ") + info.name;
    throw RequestError(e.parameter, std::string(e.what()) == "no such parameter"
                                        ? std::string("the ") + p.integrator->name +
                                              " integrator has no such parameter (it takes " +
                                              (takes.empty() ? "none" : takes) + ")"
                                        : e.what());
  }
  check_sampling(job.film);
  check_light_and_camera(job);
  if (ranks() > 1) {
    // Adaptive rounds and per-pass errors need every rank's pixels between passes; one
    // frame over MPI gathers once, at the end.
    const std::string refused =
        ": not supported with " + std::to_string(ranks()) + " MPI ranks yet";
    if (job.film.target_error > 0.0f)
      throw RequestError("target-error", format_number(job.film.target_error) + refused);
    if (job.film.time_limit_seconds > 0.0)
      throw RequestError("time-limit", format_number(job.film.time_limit_seconds) + refused);
    if (!job.reference_path.empty()) throw RequestError("reference", job.reference_path + refused);
  }
  p.camera_description = placed_camera(job, &p.camera);
  p.film = film_for(job, p.camera_description, &p.warnings);
  const uint64_t bytes = film_bytes(p.film, !job.reference_path.empty());
  if (bytes > options_.memory_budget_bytes)
    throw RequestError(
        "res", std::to_string(p.film.width) + "x" + std::to_string(p.film.height) +
                   " needs about " + format_number(static_cast<double>(bytes) / (1 << 30)) +
                   " GiB of film and sample buffers, more than the memory budget of " +
                   format_number(static_cast<double>(options_.memory_budget_bytes) / (1 << 30)) +
                   " GiB");
  return p;
}

std::vector<std::string> Session::job_warnings(const RenderJob& job) {
  add_defaults();
  std::vector<std::string> warnings;
  int index = 0;
  film_for(job, placed_camera(job, &index), &warnings);
  return warnings;
}

RenderSettings Session::film_for(const RenderJob& job, const CameraDescription& camera,
                                 std::vector<std::string>* warnings) const {
  RenderSettings film = job.film;
  if (job.width > 0 || job.height > 0) {
    if (job.width < 1 || job.height < 1 || job.width > kMaxImageSide || job.height > kMaxImageSide)
      throw RequestError("res", std::to_string(job.width) + "x" + std::to_string(job.height) +
                                    ": expected WIDTHxHEIGHT, each 1 to " +
                                    std::to_string(kMaxImageSide));
    film.width = job.width;
    film.height = job.height;
  } else {
    film.width = 640;
    film.height = 480;
    // An orthographic camera's aspect is xmag / ymag, as a perspective camera's is its
    // aspectRatio.
    const double aspect = camera.projection == Projection::orthographic ? camera.xmag / camera.ymag
                                                                        : camera.aspect_ratio;
    if (aspect > 0.0) {
      // In double, and bounded before it becomes an int: a file's aspect ratio is not to
      // be trusted with the size of the film.
      const double width = std::round(480.0 * aspect);
      if (!(width <= kMaxImageSide))
        throw RequestError("res", "camera '" + camera.name + "' of " + scene_.source_path +
                                      " has aspect ratio " + format_number(aspect) +
                                      ", which would make the image " + format_number(width) +
                                      " pixels wide (at most " + std::to_string(kMaxImageSide) +
                                      "): give the resolution explicitly");
      film.width = std::max(1, static_cast<int>(width));
    }
  }
  if (film.has_region()) {
    const TileRect& r = film.region;
    if (r.x0 < 0 || r.y0 < 0 || r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > film.width ||
        r.y1 > film.height)
      throw RequestError(
          "region",
          std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," +
              std::to_string(r.y1) +
              ": expected X0,Y0,X1,Y1 with 0 <= X0 < X1 <= " + std::to_string(film.width) +
              " and 0 <= Y0 < Y1 <= " + std::to_string(film.height) + " (the image's size)");
  }
  if (camera.projection == Projection::orthographic) {
    const OrthographicFit fit = fit_orthographic(camera, film.width, film.height);
    if (fit.xmag_changed)
      warnings->push_back("camera '" + camera.name + "' is orthographic with xmag " +
                          format_number(camera.xmag) + " and ymag " + format_number(camera.ymag) +
                          ", a " + format_number(camera.xmag / camera.ymag) +
                          ":1 view, but the image is " + std::to_string(film.width) + "x" +
                          std::to_string(film.height) + ": " + describe_fit(camera, fit) +
                          " so that pixels stay square");
  }
  return film;
}

Session::EnvironmentKey Session::environment_key(const RenderJob& job) {
  const EnvironmentRequest& e = job.environment;
  return std::make_tuple(e.path, e.rotation_degrees, e.intensity, e.hidden, job.background,
                         job.working_space);
}

const Environment& Session::environment(const RenderJob& job) {
  add_defaults();
  const EnvironmentRequest& e = job.environment;
  const EnvironmentKey key = environment_key(job);
  if (environment_.made && environment_.key == key) return environment_.environment;
  if (!std::isfinite(e.intensity) || e.intensity < 0.0f)
    throw RequestError("environment-intensity",
                       format_number(e.intensity) + ": must be a finite number >= 0");
  if (!std::isfinite(e.rotation_degrees))
    throw RequestError("environment-rotation", "must be a finite angle in degrees");
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(job.background[k]) || job.background[k] < 0.0f)
      throw RequestError("background",
                         format_number(job.background[k]) + ": must be a finite radiance >= 0");
  Environment made;
  if (!e.path.empty()) {
    // What the map costs while it is made: read as RGBA floats, kept as RGB with two
    // sampling distributions (complete, and beside a BSDF sample), each a cumulative table
    // in double and a guide table of indices, and the two weight tables they are built from.
    constexpr int64_t kBytesPerTexel = 16 + 12 + 2 * (8 + 8) + 2 * 8;
    const int64_t max_pixels = std::min<int64_t>(
        int64_t{1} << 30, static_cast<int64_t>(options_.memory_budget_bytes) / kBytesPerTexel);
    Image map;
    try {
      map = read_environment_map(e.path, max_pixels);
    } catch (const RequestError&) {
      throw;
    } catch (const std::exception& error) {
      throw RequestError("environment", error.what());
    }
    // Maps are scene-linear Rec.709, as glTF's colours are.
    if (job.working_space != WorkingSpace::linear_rec709) {
      const ColourPipeline& pipeline = colour(job.working_space);
      for (size_t i = 0; i < map.rgba.size(); i += 4) {
        const C3f c =
            pipeline.from_linear_rec709(C3f(map.rgba[i], map.rgba[i + 1], map.rgba[i + 2]));
        map.rgba[i] = c.x;
        map.rgba[i + 1] = c.y;
        map.rgba[i + 2] = c.z;
      }
    }
    try {
      made = Environment(map, e.rotation_degrees * std::numbers::pi_v<float> / 180.0f, e.intensity);
    } catch (const std::invalid_argument& error) {
      throw RequestError("environment", e.path + ": " + error.what());
    }
    made.set_hidden_from_camera(e.hidden);
  } else if (job.background.x > 0.0f || job.background.y > 0.0f || job.background.z > 0.0f) {
    made = Environment(job.background * e.intensity);
    made.set_hidden_from_camera(e.hidden);
  } else if (scene_.default_sky) {
    // The default sky lights a file that has no light of its own, and is never its backdrop.
    made = gradient_sky(scene_.default_sky->zenith, scene_.default_sky->nadir);
    made.set_hidden_from_camera(true);
  }
  environment_.environment = made;
  environment_.key = key;
  environment_.made = true;
  return environment_.environment;
}

void Session::check(const RenderJob& job) {
  add_defaults();
  const Plan p = plan(job);
  environment(job);
  if (!job.reference_path.empty()) {
    const Image reference = read_reference(job.reference_path);
    if (reference.width != p.film.width || reference.height != p.film.height)
      throw RequestError("reference",
                         job.reference_path + " is " + std::to_string(reference.width) + "x" +
                             std::to_string(reference.height) + " but the render is " +
                             std::to_string(p.film.width) + "x" + std::to_string(p.film.height));
  }
}

BuildQuality Session::build_quality(const RenderJob& job) {
  if (job.build_quality != BuildQuality::automatic) return job.build_quality;
  add_defaults();
  const Plan p = plan(job);
  const double bounces =
      takes_parameter(*p.integrator, "max-depth") ? p.parameters.integer("max-depth") : 0.0;
  const double rays =
      static_cast<double>(p.film.width) * p.film.height * p.film.spp * (1.0 + bounces);
  double primitives = static_cast<double>(scene_.spheres.size());
  for (const Mesh& mesh : scene_.meshes)
    for (const Primitive& primitive : mesh.primitives)
      primitives += static_cast<double>(primitive.indices.size() / 3);
  return automatic_build_quality(rays, primitives);
}

const RenderScene& Session::render_scene(const RenderJob& job, double* build_seconds) {
  return *render_scene(job, false, build_seconds);
}

std::shared_ptr<const RenderScene> Session::render_scene(const RenderJob& job, bool beside_running,
                                                         double* build_seconds) {
  // Rebased per scene, or per camera for a scene too large to share one origin
  // (rebasing_origin): jobs from every camera of a small scene share one build.
  const CameraDescription view = camera(job);
  if (!bounds_) bounds_ = scene_bounds(scene_);  // the geometry never changes after loading
  const V3d origin = rebasing_origin(*bounds_, view);
  // The default key light stands over the shoulder of whichever camera renders (moved by
  // --look-from or framing the scene as it may be), so the scene is rebuilt when it turns.
  std::array<double, 3> key_light{0.0, 0.0, 0.0};
  std::optional<Light> default_light;
  if (scene_.default_lighting) {
    default_light = default_key_light(view);
    const V3d& d = default_light->direction;
    key_light = {d.x, d.y, d.z};
  }
  const BuildQuality quality = build_quality(job);
  auto key =
      std::make_tuple(to_string(job.spheres), job.robust, quality, job.working_space, key_light,
                      std::array<double, 3>{origin.x, origin.y, origin.z}, job.brdf);
  if (build_seconds) *build_seconds = 0.0;
  const EnvironmentKey lighting = environment_key(job);
  const bool reusable = built_.scene && built_.key == key;
  if (reusable && built_.environment_key == lighting) return built_.scene;
  // Either a rebuild or another environment (the render scene keeps its own copy): neither
  // may happen under a prepared render that holds the scene (use_count > 1).
  if (beside_running && built_.scene && built_.scene.use_count() > 1) return nullptr;
  const Environment& sky = environment(job);
  if (reusable) {
    // Another environment needs no new BVH: only the light choices that weigh it change.
    built_.scene->set_environment(sky);
    built_.environment_key = lighting;
    return built_.scene;
  }
  if (default_light) scene_.lights = {*default_light};
  const ColourPipeline& colours = colour(job.working_space);
  const auto start = Clock::now();
  arena_->execute([&] {
    // Freed first (unless a running render still holds it): two BVHs at once would double
    // the peak memory.
    built_.scene.reset();
    GeometryOptions geometry;
    geometry.spheres = job.spheres;
    geometry.robust = job.robust;
    geometry.build_quality = quality;
    // Rebased near the camera and the geometry: hits and lights stay near 0 in float
    // wherever the scene sits in the world and wherever the camera stands
    // (docs/stress-shading.md, huge coordinates; docs/accuracy.md, far cameras).
    geometry.world_origin = origin;
    if (!device_) device_ = std::make_shared<EmbreeDevice>();
    built_.scene = std::make_shared<RenderScene>(device_, scene_, geometry, colours, sky, job.brdf);
  });
  built_.key = key;
  built_.environment_key = lighting;
  if (build_seconds) *build_seconds = seconds_since(start);
  return built_.scene;
}

Session::Prepared::~Prepared() = default;

Session::Prepared Session::prepare(const RenderJob& job) {
  return std::move(*prepare(job, false));
}

std::optional<Session::Prepared> Session::prepare_beside_running(const RenderJob& job) {
  return prepare(job, true);
}

std::optional<Session::Prepared> Session::prepare(const RenderJob& job, bool beside_running) {
  add_defaults();
  Prepared p;
  p.job_ = job;
  p.plan_ = plan(job);
  if (!job.reference_path.empty()) {
    check(job);
    p.reference_ = read_reference(job.reference_path);
  }
  RenderOutput& out = p.out_;
  out.integrator = p.plan_.integrator->name;
  out.parameters = p.plan_.parameters;
  out.film = p.plan_.film;
  out.warnings = p.plan_.warnings;
  out.camera_index = p.plan_.camera;
  out.camera_name = p.plan_.camera_description.name;
  p.scene_ = render_scene(job, beside_running, &out.build_seconds);
  if (!p.scene_) return std::nullopt;
  p.built_at_ = std::get<2>(built_.key);
  out.geometry = p.scene_->geometry().statistics();
  out.features = p.scene_->features();
  out.lights = p.scene_->lights().size();
  p.integrator_ = p.plan_.integrator->make(p.plan_.parameters);
  p.camera_.emplace(
      p.scene_->camera(p.plan_.camera_description, p.plan_.film.width, p.plan_.film.height));
  return p;
}

RenderOutput Session::render(const RenderJob& job, const JobCallbacks& callbacks) {
  return run(prepare(job), callbacks);
}

RenderOutput Session::run(Prepared prepared, const JobCallbacks& callbacks) {
  const RenderJob& job = prepared.job_;
  const Plan& p = prepared.plan_;
  const Image& reference = prepared.reference_;
  const RenderScene& built = *prepared.scene_;
  const Integrator& integrator = *prepared.integrator_;
  const Camera& camera = *prepared.camera_;
  RenderOutput out = std::move(prepared.out_);

  RenderCallbacks render_callbacks;
  render_callbacks.progress = callbacks.progress;
  render_callbacks.cancel = callbacks.cancel;
  render_callbacks.checkpoint_due = callbacks.checkpoint_due;
  render_callbacks.stop = callbacks.stop;
  render_callbacks.save = callbacks.save_checkpoint;
  render_callbacks.resume = callbacks.resume;
  render_callbacks.pass_seconds = callbacks.pass_seconds;
  if (!job.reference_path.empty()) {
    render_callbacks.after_pass = [&](int samples, const Image& so_far) {
      // A region is measured where it was rendered.
      const ImageError e = p.film.has_region() ? compare_images(crop(so_far, p.film.region),
                                                                crop(reference, p.film.region))
                                               : compare_images(so_far, reference);
      const PassError pass{samples, e.overall.rmse, e.overall.relmse};
      out.pass_errors.push_back(pass);
      if (callbacks.pass_error) callbacks.pass_error(pass);
    };
  }
  if (ranks() == 1) {
    arena_->execute([&] {
      out.result = prism::render(integrator, RenderContext{built, camera, p.film}, &out.image,
                                 render_callbacks);
    });
  } else {
    // From the shared counter's creation to the gather every rank must take part: a rank
    // that threw here would leave the others waiting forever, so it ends them all instead.
    world_->all_or_abort([&] {
      distributed::FrameSplit split(*world_, p.film);
      render_callbacks.claim_tile = [&] { return split.claim(); };
      // Rank 0's bar follows the tiles handed out to every rank, not its own share.
      render_callbacks.progress = nullptr;
      if (callbacks.progress && world_->root())
        render_callbacks.progress = [&](int, int total) {
          callbacks.progress(static_cast<int>(split.claimed_anywhere()), total);
        };
      arena_->execute([&] {
        out.result = prism::render(integrator, RenderContext{built, camera, p.film}, &out.image,
                                   render_callbacks);
      });
      out.frame_split = split.gather(&out.image, &out.result);
    });
  }
  out.resumed_samples = out.result.resumed_samples;
  out.metadata = metadata(job, p, prepared.built_at_, camera, out);
  // A scene rebuilt meanwhile is released here, on the session's threads as every other.
  arena_->execute([&] { prepared.scene_.reset(); });
  return out;
}

RenderMetadata Session::metadata(const RenderJob& job, const Plan& p, BuildQuality built_at,
                                 const Camera& camera, const RenderOutput& out) const {
  RenderMetadata m;
  m.integrator = out.integrator;
  m.spp = p.film.spp;
  m.render_seconds = out.result.seconds;
  if (p.film.has_region()) m.region = p.film.region;
  m.world_to_camera = camera.world_to_camera();
  m.world_to_ndc = camera.world_to_ndc();
  m.scene_path = request_.path;
  const M44d& placed = p.camera_description.camera_to_world;
  m.extra = {{"camera", out.camera_name},
             {"cameraPosition", format_number(placed[3][0]) + "," + format_number(placed[3][1]) +
                                    "," + format_number(placed[3][2])},
             {"spheres", to_string(job.spheres)},
             // As built: the key of the render scene this job rendered settles `auto`.
             {"buildQuality", to_string(built_at)},
             {"brdf", to_string(job.brdf)},
             {"robust", job.robust ? "1" : "0"}};
  for (const ParameterInfo& info : p.integrator->parameters)
    m.extra.push_back({camel_case(info.name), format_number(p.parameters.real(info.name))});
  for (const EnumName<RayKind>& kind : kRayKindNames) {
    std::string key = std::string("rays-") + kind.name;
    m.extra.push_back({camel_case(key), std::to_string(out.result.rays[kind.value])});
  }
  m.extra.push_back({"discardedSamples", std::to_string(out.result.rays.discarded_samples)});
  const RenderSettings& s = p.film;
  if (s.seed != 0) m.extra.push_back({"sampleSeed", std::to_string(s.seed)});
  if (s.adaptive()) {  // docs/sampling.md: spp above is then the most a pixel took
    m.extra.insert(m.extra.end(),
                   {{"adaptiveTargetError", format_number(s.target_error)},
                    {"adaptiveTimeLimit", format_number(s.time_limit_seconds)},
                    {"adaptiveMinSpp", std::to_string(s.min_spp)},
                    {"adaptiveErrorGoal", to_string(s.error_goal)},
                    {"adaptiveRounds", std::to_string(out.result.rounds)},
                    {"adaptiveTimeLimitReached", out.result.time_limit_reached ? "1" : "0"},
                    {"samplesTaken", std::to_string(out.result.rays[RayKind::camera])},
                    {"meanSpp", format_number(out.result.mean_spp(s))}});
  }
  // A resumed render's image is the same as an uninterrupted one's; this says it was not.
  if (out.resumed_samples > 0)
    m.extra.push_back({"resumedSamples", std::to_string(out.resumed_samples)});
  const auto features = feature_metadata(out.features);
  m.extra.insert(m.extra.end(), features.begin(), features.end());
  if (!out.pass_errors.empty()) {
    std::string rmse, relmse;
    for (const PassError& e : out.pass_errors) {
      rmse += (rmse.empty() ? "" : ",") + format_number(e.rmse);
      relmse += (relmse.empty() ? "" : ",") + format_number(e.relmse);
    }
    m.extra.insert(m.extra.end(),
                   {{"reference", job.reference_path},
                    {"referenceRMSE", format_number(out.pass_errors.back().rmse)},
                    {"referenceRelMSE", format_number(out.pass_errors.back().relmse)},
                    {"referenceRMSEPerPass", rmse},
                    {"referenceRelMSEPerPass", relmse}});
  }
  return m;
}

}  // namespace prism
