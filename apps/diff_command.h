// `prism diff`: error metrics between an image and a reference (renderer/image/image_metrics.h).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace prism {

struct DiffOptions {
  std::string image_path;
  std::string reference_path;
  std::string metric = "all";  // rmse | relmse | psnr | max | all
  bool has_fail_above = false;
  double fail_above = 0.0;
  std::string difference_path;  // -o: |a - b| as an EXR
  std::string heatmap_path;     // --heatmap: the false-colour PNG
  double heatmap_peak = 0.0;    // the error drawn white; 0 = the largest in the image
  bool quiet = false;           // print nothing: the exit code says it
  bool verbose = false;         // the whole table even with one --metric
};

// Adds the `diff` subcommand to `app`, filling `options` when it is parsed.
CLI::App* add_diff_command(CLI::App& app, DiffOptions* options);

// Returns 0 when the images compare within --fail-above (or none was given), 1 when the
// chosen metric is past it, 2 when they cannot be compared (unreadable, different sizes).
int run_diff(const DiffOptions& options);

}  // namespace prism
