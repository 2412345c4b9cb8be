// `prism boids`: a flock that steers around spheres (simulation/, docs/boids.md), written as
// per-frame glTF scenes and a job file for `prism batch`; with --preview, the contact sheet
// and MP4 of a clip that batch has rendered.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace prism {

struct BoidsOptions {
  std::string config;   // flock.json
  int frames = 0;       // 0 = the config's
  std::string output;   // the clip's folder
  int threads = 0;      // 0 = all cores
  std::string preview;  // a rendered clip's folder: make its previews instead
  double fps = 30.0;    // of the MP4
  bool quiet = false;   // nothing on stdout
  bool verbose = false;
};

CLI::App* add_boids_command(CLI::App& app, BoidsOptions* options);

// 0 on success; 2 for a bad config or usage (one line naming the field, nothing written);
// 1 when a file cannot be written.
int run_boids(const BoidsOptions& options);

}  // namespace prism
