// `prism render`: load a scene, render it with one integrator, write the EXR (and preview).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "apps/render_setup.h"

namespace prism {

struct RenderOptions {
  SceneOptions scene;
  std::string output_path;
  std::string preview_path;
  std::string integrator = "whitted";
  int spp = 1;
  std::string spheres = "analytic";
  std::string reference_path;  // measure the error against this image after every pass
  bool half = false;
  bool robust = false;
  bool quiet = false;
  bool verbose = false;
};

// Adds the `render` subcommand to `app`, filling `options` when it is parsed.
CLI::App* add_render_command(CLI::App& app, RenderOptions* options);

// Runs it. Returns the process exit code; errors are printed as one line on stderr.
int run_render(const RenderOptions& options);

}  // namespace prism
