// `prism compare`: renders a scene with every combination of integrator, sphere mode and
// samples per pixel, measures each against a reference, and writes a report directory
// (results.json, results.csv, images, a time-versus-error plot, index.html). docs/compare.md.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/command_line.h"
#include "apps/reference_cache.h"
#include "renderer/integrator.h"

namespace prism {

struct CompareOptions {
  SceneOptions scene;
  std::vector<std::string> integrators{"phong", "shadow", "whitted"};
  std::vector<int> spp{1, 4, 16, 64};
  std::vector<std::string> spheres{"analytic"};
  // Besides the uniform rows, one adaptive render (docs/sampling.md) per target error for
  // each integrator and sphere mode, capped at the largest `spp`; empty: none.
  std::vector<double> target_errors;
  int min_spp = RenderSettings{}.min_spp;
  // The compared renders' sample streams (RenderSettings::seed): another seed gives another
  // draw of their noise, for the spread of their errors; a rendered reference keeps a stream
  // of its own.
  int seed = 0;
  std::string reference_path;  // empty: render (or find in the cache) a reference
  // Whose render the reference is: an integrator's name (one reference for every row), or
  // "self" (each integrator against its own).
  std::string reference_integrator = "path";
  int reference_spp = 256;
  double cache_limit_gib = kDefaultCacheLimitGib;  // the reference cache's bound
  std::string report_dir;
  std::string plot_metric = "relmse";
  bool quiet = false;    // no progress and no table
  bool verbose = false;  // a line per render as it finishes
};

// Adds the `compare` subcommand to `app`, filling `options` when it is parsed.
CLI::App* add_compare_command(CLI::App& app, CompareOptions* options);

// Runs it. Returns the process exit code; errors are printed as one line on stderr.
int run_compare(const CompareOptions& options);

}  // namespace prism
