// The Python module: the job API (session/session.h) as Python objects, so a notebook loads a
// scene once and renders it with any integrator and option in a loop, as Mitsuba 3's Python
// API does. Every check is the session's own, so Python accepts and refuses exactly what
// `prism render` and job files do, and its exceptions carry the same one-line messages.
// Images are NumPy arrays of shape (height, width, 4), scene-linear RGBA in the working space.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "integrators/registry.h"
#include "renderer/enum_names.h"
#include "renderer/geometry/sphere_geometry.h"
#include "renderer/image/image_metrics.h"
#include "renderer/version.h"
#include "scene_io/gltf_loader.h"
#include "session/output_files.h"
#include "session/session.h"

namespace py = pybind11;

namespace prism {
namespace {

// `text` as a value of E, or the RequestError a job file would get for `field`.
template <NamedEnum E>
E choice(const std::string& text, const char* field) {
  E value{};
  if (!parse_enum(text, &value))
    throw RequestError(field, text + ": expected " + enum_choices<E>());
  return value;
}

// An image as a (height, width, 4) float32 array that owns its pixels (moved, not copied).
py::array_t<float> to_array(Image image) {
  auto* pixels = new std::vector<float>(std::move(image.rgba));
  py::capsule owner(pixels, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>({image.height, image.width, 4}, pixels->data(), owner);
}

// A (height, width, 3 or 4) array as an Image (alpha 1 where the array has none).
Image from_array(const py::array_t<float, py::array::c_style | py::array::forcecast>& a,
                 const char* name) {
  if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4) || a.shape(0) < 1 || a.shape(1) < 1)
    throw py::value_error(std::string(name) +
                          ": expected an array of shape (height, width, 3 or 4)");
  const int height = static_cast<int>(a.shape(0)), width = static_cast<int>(a.shape(1));
  const int channels = static_cast<int>(a.shape(2));
  Image image(width, height);
  const float* in = a.data();
  for (size_t i = 0; i < static_cast<size_t>(width) * height; ++i) {
    std::copy_n(in + i * channels, 3, &image.rgba[i * 4]);
    image.rgba[i * 4 + 3] = channels == 4 ? in[i * channels + 3] : 1.0f;
  }
  return image;
}

py::dict ray_counts(const RayCounters& rays) {
  py::dict d;
  for (const auto& [kind, name] : kRayKindNames) d[py::str(std::string(name))] = rays[kind];
  return d;
}

py::dict error_dict(const ImageError& e) {
  py::dict d;
  d["rmse"] = e.overall.rmse;
  d["relmse"] = e.overall.relmse;
  d["psnr"] = e.overall.psnr;
  d["max_abs"] = e.overall.max_abs;
  d["max_x"] = e.overall.max_x;
  d["max_y"] = e.overall.max_y;
  d["compared_pixels"] = e.compared_pixels;
  return d;
}

using Scene3 = std::array<double, 3>;

// A grey radiance or an (R, G, B) triple, as --background takes either.
Scene3 to_background(const py::object& value) {
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
    const double v = py::cast<double>(value);
    return {v, v, v};
  }
  try {
    const auto rgb = py::cast<std::vector<double>>(value);
    if (rgb.size() == 3) return {rgb[0], rgb[1], rgb[2]};
  } catch (const py::cast_error&) {
  }
  throw RequestError("background", "expected a radiance or (R, G, B)");
}

std::optional<Scene3> to_vector(const py::object& value, const char* field) {
  if (value.is_none()) return std::nullopt;
  try {
    const auto v = py::cast<std::vector<double>>(value);
    if (v.size() == 3) return Scene3{v[0], v[1], v[2]};
  } catch (const py::cast_error&) {
  }
  throw RequestError(field, "expected three numbers (X, Y, Z)");
}

struct EnvironmentOptions {
  double rotation = 0.0, intensity = 1.0;
  bool hidden = false;
};

struct CameraOptions {
  std::optional<Scene3> look_from, look_at, up;
  std::optional<double> fov;
};

