#include "apps/render_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "apps/progress_bar.h"
#include "integrators/integrators.h"
#include "renderer/image/colour.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/image_output.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "renderer/scene_features.h"
#include "renderer/geometry/sphere_geometry.h"

namespace prism {
namespace {

// The error after one pass, against --reference.
struct QuickError {
  double rmse = 0.0;
  double relmse = 0.0;
};

// "16 spp", or for an adaptive render "256 spp max, 21.7 mean, 9 rounds, time limit reached".
std::string spp_summary(const RenderResult& result, const RenderSettings& settings) {
  std::string text = std::to_string(settings.spp) + " spp";
  if (!settings.adaptive()) return text;
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, " max, %.4g mean, %d rounds%s", result.mean_spp(settings),
                result.rounds, result.time_limit_reached ? ", time limit reached" : "");
  return text + buffer;
}

// Each pixel's sample count as grey (R = G = B), alpha 1.
Image sample_count_image(const RenderResult& result, const RenderSettings& settings) {
  Image image(settings.width, settings.height);
  for (size_t i = 0; i < image.rgba.size() / 4; ++i) {
    const float n = result.samples_per_pixel.empty()
                        ? static_cast<float>(settings.spp)
                        : static_cast<float>(result.samples_per_pixel[i]);
    image.rgba[i * 4 + 0] = image.rgba[i * 4 + 1] = image.rgba[i * 4 + 2] = n;
    image.rgba[i * 4 + 3] = 1.0f;
  }
  return image;
}

int run(const RenderOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const IntegratorKind integrator_kind = parse_integrator_option(o.integrator, "--integrator");
  const SphereOptions spheres = parse_spheres_option(o.spheres, "--spheres");
  const BuildQuality build_quality = parse_build_quality_option(o.build_quality, "--build-quality");
  const SphereDetectionOptions sphere_detection = check_sphere_detection_flags(o.sphere_detection);
  SceneSetup setup = check_scene_options(o.scene);
  check_output_path(o.output_path, ".exr", "-o");
  if (!o.preview_path.empty()) check_output_path(o.preview_path, ".png", "--preview");
  if (!o.sample_count_path.empty())
    check_output_path(o.sample_count_path, ".exr", "--sample-count-image");
  if ((o.min_spp & (o.min_spp - 1)) != 0)
    throw UsageError("--min-spp " + std::to_string(o.min_spp) + ": must be a power of two");
  // Read before the scene, so a wrong path costs nothing.
  const Image reference = o.reference_path.empty() ? Image() : read_reference(o.reference_path);

  const auto thread_limit = limit_threads(o.scene.threads);
  const ColourPipeline colour(setup.working_space);
  const auto load_start = std::chrono::steady_clock::now();
  load_scene(o.scene, &setup);
  if (o.sphere_detection.replace)
    replace_detected_spheres(sphere_detection, o.scene.scene_path, &setup.scene);
  RenderSettings& settings = setup.settings;
  const CameraDescription& camera_description = setup.camera();
  if (!o.reference_path.empty()) check_reference_size(reference, o.reference_path, settings);
  settings.spp = o.spp;
  settings.specialise = !o.general_path;
  settings.target_error = static_cast<float>(o.target_error);
  settings.time_limit_seconds = o.time_limit;
  settings.min_spp = o.min_spp;
  const GeometryOptions geometry_options = setup.geometry_options(spheres, o.robust, build_quality);
  const RenderScene render_scene(setup.scene, geometry_options, colour);
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
  const Camera camera = render_scene.camera(camera_description, settings.width, settings.height);
  const std::unique_ptr<Integrator> integrator = make_integrator(integrator_kind);
  const GeometryStatistics& stats = render_scene.geometry().statistics();
  if (o.verbose) {
    std::fprintf(stderr,
                 "prism: %s: %zu triangles (%zu meshes baked, %zu instances), %zu spheres (%s), "
                 "%zu lights, camera '%s', %dx%d, %d spp, loaded and built in %.3f s\n",
                 o.scene.scene_path.c_str(), stats.triangles, stats.meshes_baked,
                 stats.mesh_instances, stats.spheres, to_string(geometry_options.spheres).c_str(),
                 render_scene.lights().size(), camera_description.name.c_str(), settings.width,
                 settings.height, settings.spp, load_seconds);
    std::fprintf(stderr, "prism: features: %s\n", to_string(render_scene.features()).c_str());
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
  if (result.time_limit_reached && !o.quiet)
    std::fprintf(stderr,
                 "prism: --time-limit %g s reached after round %d (%.4g spp mean); the image "
                 "depends on this machine's speed\n",
                 settings.time_limit_seconds, result.rounds, result.mean_spp(settings));

  RenderMetadata metadata =
      render_metadata(o.scene, setup, camera, integrator->name(), geometry_options, result);
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
  if (!o.sample_count_path.empty())
    write_exr(o.sample_count_path, sample_count_image(result, settings), colour, metadata,
              ExrPixelType::float32);

  if (!o.quiet) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const RayCounters& r = result.rays;
    std::printf("rendered %s with %s, %dx%d, %s, spheres %s\n", o.scene.scene_path.c_str(),
                integrator->name(), settings.width, settings.height,
                spp_summary(result, settings).c_str(), to_string(geometry_options.spheres).c_str());
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
    if (!o.sample_count_path.empty()) std::printf("wrote        %s\n", o.sample_count_path.c_str());
  }
  return 0;
}

}  // namespace

