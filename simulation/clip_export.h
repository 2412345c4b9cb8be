// A flock's clip as files `prism batch` renders: one glTF scene per frame (the boids as small
// oriented darts sharing one mesh, the obstacles as analytic PRISM_sphere spheres, a camera,
// a sun and a fill light, a floor) and one job file naming them, one job per frame.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Imath/ImathVec.h>
#include <nlohmann/json.hpp>

#include "simulation/flock_config.h"

namespace prism {

// Where the files of a clip go inside its folder.
struct ClipLayout {
  std::filesystem::path dir;
  int frames = 1;

  std::string frame_name(int frame) const;         // "frame_0007", digits enough for every frame
  std::filesystem::path scene(int frame) const;    // scenes/frame_0007.gltf
  std::filesystem::path exr(int frame) const;      // exr/frame_0007.exr
  std::filesystem::path preview(int frame) const;  // png/frame_0007.png
  std::filesystem::path job_file() const { return dir / "boids-jobs.json"; }
  std::filesystem::path contact_sheet() const { return dir / "contact-sheet.png"; }
  std::filesystem::path video() const { return dir / "clip.mp4"; }
};

// One frame's glTF document.
nlohmann::json frame_scene(const FlockParameters& flock, const ClipSettings& clip,
                           const std::vector<Imath::V3f>& positions,
                           const std::vector<Imath::V3f>& velocities);

// The batch job file (docs/batch.md, version 1) for every frame, paths relative to it.
nlohmann::json clip_jobs(const ClipSettings& clip, const ClipLayout& layout);

// The dart every boid is drawn as, in units of its radius: nose at +z, fitting inside the
// unit sphere so the drawn body lies within the body the simulation keeps off surfaces.
std::vector<Imath::V3f> dart_triangles();

// Runs the flock (warm-up, then steps_per_frame steps between frames) and writes the
// clip's scenes and job file into `dir`, each file atomically. The flock is built first, so
// a config it refuses writes nothing. `frame_written(i)` follows each frame.
ClipLayout write_clip(const FlockConfig& config, const std::filesystem::path& dir, int threads,
                      const std::function<void(int)>& frame_written = {});

}  // namespace prism
