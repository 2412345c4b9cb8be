// The batch runner: many renders in one process (Deadline's or Flamenco's job list on one
// machine, OSPRay Studio's batch mode). Jobs come from any front end as BatchJobSpec (a job
// file: apps/batch_file.h); the batch expands them into one render each, checks that no two
// write the same file, and renders them through the job API (session/session.h) so that:
//   - each scene is loaded and built once and reused by all its jobs, within a memory budget
//     (SceneCache, least recently used dropped first);
//   - every job runs on one task arena, whose size is the batch's thread count; small jobs
//     (kSideBySideTilesPerThread) render side by side, up to one per thread, each writing its own
//     files, while a larger one has every thread to itself and its files are written while
//     the next job renders;
//   - an output records its job's fingerprint (session/job_fingerprint.h), and a job whose
//     output exists with the fingerprint it would get now is skipped;
//   - a job that fails (a broken scene, a camera the file lacks, an output that cannot be
//     written) is recorded and the rest go on;
//   - outputs are written through temporaries renamed into place, the EXR last, so a kill at
//     any moment leaves each output either absent, old or complete.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "session/job.h"
#include "session/output_files.h"
#include "session/scene_cache.h"

namespace prism {

// Output paths of a job before expansion; each may hold the placeholders {scene} (the scene
// file's name without its extension), {camera}, {integrator}, {spp} and {job} (the job's
// name).
struct OutputPattern {
  std::string exr, preview, sample_counts;
};

// One job as a job file states it, with every option checked but lists (integrators, spp
// values) already expanded, and the cameras possibly "every camera of the scene".
struct BatchJobSpec {
  int file_index = 0;  // its position in the file's job list
  std::string name;    // the job's name
  SceneRequest scene;
  RenderJob render;  // render.camera as given ("" = the scene's first)
  bool every_camera = false;
  // What tells this render from the others its file job expanded into ("integrator whitted,
  // spp 16"), empty when the job had no lists.
  std::string variant;
  OutputPattern outputs;
  ExrPixelType pixel_type = ExrPixelType::float32;
  double checkpoint_interval = 0.0;  // the job's own; 0 = the batch's
};

// A problem with the batch as a whole, before anything renders: two jobs writing the same
// file, a placeholder that does not exist.
struct BatchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Why an output pattern cannot be substituted (a placeholder that is not one, a '{' left
// open), or "" when it can: a job file checks its jobs with it before planning, so that such
// a job fails alone (prism batch --keep-going) instead of the whole plan.
std::string placeholder_problem(const std::string& pattern);

// One render of the batch.
struct BatchJob {
  int index = 0;  // in the expanded list, the order of the file
  BatchJobSpec spec;
  std::string camera_label;  // what {camera} became
  OutputFiles files;
  std::string settings;  // canonical_settings: what its fingerprint hashes besides the files
  double cost = 0.0;     // estimated: pixels x samples x the integrator's relative cost
  std::string error;     // set when expanding it already failed (its scene cannot be loaded)
  // "jobs[3] 'name'", and the camera when the job expanded into several.
  std::string label() const;
};

enum class JobStatus { rendered, skipped, failed, cancelled };
inline constexpr EnumName<JobStatus> kJobStatusNames[] = {{JobStatus::rendered, "rendered"},
                                                          {JobStatus::skipped, "skipped"},
                                                          {JobStatus::failed, "failed"},
                                                          {JobStatus::cancelled, "cancelled"}};
constexpr std::span<const EnumName<JobStatus>> enum_names(JobStatus) {
  return kJobStatusNames;
}

// What became of one job: the report's row.
struct JobRecord {
  int index = 0;
  std::string label, name, scene, camera, integrator, output;
  int width = 0, height = 0, spp = 0;
  JobStatus status = JobStatus::cancelled;
  std::string error;            // failed: one line naming the field or file
  double seconds = 0.0;         // the job's own time: load and build it caused, render, write
  double render_seconds = 0.0;  // rendering alone
  double write_seconds = 0.0;   // writing its files
  double load_seconds = 0.0;    // loading its scene, when this job caused it
  double build_seconds = 0.0;   // building its BVH, when this job caused it
  int resumed_samples = 0;      // samples per pixel continued from a checkpoint
  int rank = 0;                 // the MPI rank that ran it
  bool side_by_side = false;    // rendered as a small job, beside others
  uint64_t rays = 0;
  double rays_per_second = 0.0;
  uint64_t scene_bytes = 0;                  // what its scene's session held after the render
  std::optional<PassError> reference_error;  // with a reference image
};

// A job with fewer tiles than this per thread of the batch renders beside others: at the end
// of a job's tiles about one tile per thread is left, so with fewer than this many each the
// idle tail is more than an eighth of the job. On 2 threads a 320 x 240 job (300 tiles of
// 16 x 16) renders alone, which measured faster there than two side by side; on 64 it is
// small.
inline constexpr int kSideBySideTilesPerThread = 8;

struct BatchOptions {
  int threads = 0;                                       // the whole batch's; 0 = every core
  uint64_t memory_budget_bytes = uint64_t{8} << 30;      // the scenes kept loaded
  uint64_t load_memory_limit_bytes = uint64_t{8} << 30;  // each load's (SessionOptions)
  bool force = false;                                    // render even up-to-date jobs
  // Seconds between a running job's checkpoints (OUTPUT.checkpoint beside its output,
  // session/checkpoint_file.h), which a later run continues from; 0 = none, and then a
  // stopped job starts over.
  double checkpoint_interval = 300.0;
  // Spread the jobs over the ranks an MPI launcher started (distributed/world.h): each rank
  // claims the next job as it becomes free, and rank 0's records are every rank's.
  bool distribute_jobs = false;
  // Small jobs render side by side (kSideBySideTilesPerThread); false: one job at a time.
  bool side_by_side = true;
};

// Small jobs render side by side, so job_finished, progress, abandon, stop and
// checkpoint_now may be called from several threads at once; job_started is called on the
// thread that called Batch::run, in the order jobs start.
struct BatchCallbacks {
  std::function<void(const BatchJob&)> job_started;
  std::function<void(const JobRecord&)> job_finished;
  // The running job's tiles, as JobCallbacks::progress.
  std::function<void(const BatchJob&, int tiles_done, int tiles_total)> progress;
  // Polled between jobs and per tile: true stops starting jobs and abandons the running one
  // (nothing of it is written; its last checkpoint stays).
  std::function<bool()> abandon;
  // Polled between jobs and passes: true stops starting jobs and ends the running one at its
  // next pass boundary with a checkpoint (what a scheduler's SIGTERM before preemption asks).
  std::function<bool()> stop;
  // Polled between passes: true saves the running job's checkpoint now and carries on.
  std::function<bool()> checkpoint_now;
};

class Batch {
 public:
  Batch(std::vector<BatchJobSpec> specs, const BatchOptions& options);
  ~Batch();

  // Expands every spec into its renders (loading the scenes of jobs that render every
  // camera, to know them) and substitutes the placeholders. Throws BatchError when two
  // renders would write the same file or a path keeps a placeholder that is not one.
  // A job whose scene fails to load stays one render, with BatchJob::error set.
  const std::vector<BatchJob>& plan();

  // The renders of shard `shard` of `shards`: the expanded list split by estimated cost
  // (each job to the shard with the least cost so far, the costliest first, ties to the
  // lower shard), the same on every machine that plans the same file; in the list's order.
  std::vector<BatchJob> shard(int shard, int shards);

  // Renders `jobs` (a plan or a shard of it), grouped by scene so each is loaded once, and
  // returns one record per job in the order of `jobs`. With distribute_jobs under several
  // ranks every rank must call it with the same jobs; rank 0 gets every rank's records, the
  // others their own (the rest cancelled).
  std::vector<JobRecord> run(const std::vector<BatchJob>& jobs, const BatchCallbacks& callbacks);

  // Whether the output of `job` exists with the fingerprint the job would record now.
  bool up_to_date(const BatchJob& job);

  const SceneCache& scenes() const { return *cache_; }
  // Scene loads and evictions of the last run, over every rank (at rank 0).
  int scene_loads() const { return scene_loads_; }
  int scene_evictions() const { return scene_evictions_; }

 private:
  struct RunningJob;
  // Whether `job` is small enough to render beside others (kSideBySideTilesPerThread).
  bool side_by_side(const BatchJob& job) const;
  // On the batch's own thread: the job's scene from the cache, its checks, checkpoint and
  // prepared render (Session::prepare_beside_running when `beside_running`, else after
  // `wait_for_running`); null, with the record failed, when it cannot render.
  std::unique_ptr<RunningJob> prepare_job(const BatchJob& job, JobRecord* record,
                                          std::chrono::steady_clock::time_point start,
                                          bool beside_running,
                                          const std::function<void()>& wait_for_running);
  // On any thread of the arena: renders a prepared job and fills its record.
  void render_prepared(RunningJob* running, const BatchCallbacks& callbacks);
  // Writes a rendered job's files (on the calling thread, compressing on it alone).
  void write_now(RunningJob* running);
  // Writes them on one task of the arena while the batch goes on.
  void write_in_background(std::unique_ptr<RunningJob> running, const BatchCallbacks& callbacks);
  std::string fingerprint(const BatchJob& job, const std::vector<InputFile>& inputs) const;

  std::vector<BatchJobSpec> specs_;
  BatchOptions options_;
  std::shared_ptr<tbb::task_arena> arena_;
  std::unique_ptr<SceneCache> cache_;
  std::vector<BatchJob> planned_;
  bool planned_done_ = false;
  int scene_loads_ = 0, scene_evictions_ = 0;
  // Sessions whose load a job's record carries; weak, and compared by owner, so that an
  // evicted session is neither kept alive nor mistaken for a later one at its address.
  std::set<std::weak_ptr<Session>, std::owner_less<>> charged_loads_;
  // The files of the last rendered job, written while the next one renders.
  struct PendingWrite;
  std::unique_ptr<PendingWrite> pending_;
  void finish_write(const BatchCallbacks& callbacks);
  // SIGUSR2-style requests for a checkpoint seen so far, so that every running job saves.
  std::atomic<uint64_t> checkpoint_requests_{0};
};

}  // namespace prism