CLI::App* add_render_command(CLI::App& app, RenderOptions* o) {
  CLI::App* cmd = app.add_subcommand("render", "Render a glTF scene to an EXR image");
  add_scene_options(cmd, &o->scene);
  cmd->add_option("-o,--output", o->output_path, "Output image (.exr), scene-linear")->required();
  cmd->add_option("--integrator", o->integrator, "phong | shadow | whitted")->capture_default_str();
  cmd->add_option("--spp", o->spp, "Samples per pixel (1 = through pixel centres)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  cmd->add_option("--target-error", o->target_error,
                  "Adaptive sampling: a pixel stops once the estimated relative error of its "
                  "neighbourhood is below this (about the RMS of (a-b)/sqrt(b^2+0.01)); --spp "
                  "is then the most a pixel takes (docs/sampling.md)")
      ->check(kPositiveFinite);
  cmd->add_option("--time-limit", o->time_limit,
                  "Seconds: take samples in rounds, start none once this has passed (--spp is "
                  "then the most); depends on the machine, unlike everything else")
      ->check(kPositiveFinite);
  cmd->add_option("--min-spp", o->min_spp,
                  "Adaptive sampling: samples every pixel takes before the first decision (a "
                  "power of two)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  cmd->add_option("--sample-count-image", o->sample_count_path,
                  "Also write each pixel's number of samples (R = G = B) to this EXR");
  cmd->add_option("--spheres", o->spheres, "analytic | mesh[:LEVEL] | embree-points")
      ->capture_default_str();
  cmd->add_option("--preview", o->preview_path, "Also write a display-referred PNG preview");
  cmd->add_option("--reference", o->reference_path,
                  "Render one sample per pixel per pass and log each pass's RMSE and relMSE "
                  "(mean of (a-b)^2/(b^2+0.01)) against this EXR on stderr; they also go into the "
                  "output's metadata. The image itself is unchanged");
  cmd->add_flag("--half", o->half, "Write half-float EXR pixels instead of 32-bit float");
  cmd->add_flag("--robust", o->robust, "Watertight triangle intersection (RTC_SCENE_FLAG_ROBUST)");
  cmd->add_option("--build-quality", o->build_quality,
                  "BVH build quality: low | medium | high (slower to build, faster to trace)")
      ->capture_default_str();
  add_sphere_detection_options(cmd, &o->sphere_detection, true);
  cmd->add_flag("--general-path", o->general_path,
                "Run the integrators' general code, not the one specialised on the scene's "
                "features (same image; for tests and benchmarks)");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("-v,--verbose", o->verbose, "Describe the scene before rendering");
  return cmd;
}

int run_render(const RenderOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
