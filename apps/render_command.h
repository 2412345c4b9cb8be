// `prism render`: load a scene, render it with one integrator, write the EXR (and preview).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace prism {

struct RenderOptions {
  std::string scene_path;
  std::string output_path;
  std::string preview_path;
  std::string integrator = "whitted";
  int spp = 1;
  std::string resolution;  // "WxH", empty = 640x480 or the camera's aspect ratio
  std::string camera;      // name or index, empty = the first
  int threads = 0;
  int max_depth = 5;
  std::string spheres = "analytic";
  std::string working_space = "linear-rec709";
  std::string reference_path;  // measure the error against this image after every pass
  float ambient = 0.0f;
  float background = 0.0f;
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
