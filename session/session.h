// The job API: everything between "a scene file and some options" and "images and figures",
// so that every front end (prism render, compare, info, a batch runner, Python) is a thin
// caller and the rules live in one place (Cycles' session/, Mitsuba's
// Integrator::render(scene, sensor, seed, spp)).
//
// A Session loads one scene once and owns what renders of it share: the scene description,
// its built render scene (BVH, materials, lights), the colour pipelines and the worker
// threads. Each render(job) checks the job, reuses or builds the render scene its geometry
// choices need, renders on the session's threads and returns the image with its rays,
// timings and metadata. Rules that used to live in one command alone hold for every caller:
//   - geometry is rebased on the camera's position clamped into the geometry's bounds
//     (GeometryOptions::world_origin, rebasing_origin in renderer/camera.h), so rays, hits
//     and lights stay near 0 in float wherever the scene sits in the world and wherever
//     the camera stands;
//   - the resolution is the job's, or 480 high at the camera's aspect ratio (an
//     orthographic camera's xmag / ymag), bounded;
//   - the film's memory is estimated and checked against the budget before it is made;
//   - thread count is set once, by the session's task arena.
#pragma once

#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <Imath/ImathBox.h>
#include <tbb/task_arena.h>

#include "distributed/world.h"
#include "integrators/registry.h"
#include "renderer/geometry/embree_device.h"
#include "renderer/render_scene.h"
#include "renderer/scene_description.h"
#include "session/job.h"

