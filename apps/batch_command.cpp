#include "apps/batch_command.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

#include <nlohmann/json.hpp>

#include "apps/batch_file.h"
#include "apps/command_line.h"
#include "apps/progress_bar.h"
#include "apps/stop_signals.h"
#include "distributed/world.h"
#include "renderer/version.h"
#include "session/batch.h"
#include "session/batch_records.h"

namespace prism {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string gib(uint64_t bytes) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g GiB", static_cast<double>(bytes) / (1 << 30));
  return buffer;
}

// "K/N", 0 <= K < N, or a UsageError.
void parse_shard(const std::string& text, int* shard, int* shards) {
  int k = 0, n = 0;
  char slash = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &k, &slash, &n, &extra) != 3 || slash != '/' || n < 1 ||
      k < 0 || k >= n)
    throw UsageError("--shard " + text + ": expected K/N with 0 <= K < N (e.g. " +
                     "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)");
  *shard = k;
  *shards = n;
}

// The deepest folder holding every output: where the report goes by default.
fs::path common_folder(const std::vector<BatchJob>& jobs, const fs::path& fallback) {
  std::optional<fs::path> common;
  for (const BatchJob& job : jobs) {
    const fs::path folder = fs::absolute(job.files.image).lexically_normal().parent_path();
    if (!common) {
      common = folder;
      continue;
    }
    fs::path shared;
    for (auto a = common->begin(), b = folder.begin();
         a != common->end() && b != folder.end() && *a == *b; ++a, ++b)
      shared /= *a;
    common = shared;
  }
  return common && !common->empty() ? *common : fallback;
}

void write_report(const fs::path& path, const json& report) {
  const fs::path temporary = path.string() + ".tmp";
  // Beside the outputs, whose folder a batch whose every job failed may not have made.
  std::error_code made;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), made);
  {
    std::ofstream out(temporary);
    out << report.dump(2) << "\n";
    if (!out)
      throw std::runtime_error(path.string() + ": the report cannot be written there (" +
                               temporary.string() + ")");
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) throw std::runtime_error(path.string() + ": " + error.message());
}

void print_table(const std::vector<JobRecord>& records) {
  std::printf("%-5s %-9s %9s %10s  %-s\n", "job", "status", "seconds", "Mrays/s", "what");
  for (const JobRecord& r : records)
    std::printf("%-5d %-9s %9.3f %10.3g  %s -> %s%s%s\n", r.index, to_string(r.status), r.seconds,
                r.rays_per_second / 1e6, r.label.c_str(), r.output.c_str(),
                r.error.empty() ? "" : ": ", r.error.c_str());
}