// A loaded scene and the session that renders it; Render objects keep it alive, since
// writing one needs the session's colour pipeline.
class PySession : public std::enable_shared_from_this<PySession> {
 public:
  PySession(const std::string& path, const std::string& scene, int threads, double memory_limit_gib,
            bool allow_external_paths, bool detect_spheres) {
    SceneRequest request;
    request.path = path;
    request.scene = scene;
    request.allow_external_paths = allow_external_paths;
    request.detect_spheres = detect_spheres;
    SessionOptions options;
    if (threads < 0)
      throw RequestError("threads", std::to_string(threads) + ": expected 0 (every core) or more");
    options.threads = threads;
    if (!(memory_limit_gib > 0.0 && memory_limit_gib <= 1024.0))
      throw RequestError("memory-limit", std::to_string(memory_limit_gib) +
                                             ": expected more than 0 and at most 1024 GiB");
    options.memory_budget_bytes = static_cast<uint64_t>(memory_limit_gib * (1u << 30));
    py::gil_scoped_release unlocked;
    session_ = std::make_unique<Session>(request, options);
  }

  Session& session() { return *session_; }

  std::vector<std::string> cameras() {
    session_->add_defaults();
    std::vector<std::string> names;
    for (const CameraDescription& c : session_->scene().cameras) names.push_back(c.name);
    return names;
  }

  RenderJob job(const std::string& integrator, int spp,
                const std::optional<std::pair<int, int>>& resolution, const std::string& camera,
                double target_error, double time_limit, int min_spp,
                const std::string& working_space, const std::string& brdf,
                const std::string& spheres, bool robust, const std::string& build_quality,
                const std::string& reference, const Scene3& background,
                const std::string& environment, const EnvironmentOptions& env,
                const CameraOptions& view, const std::optional<std::array<int, 4>>& region,
                long long seed, const py::dict& parameters) const {
    RenderJob job;
    job.integrator = integrator;
    if (camera == "auto")
      job.frame_scene = true;
    else
      job.camera = camera;
    if (view.look_from || view.look_at || view.up || view.fov) {
      CameraPlacement place;
      const auto vec = [](const std::optional<Scene3>& v) -> std::optional<V3d> {
        if (!v) return std::nullopt;
        return V3d((*v)[0], (*v)[1], (*v)[2]);
      };
      place.look_from = vec(view.look_from);
      place.look_at = vec(view.look_at);
      place.up = vec(view.up);
      place.yfov_degrees = view.fov;
      job.placement = place;
    }
    job.background =
        Imath::V3f(static_cast<float>(background[0]), static_cast<float>(background[1]),
                   static_cast<float>(background[2]));
    job.environment.path = environment;
    job.environment.rotation_degrees = static_cast<float>(env.rotation);
    job.environment.intensity = static_cast<float>(env.intensity);
    job.environment.hidden = env.hidden;
    if (resolution) {
      job.width = resolution->first;
      job.height = resolution->second;
      if (job.width < 1 || job.height < 1 || job.width > kMaxImageSide ||
          job.height > kMaxImageSide)
        throw RequestError("res", std::to_string(job.width) + "x" + std::to_string(job.height) +
                                      ": each side 1 to " + std::to_string(kMaxImageSide));
    }
    job.film.spp = spp;
    job.film.target_error = static_cast<float>(target_error);
    job.film.time_limit_seconds = time_limit;
    job.film.min_spp = min_spp;
    // The command line's --seed range, so that a job means the same from either.
    if (seed < 0 || seed > RenderSettings::kMaxSeed)
      throw RequestError("seed", std::to_string(seed) + ": must be a whole number from 0 to " +
                                     std::to_string(RenderSettings::kMaxSeed));
    job.film.seed = static_cast<uint32_t>(seed);
    // Checked against the image by the session, as the command line's --region.
    if (region) job.film.region = TileRect{(*region)[0], (*region)[1], (*region)[2], (*region)[3]};
    job.working_space = choice<WorkingSpace>(working_space, "working-space");
    job.brdf = choice<BrdfModel>(brdf, "brdf");
    std::string why;
    if (!parse_sphere_options(spheres, &job.spheres, &why)) throw RequestError("spheres", why);
    job.robust = robust;
    job.build_quality = choice<BuildQuality>(build_quality, "build-quality");
    job.reference_path = reference;
    // Python spells the registry's "max-depth" as max_depth.
    for (const auto& [key, value] : parameters) {
      std::string name = py::cast<std::string>(key);
      std::replace(name.begin(), name.end(), '_', '-');
      job.integrator_parameters[name] = py::cast<double>(value);
    }
    return job;
  }

 private:
  std::unique_ptr<Session> session_;
};

// One finished render: its image and figures, and write() for its files.
struct PyRender {
  std::shared_ptr<PySession> owner;
  RenderJob job;
  RenderOutput output;
  py::object image;

