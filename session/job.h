// What a caller asks the session for: a scene to load (SceneRequest) and renders of it
// (RenderJob), and what a render gives back (RenderOutput). Plain data, so a command line, a
// job file or Python can fill them alike; the session checks every field and names the one
// it refuses (RequestError).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "distributed/frame_split.h"
#include "integrators/parameters.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/image/colour.h"
#include "renderer/image/image.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/image_output.h"
#include "renderer/integrator.h"
#include "renderer/render.h"
#include "renderer/scene_features.h"
#include "scene_passes/sphere_detection.h"

namespace prism {

// A request the session cannot honour as asked: a camera the file does not have, a
// resolution out of range, an integrator parameter it does not take. `field` is the
// request's field spelled as its command-line flag without the dashes ("camera", "res",
// "max-depth"), so a command line can report "--camera ..." and a job file "jobs[3].camera".
// Anything else the session throws (std::runtime_error) is a scene or file that cannot be
// read or written.
struct RequestError : std::runtime_error {
  RequestError(std::string field_name, const std::string& message)
      : std::runtime_error(message), field(std::move(field_name)) {}
  std::string field;
};

struct SceneRequest {
  std::string path;                   // .gltf or .glb
  std::string scene;                  // the glTF scene, by name or index; empty = the file's
  bool allow_external_paths = false;  // buffers and images from outside the file's folder
  // Add a camera and a light where the file has none (scene_passes/scene_defaults.h). False
  // keeps the file's own until Session::add_defaults (prism info prints the file first).
  bool add_defaults = true;
  // Render meshes whose vertices lie on a sphere as analytic spheres (docs/spheres.md); the
  // session's warnings then say which were replaced and which kept.
  bool detect_spheres = false;
  SphereDetectionOptions sphere_detection;
};

struct SessionOptions {
  int threads = 0;  // worker threads for every build and render; 0 = every core
  // Several sessions may share one task arena (a batch bounds its total thread count so);
  // null: the session makes its own of `threads` threads.
  std::shared_ptr<tbb::task_arena> arena;
  // One budget for what a hostile file or an absurd option can make Prism allocate: the
  // loader charges geometry, texels and copies to it (LoadOptions::memory_limit), and a
  // render's film and sample buffers are estimated and checked against it before they are
  // made.
  uint64_t memory_budget_bytes = uint64_t{8} << 30;
  // Share each render's tiles with the other ranks an MPI launcher started with this process
  // (distributed/frame_split.h): every rank loads and builds the scene and renders the tiles
  // it claims, and rank 0's RenderOutput holds the whole image. Uniform sampling only: under
  // several ranks, adaptive sampling and a reference are refused (RequestError). Without a
  // launcher, a world of one: the same as false.
  bool distribute_frames = false;
};

// "640x480" -> 640, 480 (each 1 to kMaxImageSide); false for anything else.
inline constexpr int kMaxImageSide = 32768;
// Samples per pixel a job may ask for (--spp, --min-spp).
inline constexpr int kMaxSamplesPerPixel = 1 << 16;
bool parse_resolution(const std::string& text, int* width, int* height);

// An environment map for a job (docs/lights.md): an equirectangular (latitude-longitude)
// image, OpenEXR or Radiance HDR, in linear Rec.709, read by the session.
struct EnvironmentRequest {
  std::string path;               // empty: no map
  float rotation_degrees = 0.0f;  // about +Y, counter-clockwise seen from above
  float intensity = 1.0f;         // scales the map or the uniform background
  // Camera rays that leave the scene see black (with alpha 0, as every miss has) while the
  // environment still lights the scene and shows in reflections.
  bool hidden = false;
};

// Moves a camera: each field left out keeps the camera's own (a new eye alone keeps the
// direction of view; `up` is +Y unless given).
struct CameraPlacement {
  std::optional<V3d> look_from, look_at, up;
  std::optional<double> yfov_degrees;  // perspective cameras only, above 0 and below 180
};

struct RenderJob {
  std::string integrator = "whitted";       // a name in integrators/registry.h
  ParameterSettings integrator_parameters;  // any subset of its parameter table
  std::string camera;                       // by name or index; empty = the first
  // A camera that frames the scene's bounds as the default camera does, even when the file
  // has cameras (`camera` must then be empty).
  bool frame_scene = false;
  std::optional<CameraPlacement> placement;  // moves the camera chosen
  // Explicit image size, or (0, 0): 640 x 480, or 480 high at the camera's aspect ratio
  // (an orthographic camera's xmag / ymag).
  int width = 0, height = 0;
  // Samples and adaptive sampling; its width and height are settled by the session.
  RenderSettings film;
  WorkingSpace working_space = WorkingSpace::linear_rec709;
  // Light from beyond the scene: the map environment.path when set, else a uniform
  // environment of radiance `background` (RGB in the working space; black is none: a file
  // without lights then gets the default sky, scene_passes/scene_defaults.h). It lights the
  // scene and is seen by rays that leave it.
  Imath::V3f background{0.0f, 0.0f, 0.0f};
  EnvironmentRequest environment;
  // The glossy lobe: glTF's GGX, or the lecture's Phong (renderer/shading/bsdf.h).
  BrdfModel brdf = BrdfModel::gltf;
  // How the BVH is built; renders with the same choices share one build.
  SphereOptions spheres;
  bool robust = false;
  // `automatic`: by the rays the render expects per primitive (Session::build_quality).
  BuildQuality build_quality = BuildQuality::automatic;
  // Measure the error against this image after every pass (one sample per pixel per
  // pass); the figures go into the output and its metadata. Must be a regular EXR file of
  // the render's size.
  std::string reference_path;
};

struct PassError {
  int samples = 0;
  double rmse = 0.0, relmse = 0.0;
};

struct JobCallbacks {
  ProgressCallback progress;                         // tiles done, of tiles planned
  std::function<bool()> cancel;                      // polled per tile: true stops
  std::function<void(const PassError&)> pass_error;  // with a reference, after each pass
  // Checkpoints, as RenderCallbacks' (renderer/render.h): polled between passes; either
  // true hands the state to `save_checkpoint`, and `stop` then ends the render at that
  // pass boundary (RenderResult::stopped_at_checkpoint: nothing to write). `resume`
  // continues a saved state; it must match the job's film (session/checkpoint_file.h
  // reads one that does).
  std::function<bool()> checkpoint_due;
  std::function<bool()> stop;
  std::function<void(const RenderState&)> save_checkpoint;
  const RenderState* resume = nullptr;
  double pass_seconds = kDefaultPassSeconds;  // RenderCallbacks::pass_seconds
};

struct RenderOutput {
  Image image;
  RenderResult result;
  RenderSettings film;  // as rendered: the resolution settled
  // About this job, one line each as Session::warnings(), e.g. an orthographic camera whose
  // xmag was widened to the image's aspect ratio.
  std::vector<std::string> warnings;
  std::string integrator;      // its registry name
  ParameterValues parameters;  // every parameter of the integrator, as used
  int camera_index = 0;
  std::string camera_name;
  GeometryStatistics geometry;
  SceneFeatures features;
  size_t lights = 0;           // that deliver anything (RenderScene::lights)
  double build_seconds = 0.0;  // building the BVH for this job; 0 when an earlier job's was reused
  std::vector<PassError> pass_errors;  // with a reference
  // Samples per pixel the render continued from (JobCallbacks::resume), 0 when it started
  // at the beginning; its EXR records them as prism:resumedSamples.
  int resumed_samples = 0;
  RenderMetadata metadata;  // what its EXR records
  // With SessionOptions::distribute_frames: which rank this is and what the split cost. On
  // rank 0, `image` is the whole frame and `result` the frame's (rays summed over ranks,
  // seconds rank 0's until its image was whole); on the others, only their own tiles.
  distributed::FrameSplitStats frame_split;
};

}  // namespace prism