namespace prism {

class Session {
 public:
  // Loads the scene: the glTF loader (LoadError on a broken file; RequestError "scene" for a
  // scene the file does not have), the default camera and light where the file has none,
  // and sphere detection when asked. Nothing is built yet.
  explicit Session(const SceneRequest& request, const SessionOptions& options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const SceneRequest& request() const { return request_; }
  const SceneDescription& scene() const { return scene_; }
  // The loader's and the defaults' warnings, one line each, without the file's name (the
  // caller names it once).
  const std::vector<std::string>& warnings() const { return scene_.warnings; }
  // With detect_spheres: one line per mesh replaced or kept (with the reason), then the count.
  const std::vector<std::string>& sphere_detection_report() const { return sphere_report_; }
  double load_seconds() const { return load_seconds_; }
  const SessionOptions& options() const { return options_; }
  // The MPI rank this session renders as and how many share its frames
  // (SessionOptions::distribute_frames); 0 of 1 otherwise. Only rank 0 gets whole images, so
  // a front end prints and writes on rank 0 alone.
  int rank() const { return world_ ? world_->rank() : 0; }
  int ranks() const { return world_ ? world_->size() : 1; }
  // Adds the default camera and light where the scene has none, unless done already; every
  // check and render does it first.
  void add_defaults();

  // Checks everything about `job` that needs no render: the integrator and its parameters,
  // the camera, the resolution, the reference image and the film's memory. Throws
  // RequestError naming the field. A batch checks every job before the first render.
  void check(const RenderJob& job);

  // Renders `job`: check, build or reuse the render scene, render on the session's threads.
  // Cancelling (callbacks.cancel) returns the tiles finished so far with result.cancelled.
  // The same as run(prepare(job), callbacks).
  RenderOutput render(const RenderJob& job, const JobCallbacks& callbacks = {});

  // A render split in two, so that several renders of one session can run at once (a
  // batch's small jobs side by side): prepare does everything before the tiles (check,
  // build or reuse the render scene, the camera, the integrator) and holds on to the render
  // scene; run renders the tiles, reading only what the prepared render holds.
  //   - prepare, like every other method, must not be called while another is;
  //   - run may be called from several threads at once, and while prepare is, as long as
  //     prepare is not asked to change what a running render holds: prepare_beside_running
  //     refuses (nullopt) instead of rebuilding or re-lighting a render scene that a prepared
  //     render holds, so its caller waits for those to finish and then calls prepare.
  class Prepared;
  Prepared prepare(const RenderJob& job);
  std::optional<Prepared> prepare_beside_running(const RenderJob& job);
  RenderOutput run(Prepared prepared, const JobCallbacks& callbacks = {});

  // The film `job` renders: its settings with the resolution settled (RequestError as check).
  RenderSettings film(const RenderJob& job) {
    add_defaults();
    return plan(job).film;
  }
  // What RenderOutput::warnings of `job` will say, without rendering (RequestError as check).
  std::vector<std::string> job_warnings(const RenderJob& job);
  // The index of the camera `job.camera` names (RequestError "camera" if none).
  int camera_index(const std::string& camera);
  // The camera `job` renders from: the file's (or the default) it names, or the one framing
  // the scene (`frame_scene`), moved by its placement. RequestError naming the option
  // ("camera", "look-at", "up", "fov") when it cannot be.
  CameraDescription camera(const RenderJob& job);
  // Cameras the file itself holds (the default camera comes after them).
  size_t file_cameras() const { return file_cameras_; }
  // The render scene a job with these choices renders, built on first use and kept until a
  // job needs other choices (one at a time: two BVHs would double the peak memory).
  // `build_seconds` receives the time spent building it now (0 when reused).
  const RenderScene& render_scene(const RenderJob& job, double* build_seconds = nullptr);
  // The quality `job` builds at: its own, or for BuildQuality::automatic the choice of
  // automatic_build_quality for the rays it expects, width x height x spp x (1 + the
  // integrator's max-depth, if it has one: each bounce another ray per sample), through the
  // scene's primitives (each mesh's triangles once, as instances share a mesh's BVH, and
  // the spheres).
  BuildQuality build_quality(const RenderJob& job);
  const ColourPipeline& colour(WorkingSpace space);
  // The environment `job` renders with (docs/lights.md): its map, else its uniform
  // background, else the default sky of a file without lights, else black. Read and made on
  // first use and kept until a job asks for another; RequestError "environment" for a map
  // that is missing, not an OpenEXR or Radiance HDR image, too large for the memory budget,
  // or holding a negative or non-finite texel.
  const Environment& environment(const RenderJob& job);
  // Bytes the session holds: the scene description (geometry, texels) and the BVH built
  // for it, as Embree reports it. What a cache of sessions weighs against its budget.
  uint64_t memory_bytes() const;

  // The session's thread limit: its arena's concurrency.
  int threads() const { return arena_->max_concurrency(); }

  // Runs `f` on the session's worker threads, within its thread limit.
  template <typename F>
  decltype(auto) execute(F&& f) {
    return arena_->execute(std::forward<F>(f));
  }

 private:
  // What a checked job resolves to.
  struct Plan {
    const IntegratorInfo* integrator = nullptr;
    ParameterValues parameters;
    int camera = 0;  // the file's camera the job names; -1 for one framing the scene
    CameraDescription camera_description;  // as placed
    RenderSettings film;
    std::vector<std::string> warnings;  // RenderOutput::warnings
  };
  Plan plan(const RenderJob& job) const;
  // What an environment is made from: a job's environment options and working space.
  using EnvironmentKey = std::tuple<std::string, float, float, bool, Imath::V3f, WorkingSpace>;
  static EnvironmentKey environment_key(const RenderJob& job);
  // prepare's work; with `beside_running`, nullopt where it would change a held scene.
  std::optional<Prepared> prepare(const RenderJob& job, bool beside_running);
  // render_scene's work; with `beside_running`, null where it would change a held scene.
  std::shared_ptr<const RenderScene> render_scene(const RenderJob& job, bool beside_running,
                                                  double* build_seconds);
  int find_camera(const std::string& camera) const;
  CameraDescription placed_camera(const RenderJob& job, int* index) const;
  // The film of `job` from `camera`: the job's resolution or the camera's default, with the
  // warnings it gives.
  RenderSettings film_for(const RenderJob& job, const CameraDescription& camera,
                          std::vector<std::string>* warnings) const;
  RenderMetadata metadata(const RenderJob& job, const Plan& plan, BuildQuality built_at,
                          const Camera& camera, const RenderOutput& output) const;

  SceneRequest request_;
  SessionOptions options_;
  const distributed::World* world_ = nullptr;  // with distribute_frames
  SceneDescription scene_;
  std::optional<Imath::Box3d> bounds_;  // scene_bounds(scene_), on first use
  std::vector<std::string> sphere_report_;
  bool defaults_added_ = false;
  size_t file_cameras_ = 0;
  double load_seconds_ = 0.0;
  std::shared_ptr<tbb::task_arena> arena_;
  // One Embree device for every render scene the session builds.
  std::shared_ptr<EmbreeDevice> device_;
  std::map<WorkingSpace, std::unique_ptr<ColourPipeline>> colours_;
  // The render scene kept, with the choices it was built for.
  struct BuiltScene {
    std::tuple<std::string, bool, BuildQuality, WorkingSpace, std::array<double, 3>,
               std::array<double, 3>, BrdfModel>
        key;
    // Shared with the prepared renders that hold it: a rebuild while they run leaves
    // theirs alive until they finish.
    std::shared_ptr<RenderScene> scene;
    // The environment set on it, as MadeEnvironment::key.
    EnvironmentKey environment_key;
  };
  BuiltScene built_;
  // The environment kept, with the job's choices it was made for.
  struct MadeEnvironment {
    EnvironmentKey key;
    Environment environment;
    bool made = false;
  };
  MadeEnvironment environment_;
};

class Session::Prepared {
 public:
  Prepared(Prepared&&) = default;
  Prepared& operator=(Prepared&&) = default;
  ~Prepared();
  const RenderSettings& film() const { return plan_.film; }

 private:
  friend class Session;
  Prepared() = default;
  RenderJob job_;
  Plan plan_;
  Image reference_;
  std::shared_ptr<const RenderScene> scene_;
  BuildQuality built_at_ = BuildQuality::automatic;
  std::unique_ptr<Integrator> integrator_;
  std::optional<Camera> camera_;
  RenderOutput out_;
};

}  // namespace prism