// One line on a terminal: the jobs done, the share of the whole batch with an ETA, and the
// running jobs (small ones render side by side) with their shares.
class BatchProgress {
 public:
  BatchProgress(bool enabled, size_t jobs)
      : terminal_(enabled && isatty(STDERR_FILENO)), enabled_(enabled), jobs_(jobs) {}
  void started(const BatchJob& job) {
    std::lock_guard lock(mutex_);
    running_[job.index] = {job.label(), 0.0};
  }
  void tiles(const BatchJob& job, int done, int total) {
    if (!terminal_ || total <= 0) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    if (auto it = running_.find(job.index); it != running_.end())
      it->second.fraction = static_cast<double>(done) / total;
    const auto now = Clock::now();
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    draw();
  }
  void finished(const JobRecord& r) {
    std::lock_guard lock(mutex_);
    ++done_;
    running_.erase(r.index);
    if (!enabled_) return;
    if (terminal_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "prism: [%zu/%zu] %s %s %.3f s%s%s\n", done_, jobs_, to_string(r.status),
                 r.label.c_str(), r.seconds, r.error.empty() ? "" : ": ", r.error.c_str());
  }
  void finish() {
    if (terminal_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  struct Running {
    std::string label;
    double fraction = 0.0;
  };
  void draw() {
    double running = 0.0;
    for (const auto& [index, job] : running_) running += job.fraction;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double overall = (static_cast<double>(done_) + running) / static_cast<double>(jobs_);
    const double eta = overall > 0.0 ? elapsed * (1.0 - overall) / overall : 0.0;
    std::string jobs;
    for (const auto& [index, job] : running_)
      jobs += (jobs.empty() ? "" : ", ") + job.label + " " +
              std::to_string(static_cast<int>(job.fraction * 100.0)) + "%";
    const std::string line = "[" + std::to_string(done_) + "/" + std::to_string(jobs_) + " jobs] " +
                             std::to_string(static_cast<int>(overall * 100.0)) + "%  ETA " +
                             std::to_string(static_cast<long>(eta + 0.5)) + "s  " + jobs;
    // Cut to the terminal's width, so that the line never wraps.
    const size_t columns = static_cast<size_t>(std::max(20, terminal_columns()));
    std::fprintf(stderr, "\r\033[K%s", line.substr(0, columns - 1).c_str());
    std::fflush(stderr);
  }
  bool terminal_, enabled_;
  size_t jobs_, done_ = 0;
  std::map<int, Running> running_;  // by job index
  std::mutex mutex_;
  Clock::time_point start_ = Clock::now(), last_{};
};

// The command that continues this run: the same jobs (its shard, --keep-going's) and the same
// report; not --force, which would render again what is now done.
std::string resume_command(const BatchCommandOptions& o) {
  std::string command = "prism batch " + o.job_file;
  if (o.keep_going) command += " --keep-going";
  if (!o.shard.empty()) command += " --shard " + o.shard;
  if (!o.report.empty()) command += " --report " + o.report;
  return command;
}

int run(const BatchCommandOptions& o) {
  const auto wall_start = Clock::now();
  int shard = 0, shards = 1;
  if (!o.shard.empty()) parse_shard(o.shard, &shard, &shards);
  JobFile file = read_job_file(o.job_file);
  for (const JobFileError& e : file.errors)
    std::fprintf(stderr, "prism: error: %s: %s\n", o.job_file.c_str(), e.describe().c_str());
  if (!file.errors.empty() && (file.specs.empty() || !o.keep_going)) {
    if (file.jobs > 0)
      std::fprintf(stderr, "prism: %zu of %d jobs invalid: nothing rendered%s\n",
                   file.errors.size(), file.jobs,
                   file.specs.empty() ? "" : " (--keep-going renders the rest)");
    return 2;
  }

  BatchOptions options;
  options.threads = o.threads;
  options.force = o.force;
  options.checkpoint_interval = o.checkpoint_interval;
  options.side_by_side = !o.one_at_a_time;
  options.distribute_jobs = true;  // under mpirun; a plain run is a world of one
  options.memory_budget_bytes = static_cast<uint64_t>(o.memory_budget_gib * double(1 << 30));
  options.load_memory_limit_bytes = static_cast<uint64_t>(o.memory_limit_gib * double(1 << 30));
  Batch batch(std::move(file.specs), options);
  std::vector<BatchJob> jobs;
  try {
    batch.plan();
    jobs = batch.shard(shard, shards);
  } catch (const BatchError& e) {
    std::fprintf(stderr, "prism: error: %s: %s\n", o.job_file.c_str(), e.what());
    return 2;
  }

  // Every rank plans the same file and claims jobs from it; rank 0 alone prints and reports.
  const distributed::World& world = distributed::World::process();
  const bool root = world.root();
  if (o.dry_run) {
    if (!root) return 0;
    for (const BatchJob& job : jobs) {
      const RenderJob& r = job.spec.render;
      const std::string res = r.width > 0 ? std::to_string(r.width) + "x" + std::to_string(r.height)
                                          : std::string("default");
      const char* state = !job.error.empty()      ? "fails"
                          : batch.up_to_date(job) ? "up to date"
                                                  : "to render";
      std::printf("%4d  %s  %s  camera %s  %s  %d spp  %s  -> %s  [%s%s%s]\n", job.index,
                  job.label().c_str(), job.spec.scene.path.c_str(), job.camera_label.c_str(),
                  r.integrator.c_str(), r.film.spp, res.c_str(), job.files.image.c_str(), state,
                  job.error.empty() ? "" : ": ", job.error.c_str());
    }
    std::printf("%zu renders%s\n", jobs.size(), shards > 1 ? (" in shard " + o.shard).c_str() : "");
    return 0;
  }

  // Before the first job: a SIGTERM while a scene loads is not lost either.
  StopSignalScope signals(true);
  BatchProgress progress(root && !o.quiet, jobs.size());
  BatchCallbacks callbacks;
  callbacks.job_started = [&](const BatchJob& job) {
    if (o.verbose && root) {
      progress.finish();
      std::fprintf(stderr, "prism: starting job %d: %s: %s, camera %s -> %s\n", job.index,
                   job.label().c_str(), job.spec.scene.path.c_str(), job.camera_label.c_str(),
                   job.files.image.c_str());
    }
    progress.started(job);
  };
  callbacks.progress = [&](const BatchJob& job, int done, int total) {
    progress.tiles(job, done, total);
  };
  callbacks.job_finished = [&](const JobRecord& r) { progress.finished(r); };
  callbacks.abandon = [] { return interrupted(); };
  callbacks.stop = [] { return stop_requested(); };
  callbacks.checkpoint_now = [] { return checkpoint_requested(); };
  std::vector<JobRecord> records = batch.run(jobs, callbacks);
  signals.restore();
  progress.finish();
  // Jobs the file got wrong, kept going past, are failures of this batch too.
  for (const JobFileError& e : file.errors) {
    JobRecord r;
    r.index = -1;
    r.label = "jobs[" + std::to_string(e.job) + "] '" + e.name + "'";
    r.name = e.name;
    r.status = JobStatus::failed;
    r.error = (e.field.empty() ? "" : e.field + ": ") + e.message;
    records.push_back(r);
  }

  if (!root) return 0;
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  size_t counts[4] = {};
  double job_seconds = 0.0;
  for (const JobRecord& r : records) {
    ++counts[static_cast<size_t>(r.status)];
    job_seconds += r.render_seconds + r.write_seconds + r.load_seconds + r.build_seconds;
  }
  json report = {{"version", 1},
                 {"prism", std::string(kVersion) + " " + kBuildCommit},
                 {"job_file", fs::absolute(o.job_file).lexically_normal().string()},
                 {"shard", std::to_string(shard) + "/" + std::to_string(shards)},
                 {"ranks", world.size()},
                 {"wall_seconds", wall},
                 {"scenes_loaded", batch.scene_loads()},
                 {"scenes_evicted", batch.scene_evictions()},
                 {"jobs", json::array()}};
  for (const JobRecord& r : records) report["jobs"].push_back(record_json(r));
  for (const EnumName<JobStatus>& s : kJobStatusNames)
    report["counts"][s.name] = counts[static_cast<size_t>(s.value)];
  fs::path report_path = o.report;
  if (report_path.empty()) {
    report_path = common_folder(jobs, fs::absolute(o.job_file).parent_path()) /
                  (shards > 1 ? "batch-report-" + std::to_string(shard) + "-of-" +
                                    std::to_string(shards) + ".json"
                              : std::string("batch-report.json"));
  }
  write_report(report_path, report);

  if (!o.quiet) {
    print_table(records);
    std::printf(
        "%zu rendered, %zu skipped, %zu failed, %zu cancelled in %.3f s (jobs' own load, build, "
        "render and write %.3f s); %d scene loads, %d evicted, %s kept\n",
        counts[0], counts[1], counts[2], counts[3], wall, job_seconds, batch.scene_loads(),
        batch.scene_evictions(), gib(batch.scenes().bytes()).c_str());
    std::printf("report       %s\n", report_path.c_str());
  }
  if (const int signal = stop_signal()) {
    std::fprintf(stderr, "prism: stopped by %s: no job half-written%s; to resume, run: %s\n",
                 stop_signal_name(signal),
                 signal == SIGINT ? "" : ", the running one saved a checkpoint",
                 resume_command(o).c_str());
    return 128 + signal;
  }
  return counts[static_cast<size_t>(JobStatus::failed)] > 0 ? 1 : 0;
}

}  // namespace

CLI::App* add_batch_command(CLI::App& app, BatchCommandOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "batch", "Render every job of a job file (docs/batch.md), each scene loaded once");
  cmd->add_option("jobs", o->job_file, "Job file (.json, docs/batch.md)")->required();
  cmd->add_flag("--dry-run", o->dry_run, "Print the renders the file expands into and stop");
  cmd->add_flag("--force", o->force, "Render jobs whose outputs are up to date too");
  cmd->add_flag("--keep-going", o->keep_going,
                "Render the valid jobs of a file that has invalid ones (they count as failed)");
  cmd->add_option("--threads", o->threads, "Worker threads for the whole batch (0 = all cores)")
      ->check(whole_number(0, 1024))
      ->capture_default_str();
  cmd->add_flag("--one-at-a-time", o->one_at_a_time,
                "Render one job at a time (by default small jobs render side by side)");
  cmd->add_option("--memory-budget", o->memory_budget_gib,
                  "GiB the scenes kept loaded between jobs may hold (least recently used "
                  "dropped first)")
      ->check(CLI::Range(0.0, 1024.0))
      ->capture_default_str();
  add_memory_limit_option(cmd, &o->memory_limit_gib);
  cmd->add_option("--shard", o->shard,
                  "K/N: render only shard K (0-based) of N, balanced by estimated cost (Slurm "
                  "arrays, Kubernetes indexed jobs)");
  cmd->add_option("--report", o->report,
                  "Where to write the JSON report (default: batch-report.json in the folder "
                  "holding every output)");
  cmd->add_option("--checkpoint-interval", o->checkpoint_interval,
                  "Seconds between a running job's checkpoints (OUTPUT.checkpoint), which the "
                  "next run continues from; SIGTERM and SIGUSR1 save one and stop; 0 = none")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  add_verbosity_flags(cmd, &o->quiet, &o->verbose, "No progress and no summary table",
                      "Also say when each job starts, with its scene, camera and output");
  return cmd;
}

int run_batch(const BatchCommandOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