  void write(const std::string& path, const std::string& preview, bool half,
             const std::string& compression, const std::string& view, double exposure) {
    OutputFiles files;
    files.image = path;
    files.exr_only = false;  // the format by the extension, as prism render's -o
    files.display.view = view;
    files.display.exposure = exposure;
    files.preview = preview;
    files.pixel_type = half ? ExrPixelType::half : ExrPixelType::float32;
    files.compression = choice<ExrCompression>(compression, "compression");
    Session& session = owner->session();
    check_output_files(files, session.request().path);
    // The NumPy array owns the pixels now; the writer reads them through the output again.
    const py::array_t<float> pixels = image;
    output.image.rgba.assign(pixels.data(), pixels.data() + pixels.size());
    py::gil_scoped_release unlocked;
    write_output_files(files, output, session.colour(job.working_space), session.threads());
    std::vector<float>().swap(output.image.rgba);
  }
};

}  // namespace
}  // namespace prism

PYBIND11_MODULE(_prism, m) {
  using namespace prism;
  m.doc() = "Prism: render glTF scenes with Prism's integrators from Python (docs/python.md)";
  m.attr("__version__") = kVersion;

  static py::exception<RequestError> request_error(m, "RequestError", PyExc_ValueError);
  static py::exception<LoadError> load_error(m, "LoadError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const RequestError& e) {
      // The option it refuses, spelled as in job files, as an attribute beside the message.
      py::object type = request_error;
      py::object error = type(e.what());
      error.attr("field") = e.field;
      PyErr_SetObject(request_error.ptr(), error.ptr());
    } catch (const LoadError& e) {
      load_error(e.what());
    }
  });

  m.def(
      "integrators",
      [] {
        py::list out;
        for (const IntegratorInfo* info : integrator_registry()) {
          py::dict d;
          d["name"] = info->name;
          d["summary"] = info->summary;
          py::list parameters;
          for (const ParameterInfo& p : info->parameters) {
            py::dict pd;
            pd["name"] = p.name;
            pd["type"] = std::string(to_string(p.type));
            pd["default"] = p.default_value;
            pd["min"] = p.min;
            pd["max"] = p.max;
            pd["description"] = p.description;
            parameters.append(pd);
          }
          d["parameters"] = parameters;
          out.append(d);
        }
        return out;
      },
      "The registered integrators, each with its parameter table.");

  py::class_<PySession, std::shared_ptr<PySession>>(
      m, "Session", "A glTF scene loaded once, rendered many times.")
      .def(py::init<const std::string&, const std::string&, int, double, bool, bool>(),
           py::arg("path"), py::arg("scene") = "", py::arg("threads") = 0,
           py::arg("memory_limit_gib") = 8.0, py::arg("allow_external_paths") = false,
           py::arg("detect_spheres") = false)
      .def_property_readonly("path", [](PySession& s) { return s.session().request().path; })
      .def_property_readonly("warnings", [](PySession& s) { return s.session().warnings(); })
      .def_property_readonly("cameras", &PySession::cameras,
                             "Camera names (the default camera's when the file has none).")
      .def_property_readonly("threads", [](PySession& s) { return s.session().threads(); })
      .def_property_readonly("load_seconds",
                             [](PySession& s) { return s.session().load_seconds(); })
      .def(
          "render",
          [](PySession& self, const std::string& integrator, int spp,
             const std::optional<std::pair<int, int>>& resolution, const std::string& camera,
             double target_error, double time_limit, int min_spp, const std::string& working_space,
             const py::object& background, const std::string& environment,
             double environment_rotation, double environment_intensity, bool hide_environment,
             const py::object& look_from, const py::object& look_at, const py::object& up,
             const std::optional<double>& fov, const std::string& brdf, const std::string& spheres,
             bool robust, const std::string& build_quality, const std::string& reference,
             const std::optional<std::array<int, 4>>& region, long long seed,
             const py::kwargs& parameters) {
            auto render = std::make_unique<PyRender>();
            render->owner = self.shared_from_this();
            const EnvironmentOptions env{environment_rotation, environment_intensity,
                                         hide_environment};
            const CameraOptions view{to_vector(look_from, "look-from"),
                                     to_vector(look_at, "look-at"), to_vector(up, "up"), fov};
            render->job = self.job(integrator, spp, resolution, camera, target_error, time_limit,
                                   min_spp, working_space, brdf, spheres, robust, build_quality,
                                   reference, to_background(background), environment, env, view,
                                   region, seed, parameters);
            {
              py::gil_scoped_release unlocked;
              render->output = self.session().render(render->job);
            }
            render->image = to_array(std::move(render->output.image));
            return render;
          },
          py::arg("integrator") = "whitted", py::arg("spp") = 1, py::arg("resolution") = py::none(),
          py::arg("camera") = "", py::arg("target_error") = 0.0, py::arg("time_limit") = 0.0,
          py::arg("min_spp") = 8, py::arg("working_space") = "linear-rec709",
          py::arg("background") = 0.0, py::arg("environment") = "",
          py::arg("environment_rotation") = 0.0, py::arg("environment_intensity") = 1.0,
          py::arg("hide_environment") = false, py::arg("look_from") = py::none(),
          py::arg("look_at") = py::none(), py::arg("up") = py::none(), py::arg("fov") = py::none(),
          py::arg("brdf") = "gltf", py::arg("spheres") = "analytic", py::arg("robust") = false,
          py::arg("build_quality") = "auto", py::arg("reference") = "",
          py::arg("region") = py::none(), py::arg("seed") = 0,
          "Renders one job; integrator parameters (max_depth=..., ambient=...) as keywords. "
          "region=(x0, y0, x1, y1) renders only those pixels (x1, y1 exclusive); the rest of "
          "the image is 0, and a written EXR stores the region as its data window. seed=N "
          "(as render --seed) draws another, independent sample stream; 0 is the default.");

  py::class_<PyRender>(m, "Render", "One finished render: image, rays, timings, metadata.")
      .def_readonly("image", &PyRender::image)
      .def_property_readonly("width", [](const PyRender& r) { return r.output.film.width; })
      .def_property_readonly("height", [](const PyRender& r) { return r.output.film.height; })
      .def_property_readonly("spp", [](const PyRender& r) { return r.output.film.spp; })
      .def_property_readonly(
          "mean_spp", [](const PyRender& r) { return r.output.result.mean_spp(r.output.film); })
      .def_property_readonly("integrator", [](const PyRender& r) { return r.output.integrator; })
      .def_property_readonly("parameters",
                             [](const PyRender& r) { return r.output.parameters.values(); })
      .def_property_readonly("camera", [](const PyRender& r) { return r.output.camera_name; })
      .def_property_readonly("camera_index",
                             [](const PyRender& r) { return r.output.camera_index; })
      .def_property_readonly("rays",
                             [](const PyRender& r) { return ray_counts(r.output.result.rays); })
      .def_property_readonly("seconds", [](const PyRender& r) { return r.output.result.seconds; })
      .def_property_readonly("build_seconds",
                             [](const PyRender& r) { return r.output.build_seconds; })
      .def_property_readonly(
          "rays_per_second",
          [](const PyRender& r) {
            const double s = r.output.result.seconds;
            return s > 0.0 ? static_cast<double>(r.output.result.rays.total()) / s : 0.0;
          })
      .def_property_readonly("warnings", [](const PyRender& r) { return r.output.warnings; })
      .def_property_readonly("pass_errors",
                             [](const PyRender& r) {
                               py::list out;
                               for (const PassError& e : r.output.pass_errors) {
                                 py::dict d;
                                 d["samples"] = e.samples;
                                 d["rmse"] = e.rmse;
                                 d["relmse"] = e.relmse;
                                 out.append(d);
                               }
                               return out;
                             })
      .def("write", &PyRender::write, py::arg("path"), py::arg("preview") = "",
           py::arg("half") = false,
           py::arg("compression") = std::string(to_string(kDefaultExrCompression)),
           py::arg("view") = "", py::arg("exposure") = 0.0,
           "Writes the image (its format by the extension, as prism render's -o) and an optional "
           "PNG preview, atomically; view and exposure apply to display-referred formats.");

  m.def(
      "read_exr", [](const std::string& path) { return to_array(read_exr(path)); }, py::arg("path"),
      "Reads an EXR as a (height, width, 4) float32 array.");
  m.def(
      "compare_images",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& image,
         const py::array_t<float, py::array::c_style | py::array::forcecast>& reference) {
        const Image a = from_array(image, "image"), b = from_array(reference, "reference");
        if (a.width != b.width || a.height != b.height)
          throw py::value_error("image and reference differ in size");
        return error_dict(compare_images(a, b));
      },
      py::arg("image"), py::arg("reference"),
      "Error of `image` against `reference` over RGB, as `prism diff` reports it.");
}
