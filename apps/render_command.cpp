#include "apps/render_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

#include "apps/progress_bar.h"
#include "apps/stop_signals.h"
#include "session/checkpoint_file.h"
#include "session/job_fingerprint.h"
#include "session/output_files.h"
#include "session/session.h"

namespace prism {
namespace {

// "16 spp", or for an adaptive render "256 spp max, 21.7 mean, 9 rounds, time limit reached".
std::string spp_summary(const RenderResult& result, const RenderSettings& settings) {
  std::string text = std::to_string(settings.spp) + " spp";
  if (!settings.adaptive()) return text;
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, " max, %.4g mean, %d rounds%s", result.mean_spp(settings),
                result.rounds, result.time_limit_reached ? ", time limit reached" : "");
  return text + buffer;
}

// "camera 1,024, shadow 2,048, reflection 0, refraction 0, total 3,072"
std::string ray_summary(const RayCounters& rays) {
  std::string text;
  for (const EnumName<RayKind>& kind : kRayKindNames)
    text += std::string(kind.name) + " " + with_commas(rays[kind.value]) + ", ";
  return text + "total " + with_commas(rays.total());
}

// The command line as a shell reads it back: words with anything but safe characters in
// single quotes.
std::string shell_command(const std::vector<std::string>& argv) {
  std::string text;
  for (const std::string& word : argv) {
    if (!text.empty()) text += ' ';
    const bool safe = !word.empty() && word.find_first_not_of(
                                           "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                           "0123456789_-+=/.,:@%") == std::string::npos;
    if (safe) {
      text += word;
      continue;
    }
    text += '\'';
    for (char c : word) text += c == '\'' ? std::string("'\\''") : std::string(1, c);
    text += '\'';
  }
  return text;
}

// A view the config's display lacks is a usage error found before the render.
void check_view(const ColourPipeline& colour, const std::string& view) {
  if (view.empty()) return;
  std::string names;
  for (const DisplayView& v : colour.views()) {
    if (v.display != colour.display()) continue;
    if (v.view == view) return;
    names += (names.empty() ? "" : ", ") + v.view;
  }
  throw UsageError("--view " + view + ": display '" + colour.display() + "' of OCIO config " +
                   colour.config_source() + " has the views " + names);
}

}  // namespace

RenderRequest render_request(const RenderOptions& o) {
  RenderRequest r;
  // Everything that needs no file first, so a typo costs nothing.
  RenderJob& job = r.job;
  job = base_job(o.scene);
  if (o.integrator.find(',') != std::string::npos)
    throw UsageError("--integrator " + o.integrator +
                     ": render takes one integrator (prism compare takes a list)");
  job.integrator = parse_integrator_option(o.integrator, "--integrator").name;
  job.spheres = parse_spheres_option(o.spheres, "--spheres");
  job.build_quality = parse_choice<BuildQuality>(o.build_quality, "--build-quality");
  job.robust = o.robust;
  job.film.spp = o.spp;
  job.film.specialise = !o.general_path;
  job.film.target_error = static_cast<float>(o.target_error);
  job.film.time_limit_seconds = o.time_limit;
  job.film.min_spp = o.min_spp;
  job.film.error_goal = parse_choice<ErrorGoal>(o.error_goal, "--error-goal");
  job.film.seed = static_cast<uint32_t>(o.seed);
  if ((o.min_spp & (o.min_spp - 1)) != 0)
    throw UsageError("--min-spp " + std::to_string(o.min_spp) + ": must be a power of two");
  // Adaptive sampling decides after --min-spp samples and stops at --spp: with no room
  // between them it would take every sample in every pixel, as if not asked.
  if (o.target_error > 0.0 && o.spp <= o.min_spp)
    throw UsageError("--target-error " + format_error(o.target_error) + " with --spp " +
                     std::to_string(o.spp) + ": adaptive sampling takes --min-spp " +
                     std::to_string(o.min_spp) + " samples in every pixel before it decides and " +
                     "at most --spp, so it would change nothing; raise --spp above " +
                     std::to_string(o.min_spp) + " or lower --min-spp");
  if (!o.region.empty()) job.film.region = parse_region_option(o.region, "--region");
  if (!std::isfinite(o.checkpoint_interval) || o.checkpoint_interval < 0.0)
    throw UsageError("--checkpoint-interval " + std::to_string(o.checkpoint_interval) +
                     ": must be a finite number of seconds >= 0");
  r.checkpoint_interval = o.checkpoint_interval;
  job.reference_path = o.reference_path;
  r.files.image = o.output_path;
  r.files.preview = o.preview_path;
  r.files.sample_counts = o.sample_count_path;
  r.files.pixel_type = o.half ? ExrPixelType::half : ExrPixelType::float32;
  r.files.compression = parse_choice<ExrCompression>(o.compression, "--compression");
  if (!std::isfinite(o.exposure) || std::abs(o.exposure) > 64.0)
    throw UsageError("--exposure " + format_error(o.exposure) +
                     ": must be a number of stops from -64 to 64");
  r.files.display = {o.view, o.exposure};
  r.scene = scene_request(o.scene, o.sphere_detection);
  r.session = session_options(o.scene);
  return r;
}

namespace {

int run(const RenderOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const RenderRequest r = render_request(o);
  const RenderJob& job = r.job;
  OutputFiles files = r.files;
  files.exr_only = false;  // a render's -o may be any format; a batch's stay EXR
  const SceneRequest& request = r.scene;
  check_output_files(files, o.scene.scene_path);
  // Options the output's format does not have: said before the render, as a typo should be.
  std::vector<std::string> ignored;
  ImageFormat format = ImageFormat::exr;
  if (image_format_for_path(files.image, &format) && format != ImageFormat::exr) {
    if (o.half) ignored.push_back("--half");
    if (o.compression_given) ignored.push_back("--compression");
  }
  const bool checkpoints = r.checkpoint_interval > 0.0;
  // Before the scene loads, so that a SIGTERM during a long load is not lost either.
  StopSignalScope signals(checkpoints);

  SessionOptions options = r.session;
  options.distribute_frames = true;  // under mpirun; a plain run is a world of one
  Session session(request, options);
  // Every rank would say the same: rank 0 alone prints, and writes the files.
  const bool root = session.rank() == 0;
  // Before the warnings: a job that cannot run is one line, not the scene's notes and then it.
  session.check(job);
  check_view(session.colour(job.working_space), files.display.view);
  if (root) {
    print_warnings(o.scene.scene_path, session.warnings());
    for (const std::string& line : session.sphere_detection_report())
      std::fprintf(stderr, "prism: --detect-spheres: %s: %s\n", o.scene.scene_path.c_str(),
                   line.c_str());
  }
  if (root && !o.quiet)
    for (const std::string& option : ignored)
      std::fprintf(stderr,
                   "prism: warning: %s sets how EXR files are stored; %s is not one and is "
                   "written without it (-o NAME.exr writes an EXR)\n",
                   option.c_str(), files.image.c_str());
  if (root) print_warnings(o.scene.scene_path, session.job_warnings(job));
  // Built before the render so that --verbose can describe it and the summary time it.
  double build_seconds = 0.0;
  const RenderScene& built = session.render_scene(job, &build_seconds);
  if (o.verbose && root) {
    const GeometryStatistics& stats = built.geometry().statistics();
    const RenderSettings film = session.film(job);
    std::fprintf(
        stderr,
        "prism: %s: %zu triangles (%zu meshes baked, %zu instances), %zu spheres (%s), "
        "%zu lights (%zu dark, left out), camera '%s', %dx%d, %d spp, loaded and built in %.3f s\n",
        o.scene.scene_path.c_str(), stats.triangles, stats.meshes_baked, stats.mesh_instances,
        stats.spheres, to_string(job.spheres).c_str(), built.lights().size(), built.dark_lights(),
        session.camera(job).name.c_str(), film.width, film.height, film.spp,
        session.load_seconds() + build_seconds);
    std::fprintf(stderr, "prism: features: %s\n", to_string(built.features()).c_str());
  }

  // A checkpoint of this job continues it; any other (an edited scene, another option, a
  // damaged file) is reported and rendered over from the start.
  const std::string checkpoint = checkpoint_path(o.output_path);
  std::string fingerprint;
  std::optional<RenderState> resume;
  std::error_code exists_error;
  if (checkpoints) {
    fingerprint = job_fingerprint(canonical_settings(request, job, files.pixel_type),
                                  hash_inputs(session.scene().source_files));
    if (std::filesystem::exists(checkpoint, exists_error)) {
      CheckpointRead read = read_checkpoint(checkpoint, session.film(job), fingerprint);
      if (read.state) {
        resume = std::move(read.state);
        std::fprintf(stderr,
                     "prism: resuming %s from its checkpoint: %d of %d samples per pixel done\n",
                     o.output_path.c_str(), resume->samples_done, resume->spp);
      } else {
        std::fprintf(stderr, "prism: warning: %s: %s; rendering from the start\n",
                     checkpoint.c_str(), read.reason.c_str());
      }
    }
  }
  if (stop_requested() || interrupted()) {
    std::fprintf(stderr, "prism: %s before the render started: nothing written\n",
                 stop_signal_name(stop_signal()));
    return 128 + stop_signal();
  }

  // With a reference, the per-pass lines report progress, and a bar would garble them.
  ProgressBar progress(root && !o.quiet && o.reference_path.empty());
  JobCallbacks callbacks;
  callbacks.progress = [&](int done, int total) { progress.update(done, total); };
  if (!o.quiet)
    callbacks.pass_error = [&](const PassError& e) {
      std::fprintf(stderr, "prism: pass %d/%d: RMSE %.6g relMSE %.6g\n", e.samples, job.film.spp,
                   e.rmse, e.relmse);
    };
  callbacks.cancel = [] { return interrupted(); };
  // A checkpoint that cannot be written (a full disk) is reported once; the render goes on.
  std::string save_error;
  int saved_samples = -1;
  auto last_save = std::chrono::steady_clock::now();
  if (checkpoints) {
    callbacks.checkpoint_due = [&] {
      return checkpoint_requested() ||
             std::chrono::duration<double>(std::chrono::steady_clock::now() - last_save).count() >=
                 o.checkpoint_interval;
    };
    callbacks.stop = [] { return stop_requested(); };
    callbacks.save_checkpoint = [&](const RenderState& state) {
      try {
        write_checkpoint(checkpoint, state, fingerprint);
        saved_samples = state.samples_done;
        save_error.clear();
      } catch (const std::exception& e) {
        if (save_error.empty()) {
          progress.finish();
          std::fprintf(stderr, "prism: warning: cannot save the checkpoint: %s\n", e.what());
        }
        save_error = e.what();
      }
      last_save = std::chrono::steady_clock::now();
    };
    callbacks.resume = resume ? &*resume : nullptr;
  }
  const RenderOutput out = session.render(job, callbacks);
  signals.restore();
  progress.finish();
  if (!root) return 0;
  const RenderResult& result = out.result;
  if (result.cancelled) {
    std::fprintf(stderr, "prism: interrupted by SIGINT: nothing written\n");
    return 130;
  }
  if (result.stopped_at_checkpoint) {
    const int sig = stop_signal();
    if (!save_error.empty()) {
      std::fprintf(stderr, "prism: stopped by %s, but the checkpoint could not be saved (%s)%s\n",
                   stop_signal_name(sig), save_error.c_str(),
                   saved_samples >= 0 || resume ? "; the last one saved remains" : "");
    } else {
      std::fprintf(stderr,
                   "prism: stopped by %s after %d of %d samples per pixel; saved %s, nothing "
                   "else written\n",
                   stop_signal_name(sig), saved_samples, std::max(1, job.film.spp),
                   checkpoint.c_str());
    }
    std::fprintf(stderr, "prism: to resume, run: %s\n", shell_command(o.argv).c_str());
    return 128 + sig;
  }
  const distributed::FrameSplitStats& split = out.frame_split;
  if (o.verbose && split.ranks > 1) {
    std::string tiles;
    for (uint64_t n : split.tiles_per_rank) tiles += (tiles.empty() ? "" : " + ") + with_commas(n);
    std::fprintf(stderr,
                 "prism: %d MPI ranks rendered %s tiles; rank 0 received %s tiles, %s bytes "
                 "(%.0f per tile), waited %.4f s for the last rank and gathered in %.4f s\n",
                 split.ranks, tiles.c_str(), with_commas(split.tiles_received).c_str(),
                 with_commas(split.bytes_received).c_str(),
                 split.tiles_received ? static_cast<double>(split.bytes_received) /
                                            static_cast<double>(split.tiles_received)
                                      : 0.0,
                 split.wait_seconds, split.gather_seconds);
    std::fprintf(stderr, "prism: MPI transport: %s\n", split.transport.c_str());
  }
  if (result.time_limit_reached && !o.quiet)
    std::fprintf(stderr,
                 "prism: --time-limit %g s reached after round %d (%.4g spp mean); the image "
                 "depends on this machine's speed\n",
                 out.film.time_limit_seconds, result.rounds, result.mean_spp(out.film));
  // A large image takes a while to write: the line says so rather than sitting still.
  progress.phase("writing " + o.output_path);
  write_output_files(files, out, session.colour(job.working_space), session.threads());
  progress.finish();
  // The image is on disk: the checkpoint has nothing left to continue.
  if (checkpoints) {
    std::error_code remove_error;
    std::filesystem::remove(checkpoint, remove_error);
  }

  if (!o.quiet) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const RayCounters& r = result.rays;
    std::printf("rendered %s with %s, %dx%d, %s, spheres %s\n", o.scene.scene_path.c_str(),
                out.integrator.c_str(), out.film.width, out.film.height,
                spp_summary(result, out.film).c_str(), to_string(job.spheres).c_str());
    std::printf("render time  %.3f s (load + build %.3f s, total %.3f s)\n", result.seconds,
                session.load_seconds() + build_seconds, wall);
    std::printf("rays         %s\n", ray_summary(r).c_str());
    std::printf("rays/second  %.3g\n", result.seconds > 0.0 ? r.total() / result.seconds : 0.0);
    std::printf("discarded    %s non-finite samples\n", with_commas(r.discarded_samples).c_str());
    if (out.resumed_samples > 0)
      std::printf("resumed      from %s at %d of %d spp (its rays and time included above)\n",
                  checkpoint.c_str(), out.resumed_samples, std::max(1, out.film.spp));
    if (!out.pass_errors.empty())
      std::printf("reference    RMSE %s, relMSE %s against %s\n",
                  format_error(out.pass_errors.back().rmse).c_str(),
                  format_error(out.pass_errors.back().relmse).c_str(), o.reference_path.c_str());
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
  cmd->add_option("-o,--output", o->output_path,
                  "Output image, its format by the extension: .exr (scene-linear, the master "
                  "with metadata), .tif/.tiff/.hdr (scene-linear), .png/.jpg/.jpeg "
                  "(display-referred through --view)")
      ->required();
  std::string integrators;
  for (const IntegratorInfo* info : integrator_registry())
    integrators += std::string(integrators.empty() ? "" : "; ") + info->name + ": " + info->summary;
  cmd->add_option("--integrator", o->integrator, integrators)->capture_default_str();
  cmd->add_option("--spp", o->spp,
                  "Samples per pixel, stratified over each pixel (the default anti-aliases); 1 = "
                  "one ray through each pixel's centre, as the lecture's view rays")
      ->check(whole_number(1, 1 << 16))
      ->capture_default_str();
  cmd->add_option("--target-error", o->target_error,
                  "Adaptive sampling: a pixel stops once the estimated relative error of its "
                  "neighbourhood is below this (about the RMS of (a-b)/sqrt(b^2+0.01)); --spp "
                  "is then the most a pixel takes (docs/sampling.md)")
      ->check(kPositiveFinite);
  cmd->add_option("--error-goal", o->error_goal,
                  "What --target-error bounds: " + enum_choices<ErrorGoal>(" | ") +
                      "; pixel: every pixel's relative error (as Cycles' noise threshold); "
                      "image: the image's (the root of its relMSE), samples going where they "
                      "lower it most (docs/sampling.md)")
      ->capture_default_str();
  cmd->add_option("--time-limit", o->time_limit,
                  "Seconds: take samples in rounds, start none once this has passed (--spp is "
                  "then the most); depends on the machine, unlike everything else")
      ->check(kPositiveFinite);
  cmd->add_option("--min-spp", o->min_spp,
                  "Adaptive sampling: samples every pixel takes before the first decision (a "
                  "power of two)")
      ->check(whole_number(1, 1 << 16))
      ->capture_default_str();
  add_seed_option(cmd, &o->seed,
                  "Sample streams: 0 is the default render's; any other draws independent noise "
                  "with the same expected image, e.g. to estimate a render's error against "
                  "another, or a reference that shares no samples with what it measures");
  cmd->add_option("--region", o->region,
                  "X0,Y0,X1,Y1: render only the pixels X0 <= x < X1, Y0 <= y < Y1 (from the top "
                  "left), bit-identical to the same pixels of the whole frame; an EXR keeps the "
                  "full frame as its display window and the region as its data window, other "
                  "formats hold the region alone");
  cmd->add_option("--sample-count-image", o->sample_count_path,
                  "Also write each pixel's number of samples (R = G = B) to this EXR");
  cmd->add_option("--spheres", o->spheres, "analytic | mesh[:LEVEL] | embree-points")
      ->capture_default_str();
  cmd->add_option("--preview", o->preview_path, "Also write a display-referred PNG preview");
  cmd->add_option("--view", o->view,
                  "OCIO view of the PNG and JPEG outputs (default: Standard; 'ACES 1.0 "
                  "SDR-video' rolls highlights off; prism info --views lists them)");
  cmd->add_option("--exposure", o->exposure,
                  "Stops by which the PNG and JPEG outputs are brightened (negative: darkened) "
                  "before the view")
      ->capture_default_str();
  cmd->add_option("--reference", o->reference_path,
                  "Render one sample per pixel per pass and log each pass's RMSE and relMSE "
                  "(mean of (a-b)^2/(b^2+0.01)) against this EXR on stderr; they also go into the "
                  "output's metadata. The image itself is unchanged");
  cmd->add_flag("--half", o->half, "Write half-float EXR pixels instead of 32-bit float");
  cmd->add_option_function<std::string>(
      "--compression",
      [o](const std::string& value) {
        o->compression = value;
        o->compression_given = true;
      },
      "EXR compression, all lossless: " + enum_choices<ExrCompression>(" | ") +
          " (docs/benchmarks.md, \"EXR writing\": none and rle write fastest, "
          "piz and zip smallest; default " +
          to_string(kDefaultExrCompression) + ")");
  cmd->add_flag("--robust", o->robust, "Watertight triangle intersection (RTC_SCENE_FLAG_ROBUST)")
      ->group(kDeveloperGroup);
  cmd->add_option("--build-quality", o->build_quality,
                  "BVH build quality: " + enum_choices<BuildQuality>(" | ") +
                      " (slower to build, faster to trace; auto chooses by the rays the render "
                      "expects per primitive)")
      ->capture_default_str()
      ->group(kDeveloperGroup);
  add_sphere_detection_options(cmd, &o->sphere_detection, true);
  cmd->add_flag("--general-path", o->general_path,
                "Run the integrators' general code, not the one specialised on the scene's "
                "features (same image; for tests and benchmarks)")
      ->group(kDeveloperGroup);
  cmd->add_option("--checkpoint-interval", o->checkpoint_interval,
                  "Seconds: save the render's state to OUTPUT.checkpoint this often, and on "
                  "SIGTERM or SIGUSR1 save it and stop (exit 128 + signal); running the same "
                  "command again continues it, bit-identically (0 = off)")
      ->capture_default_str();
  add_verbosity_flags(cmd, &o->quiet, &o->verbose, "No progress bar and no summary",
                      "Describe the scene before rendering");
  return cmd;
}

int run_render(const RenderOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
