// `prism render`: load a scene, render it with one integrator, write the EXR (and preview).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/command_line.h"
#include "session/output_files.h"

namespace prism {

inline constexpr int kDefaultRenderSpp = 16;

struct RenderOptions {
  SceneOptions scene;
  std::string output_path;
  std::string preview_path;
  std::string view;       // OCIO view of the display-referred outputs; empty = Standard
  double exposure = 0.0;  // stops, display-referred outputs only
  std::string integrator = "whitted";
  // Anti-aliased by default (docs/sampling.md); 1 traces the lecture's pixel-centre rays.
  int spp = kDefaultRenderSpp;
  // Adaptive sampling (docs/sampling.md): 0 = off; with either, spp is the maximum.
  double target_error = 0.0;
  double time_limit = 0.0;
  int min_spp = 8;
  std::string error_goal = to_string(ErrorGoal::pixel);  // what --target-error bounds
  // Selects the pixels' sample streams (RenderSettings::seed): 0 is every render's by default;
  // another gives the same image in expectation with independent noise.
  int seed = 0;
  std::string sample_count_path;  // also write each pixel's sample count as an EXR
  std::string region;             // "X0,Y0,X1,Y1": render only these pixels; empty = all
  std::string spheres = "analytic";
  SphereDetectionFlags sphere_detection;  // --detect-spheres, --sphere-tolerance
  std::string reference_path;             // measure the error against this image after every pass
  bool half = false;
  std::string compression = to_string(kDefaultExrCompression);
  bool compression_given = false;  // --compression on the command line (not the default)
  bool robust = false;
  std::string build_quality = "auto";  // BVH build quality (docs/benchmarks.md)
  bool general_path = false;           // RenderSettings::specialise = false
  bool quiet = false;
  bool verbose = false;
  // Seconds between checkpoints (OUTPUT.checkpoint); 0 = none. With it, SIGTERM and SIGUSR1
  // save one and stop, and a re-run continues from it (docs/sampling.md, Checkpoints).
  double checkpoint_interval = 0.0;
  // The command line as run, to print the command that resumes a stopped render.
  std::vector<std::string> argv;
};

// What a `prism render` command line asks for, checked (UsageError or RequestError naming the
// option): the scene to load, the session, the job and its files (their paths are not
// checked here: a batch's may still hold placeholders; check_output_files does). `prism batch`
// turns each job of a job file into the same, so both accept and refuse exactly the same options.
struct RenderRequest {
  SceneRequest scene;
  SessionOptions session;
  RenderJob job;
  OutputFiles files;
  double checkpoint_interval = 0.0;  // seconds between checkpoints; 0 = none
};
RenderRequest render_request(const RenderOptions& options);

// Adds the `render` subcommand to `app`, filling `options` when it is parsed.
CLI::App* add_render_command(CLI::App& app, RenderOptions* options);

// Runs it. Returns the process exit code; errors are printed as one line on stderr. A render
// stopped by SIGINT exits 130 with nothing written; one stopped by SIGTERM or SIGUSR1 with
// checkpoints on saves its checkpoint, writes no image and exits 128 + the signal's number
// (143, 138).
int run_render(const RenderOptions& options);

}  // namespace prism
