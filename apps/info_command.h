// `prism info`: what a glTF file holds as Prism reads it (meshes, materials, textures with
// their encodings, lights, cameras, spheres, extensions), the feature set the renderer
// derives from it (renderer/scene_features.h) and the loader's warnings. docs/info.md.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "apps/command_line.h"

namespace prism {

struct InfoOptions {
  std::string scene_path;
  std::string spheres = "analytic";  // the sphere mode the feature set assumes
  bool allow_external_paths = false;
  SphereDetectionFlags sphere_detection;  // --sphere-tolerance for the sphere-shaped meshes
  bool find_sphere_meshes = false;        // --detect-spheres: list them (a weld of every mesh)
  std::string scene;                      // glTF scene name or index, empty = the file's default
  bool timing = false;                    // also time loading and the BVH build
  bool views = false;
  bool json = false;  // one JSON object (docs/info.md) instead of the text                     //
                      // list the OCIO config's displays and views
  double memory_limit_gib = 8.0;  // --memory-limit
  bool quiet = false;             // print nothing: the exit code says if it loads
  bool verbose = false;           // also --timing
};

// Adds the `info` subcommand to `app`, filling `options` when it is parsed.
CLI::App* add_info_command(CLI::App& app, InfoOptions* options);

// 0 after printing; 1 with one line on stderr when the file cannot be loaded; 2 for a bad
// --spheres.
int run_info(const InfoOptions& options);

}  // namespace prism
