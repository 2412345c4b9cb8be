#include "session/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <span>

#include <tbb/task_group.h>

#include "distributed/world.h"
#include "renderer/image/image_metrics.h"
#include "session/batch_records.h"
#include "session/checkpoint_file.h"

namespace prism {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A camera's name as a file-name part: what is not a letter, digit, '.', '-' or '_' becomes
// '_', so a name with a slash cannot reach another folder.
std::string file_name_part(const std::string& text) {
  std::string out;
  for (char c : text)
    out +=
        (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') ? c : '_';
  return out;
}

// Relative cost per sample of each integrator, for balancing shards: what a camera ray sets
// off (shadow rays, reflections) on a typical scene.
double integrator_cost(const std::string& integrator) {
  if (integrator == "phong") return 1.0;
  if (integrator == "shadow") return 1.5;
  return 2.5;
}

const std::set<std::string> kPlaceholders = {"scene", "camera", "integrator", "spp", "job"};

std::string substitute(const std::string& pattern, const std::map<std::string, std::string>& values,
                       const std::string& where) {
  if (const std::string problem = placeholder_problem(pattern); !problem.empty())
    throw BatchError(where + ": " + problem);
  std::string out;
  size_t i = 0;
  while (i < pattern.size()) {
    const size_t open = pattern.find('{', i);
    if (open == std::string::npos) {
      out += pattern.substr(i);
      break;
    }
    const size_t close = pattern.find('}', open);
    out += pattern.substr(i, open - i) + values.at(pattern.substr(open + 1, close - open - 1));
    i = close + 1;
  }
  return out;
}

std::string same_file_key(const std::string& path) {
  std::error_code error;
  const fs::path p = fs::weakly_canonical(path, error);
  return error ? fs::absolute(path).lexically_normal().string() : p.string();
}

// The record's description of its job (everything but what happened to it).
void describe(const BatchJob& job, JobRecord* record) {
  record->index = job.index;
  record->label = job.label();
  record->name = job.spec.name;
  record->scene = job.spec.scene.path;
  record->camera = job.camera_label;
  record->integrator = job.spec.render.integrator;
  record->output = job.files.image;
  record->spp = job.spec.render.film.spp;
  if (record->width == 0) {
    record->width = job.spec.render.width;
    record->height = job.spec.render.height;
  }
}

// Every rank's records of the jobs it ran, at rank 0; slots no rank ran stay cancelled.
void gather_records(const distributed::World& world, const std::vector<uint8_t>& ran,
                    std::vector<JobRecord>* records) {
  nlohmann::json mine = nlohmann::json::array();
  for (size_t slot = 0; slot < records->size(); ++slot)
    if (ran[slot]) mine.push_back({{"slot", slot}, {"record", record_json((*records)[slot])}});
  const std::string text = mine.dump();
  const auto all = distributed::gather_at_root(
      world, std::as_bytes(std::span<const char>(text.data(), text.size())));
  if (!world.root()) return;
  for (size_t rank = 1; rank < all.size(); ++rank) {
    const auto& bytes = all[rank];
    const nlohmann::json theirs = nlohmann::json::parse(
        std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    for (const nlohmann::json& item : theirs) {
      const size_t slot = item.at("slot").get<size_t>();
      if (slot < records->size()) (*records)[slot] = record_from_json(item.at("record"));
    }
  }
}

// A job that threw: its record names the field when the request was at fault.
void record_failure(const std::exception& e, JobRecord* record) {
  record->status = JobStatus::failed;
  const auto* request = dynamic_cast<const RequestError*>(&e);
  record->error = request ? request->field + ": " + e.what() : e.what();
}

}  // namespace

std::string placeholder_problem(const std::string& pattern) {
  for (size_t open = pattern.find('{'); open != std::string::npos;
       open = pattern.find('{', open + 1)) {
    const size_t close = pattern.find('}', open);
    if (close == std::string::npos) return pattern + ": '{' without a closing '}'";
    const std::string name = pattern.substr(open + 1, close - open - 1);
    if (!kPlaceholders.count(name))
      return pattern + ": no placeholder {" + name +
             "} (there are {scene}, {camera}, {integrator}, {spp} and {job})";
  }
  return "";
}

std::string BatchJob::label() const {
  std::string text = "jobs[" + std::to_string(spec.file_index) + "] '" + spec.name + "'";
  std::string parts = spec.variant;
  if (spec.every_camera) parts = "camera " + camera_label + (parts.empty() ? "" : ", " + parts);
  return parts.empty() ? text : text + " (" + parts + ")";
}

struct Batch::PendingWrite {
  tbb::task_group group;
  std::unique_ptr<RunningJob> running;  // keeps its scene, and so its colour pipelines, alive
};

Batch::Batch(std::vector<BatchJobSpec> specs, const BatchOptions& options)
    : specs_(std::move(specs)),
      options_(options),
      arena_(std::make_shared<tbb::task_arena>(
          options.threads > 0 ? options.threads : int{tbb::task_arena::automatic})) {
  SessionOptions session;
  session.threads = options.threads;
  session.arena = arena_;
  session.memory_budget_bytes = options.load_memory_limit_bytes;
  cache_ = std::make_unique<SceneCache>(options.memory_budget_bytes, session);
}

Batch::~Batch() {
  if (pending_) arena_->execute([&] { pending_->group.wait(); });
}

const std::vector<BatchJob>& Batch::plan() {
  if (planned_done_) return planned_;
  std::map<std::string, std::string> written;  // file -> the job writing it
  for (const BatchJobSpec& spec : specs_) {
    std::vector<std::pair<std::string, std::string>> cameras;  // (render.camera, label)
    std::string error;
    if (spec.every_camera) {
      const auto entry = cache_->get(spec.scene);
      if (!entry->session) {
        error = entry->error;
        cameras.push_back({"", "all"});
      } else {
        const auto& list = entry->session->scene().cameras;
        std::map<std::string, int> uses;
        for (const auto& c : list) ++uses[file_name_part(c.name)];
        for (size_t i = 0; i < list.size(); ++i) {
          const std::string name = file_name_part(list[i].name);
          cameras.push_back({std::to_string(i),
                             name.empty() || uses[name] > 1 ? "camera" + std::to_string(i) : name});
        }
      }
    } else {
      cameras.push_back({spec.render.camera, spec.render.camera.empty()
                                                 ? "default"
                                                 : file_name_part(spec.render.camera)});
    }
    for (const auto& [camera, label] : cameras) {
      BatchJob job;
      job.index = static_cast<int>(planned_.size());
      job.spec = spec;
      job.spec.render.camera = camera;
      job.camera_label = label;
      job.error = error;
      const std::map<std::string, std::string> values = {
          {"scene", fs::path(spec.scene.path).stem().string()},
          {"camera", label},
          {"integrator", spec.render.integrator},
          {"spp", std::to_string(spec.render.film.spp)},
          {"job", file_name_part(spec.name)}};
      const std::string where = job.label();
      job.files.image = substitute(spec.outputs.exr, values, where + ": output");
      if (!spec.outputs.preview.empty())
        job.files.preview = substitute(spec.outputs.preview, values, where + ": preview");
      if (!spec.outputs.sample_counts.empty())
        job.files.sample_counts =
            substitute(spec.outputs.sample_counts, values, where + ": sample-count-image");
      job.files.pixel_type = spec.pixel_type;
      job.files.create_directories = true;
      for (const std::string* path :
           {&job.files.image, &job.files.preview, &job.files.sample_counts}) {
        if (path->empty()) continue;
        const auto [it, added] = written.emplace(same_file_key(*path), where);
        if (!added)
          throw BatchError(where + " and " + it->second + " would both write " + *path +
                           ": give the output a placeholder that tells them apart ({scene}, "
                           "{camera}, {integrator}, {spp} or {job})");
      }
      if (job.error.empty()) {
        try {
          check_output_files(job.files, spec.scene.path);
        } catch (const RequestError& e) {
          job.error = e.field + ": " + e.what();
        }
      }
      job.settings = canonical_settings(job.spec.scene, job.spec.render, job.spec.pixel_type);
      const double pixels = job.spec.render.width > 0 ? static_cast<double>(job.spec.render.width) *
                                                            job.spec.render.height
                                                      : 640.0 * 480.0;
      job.cost = job.error.empty() ? pixels * std::max(1, job.spec.render.film.spp) *
                                         integrator_cost(job.spec.render.integrator)
                                   : 1.0;
      planned_.push_back(std::move(job));
    }
  }
  planned_done_ = true;
  return planned_;
}

std::vector<BatchJob> Batch::shard(int shard, int shards) {
  const std::vector<BatchJob>& jobs = plan();
  std::vector<size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return jobs[a].cost > jobs[b].cost; });
  std::vector<double> load(static_cast<size_t>(std::max(1, shards)), 0.0);
  std::vector<int> owner(jobs.size(), 0);
  for (size_t i : order) {
    const size_t least =
        static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[least] += jobs[i].cost;
    owner[i] = static_cast<int>(least);
  }
  std::vector<BatchJob> mine;
  for (size_t i = 0; i < jobs.size(); ++i)
    if (owner[i] == shard) mine.push_back(jobs[i]);
  return mine;
}

std::string Batch::fingerprint(const BatchJob& job, const std::vector<InputFile>& inputs) const {
  return job_fingerprint(job.settings, inputs);
}

bool Batch::up_to_date(const BatchJob& job) {
  const std::optional<std::string> stored = read_exr_attribute(job.files.image, "jobFingerprint");
  const std::optional<std::string> inputs_text = read_exr_attribute(job.files.image, "jobInputs");
  if (!stored || !inputs_text) return false;
  std::vector<InputFile> recorded;
  if (!parse_inputs(*inputs_text, &recorded) || recorded.empty()) return false;
  // The files the output was rendered from, hashed as they are now.
  std::vector<InputFile> now;
  try {
    for (const InputFile& input : recorded) now.push_back({input.path, content_hash(input.path)});
  } catch (const std::exception&) {
    return false;  // an input is gone: render again, and let the load say why if it fails
  }
  // The master is written last, but a preview deleted since must be made again.
  for (const std::string* other : {&job.files.preview, &job.files.sample_counts})
    if (!other->empty() && !fs::exists(*other)) return false;
  return fingerprint(job, now) == *stored;
}

// A job between its preparation on the batch's own thread and the end of its render (on
// any of the arena's threads): what its callbacks and its record need, at a fixed address.
struct Batch::RunningJob {
  const BatchJob* job = nullptr;
  JobRecord* record = nullptr;
  std::shared_ptr<const SceneCache::Entry> entry;
  std::optional<Session::Prepared> prepared;
  const ColourPipeline* colour = nullptr;
  std::string job_print, checkpoint;
  std::optional<RenderState> resume;
  double interval = 0.0;
  Clock::time_point start, last_save;
  uint64_t checkpoint_requests_seen = 0;
  std::string save_error;
  RenderOutput output;  // rendered, until its files are written
};

bool Batch::side_by_side(const BatchJob& job) const {
  // A small job spends much of its time where its own tiles cannot fill every thread (its
  // preparation, the last tiles, compressing its EXR), which a neighbour's tiles fill; a job
  // with enough tiles keeps every thread busy by itself, and beside another only shares
  // the caches.
  const RenderJob& r = job.spec.render;
  const int64_t width = r.width > 0 ? r.width : 640, height = r.height > 0 ? r.height : 480;
  const int64_t tile = std::max(1, r.film.tile_size);
  const int64_t tiles = ((width + tile - 1) / tile) * ((height + tile - 1) / tile);
  return tiles < int64_t{kSideBySideTilesPerThread} * arena_->max_concurrency();
}

std::vector<JobRecord> Batch::run(const std::vector<BatchJob>& jobs,
                                  const BatchCallbacks& callbacks) {
  std::vector<JobRecord> records(jobs.size());
  // Described before the first job: job_finished callbacks print the label and output.
  for (size_t slot = 0; slot < jobs.size(); ++slot) describe(jobs[slot], &records[slot]);
  // Grouped by scene in the order scenes first appear, so each is loaded once even when a
  // job file interleaves them; the same order on every run.
  std::vector<size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  {
    std::map<std::string, size_t> first;
    for (size_t i = 0; i < jobs.size(); ++i) first.emplace(SceneCache::key(jobs[i].spec.scene), i);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return first[SceneCache::key(jobs[a].spec.scene)] <
             first[SceneCache::key(jobs[b].spec.scene)];
    });
  }
  const distributed::World* world =
      options_.distribute_jobs ? &distributed::World::process() : nullptr;
  std::unique_ptr<distributed::SharedCounter> claims;
  if (world && world->size() > 1) claims = std::make_unique<distributed::SharedCounter>(*world);
  std::vector<uint8_t> ran(jobs.size(), 0);
  std::atomic<bool> stopping{false};
  // Small jobs render side by side: at most one per thread at once, each on the arena's
  // threads with its tiles, so one job's serial parts overlap the others' tiles.
  const int most_side_by_side = options_.side_by_side ? arena_->max_concurrency() : 1;
  std::atomic<int> side_by_side_running{0}, writes_waiting{0};
  tbb::task_group side_by_side_group;
  // A job that did not render: its time is all its own.
  auto finish = [&](JobRecord& record, Clock::time_point start) {
    record.seconds = seconds_since(start);
    if (callbacks.job_finished) callbacks.job_finished(record);
  };
  arena_->execute([&] {
    // The main loop runs inside the arena, so that its thread takes tiles while it waits.
    for (size_t position = 0; position < order.size(); ++position) {
      if (stopping || (callbacks.stop && callbacks.stop()) ||
          (callbacks.abandon && callbacks.abandon())) {
        stopping = true;
        break;
      }
      // Several ranks claim positions as each becomes free: the next job goes to whichever
      // rank is idle first, so a long job does not hold up the rest.
      if (claims) {
        position = static_cast<size_t>(claims->next());
        if (position >= order.size()) break;
      }
      const size_t slot = order[position];
      const BatchJob& job = jobs[slot];
      JobRecord& record = records[slot];
      ran[slot] = 1;
      record.rank = world ? world->rank() : 0;
      if (callbacks.job_started) callbacks.job_started(job);
      const auto start = Clock::now();
      if (!job.error.empty()) {
        record.status = JobStatus::failed;
        record.error = job.error;
        finish(record, start);
        continue;
      }
      if (!options_.force && up_to_date(job)) {
        record.status = JobStatus::skipped;
        finish(record, start);
        continue;
      }
      const bool small = side_by_side(job);
      // A large job has the arena to itself: the small ones before it finish first.
      if (!small) side_by_side_group.wait();
      std::unique_ptr<RunningJob> running =
          prepare_job(job, &record, start, small && side_by_side_running > 0,
                      [&] { side_by_side_group.wait(); });
      if (!running) {
        finish(record, start);
        continue;
      }
      if (!small) {
        render_prepared(running.get(), callbacks);
        if (record.status == JobStatus::cancelled) stopping = true;
        // Its files are written while the next job renders; its record is final, and
        // reported, once they are.
        if (record.status == JobStatus::rendered) {
          write_in_background(std::move(running), callbacks);
          continue;
        }
        if (callbacks.job_finished) callbacks.job_finished(record);
        continue;
      }
      record.side_by_side = most_side_by_side > 1;
      auto render_small = [&, running = std::shared_ptr<RunningJob>(std::move(running))] {
        render_prepared(running.get(), callbacks);
        if (running->record->status == JobStatus::cancelled) stopping = true;
        if (running->record->status != JobStatus::rendered) {
          if (callbacks.job_finished) callbacks.job_finished(*running->record);
          return;
        }
        auto write = [&, running] {
          write_now(running.get());
          if (callbacks.job_finished) callbacks.job_finished(*running->record);
        };
        // Written by a task of its own, so that the thread that rendered it (often the
        // batch's own) goes on to the next job and the write fills a gap in the tiles; but
        // no more writes wait than there are other threads to take them, so that a kill
        // loses at most those jobs (and one thread writes at once).
        if (writes_waiting.fetch_add(1) + 1 < arena_->max_concurrency()) {
          side_by_side_group.run([write, &writes_waiting] {
            write();
            --writes_waiting;
          });
        } else {
          --writes_waiting;
          write();
        }
      };
      if (side_by_side_running + 1 < most_side_by_side) {
        ++side_by_side_running;
        side_by_side_group.run([render_small, &side_by_side_running] {
          render_small();
          --side_by_side_running;
        });
      } else {
        render_small();  // on this thread, which the others' tiles share meanwhile
      }
    }
    side_by_side_group.wait();
  });
  finish_write(callbacks);
  if (claims) {
    claims.reset();  // collective: every rank is done claiming
    gather_records(*world, ran, &records);
  }
  uint64_t counts[2] = {static_cast<uint64_t>(cache_->loads()),
                        static_cast<uint64_t>(cache_->evictions())};
  if (world && world->size() > 1) distributed::sum_at_root(*world, counts);
  scene_loads_ = static_cast<int>(counts[0]);
  scene_evictions_ = static_cast<int>(counts[1]);
  return records;
}

std::unique_ptr<Batch::RunningJob> Batch::prepare_job(
    const BatchJob& job, JobRecord* record, Clock::time_point start, bool beside_running,
    const std::function<void()>& wait_for_running) {
  auto running = std::make_unique<RunningJob>();
  running->job = &job;
  running->record = record;
  running->start = start;
  const auto entry = cache_->get(job.spec.scene);
  // The first job of a scene pays for its load, even when planning did it (to list the
  // cameras of "camera": "all"), so that the jobs' times add up to the batch's.
  if (entry->session && charged_loads_.insert(entry->session).second)
    record->load_seconds = entry->session->load_seconds();
  if (!entry->session) {
    record->status = JobStatus::failed;
    record->error = (entry->request_error ? "scene: " : "") + entry->error;
    return nullptr;
  }
  running->entry = entry;
  Session& session = *entry->session;
  running->job_print = fingerprint(job, entry->inputs);
  running->interval = job.spec.checkpoint_interval > 0.0 ? job.spec.checkpoint_interval
                                                         : options_.checkpoint_interval;
  running->checkpoint = checkpoint_path(job.files.image);
  try {
    session.check(job.spec.render);
    // Made now, not when planning, so that a job file that renders nothing makes nothing; the
    // checkpoint, beside the image, needs its folder before the image does.
    make_output_directories(job.files);
    if (running->interval > 0.0) {
      std::error_code error;
      if (fs::exists(running->checkpoint, error)) {
        // Another job's, or a damaged one, is rendered over from the start (and replaced).
        CheckpointRead read =
            read_checkpoint(running->checkpoint, session.film(job.spec.render), running->job_print);
        if (read.state) running->resume = std::move(read.state);
      }
    }
    if (beside_running) {
      running->prepared = session.prepare_beside_running(job.spec.render);
      // Its render scene differs from the one the running jobs hold: they finish first.
      if (!running->prepared) wait_for_running();
    }
    if (!running->prepared) running->prepared = session.prepare(job.spec.render);
    running->colour = &session.colour(job.spec.render.working_space);
  } catch (const std::exception& e) {
    record_failure(e, record);
    return nullptr;
  }
  // A build made the session heavier.
  cache_->trim();
  record->scene_bytes = session.memory_bytes();
  running->last_save = Clock::now();
  running->checkpoint_requests_seen = checkpoint_requests_;
  return running;
}

void Batch::render_prepared(RunningJob* running, const BatchCallbacks& callbacks) {
  const BatchJob& job = *running->job;
  JobRecord& record = *running->record;
  Session& session = *running->entry->session;
  JobCallbacks job_callbacks;
  if (callbacks.progress)
    job_callbacks.progress = [&](int done, int total) { callbacks.progress(job, done, total); };
  if (callbacks.abandon) job_callbacks.cancel = callbacks.abandon;
  if (running->interval > 0.0) {
    job_callbacks.checkpoint_due = [&] {
      // A request (SIGUSR2) is for every running job, and each polls it once.
      if (callbacks.checkpoint_now && callbacks.checkpoint_now()) ++checkpoint_requests_;
      const uint64_t requests = checkpoint_requests_;
      const bool requested = requests != running->checkpoint_requests_seen;
      running->checkpoint_requests_seen = requests;
      return requested || seconds_since(running->last_save) >= running->interval;
    };
    if (callbacks.stop) job_callbacks.stop = callbacks.stop;
    job_callbacks.save_checkpoint = [&](const RenderState& state) {
      try {
        write_checkpoint(running->checkpoint, state, running->job_print);
      } catch (const std::exception& e) {
        running->save_error = e.what();  // the render goes on; the previous checkpoint stays
      }
      running->last_save = Clock::now();
    };
    job_callbacks.resume = running->resume ? &*running->resume : nullptr;
  }
  RenderOutput out;
  try {
    out = session.run(std::move(*running->prepared), job_callbacks);
    record.seconds = seconds_since(running->start);
  } catch (const std::exception& e) {
    record_failure(e, &record);
    return;
  }
  running->prepared.reset();
  record.width = out.film.width;
  record.height = out.film.height;
  record.render_seconds = out.result.seconds;
  record.build_seconds = out.build_seconds;
  record.rays = out.result.rays.total();
  record.rays_per_second =
      out.result.seconds > 0.0 ? static_cast<double>(record.rays) / out.result.seconds : 0.0;
  if (!out.pass_errors.empty()) record.reference_error = out.pass_errors.back();
  record.resumed_samples = out.resumed_samples;
  if (out.result.cancelled || out.result.stopped_at_checkpoint) {
    record.status = JobStatus::cancelled;
    record.error =
        out.result.stopped_at_checkpoint
            ? (running->save_error.empty()
                   ? "stopped; its checkpoint " + running->checkpoint +
                         " continues it on the next run"
                   : "stopped, but its checkpoint could not be saved: " + running->save_error)
            : "abandoned";
    return;
  }
  record.status = JobStatus::rendered;
  out.metadata.extra.insert(out.metadata.extra.end(),
                            {{"jobName", job.spec.name},
                             {"jobFingerprint", running->job_print},
                             {"jobInputs", format_inputs(running->entry->inputs)},
                             {"jobSettings", job.settings}});
  running->output = std::move(out);
}

void Batch::write_now(RunningJob* running) {
  JobRecord& record = *running->record;
  const auto write_start = Clock::now();
  try {
    // One thread: the jobs beside it keep the others busy.
    write_output_files(running->job->files, running->output, *running->colour, 1);
    // The image is on disk: its checkpoint has nothing left to continue.
    std::error_code ignored;
    fs::remove(running->checkpoint, ignored);
  } catch (const std::exception& e) {
    record.status = JobStatus::failed;
    record.error = e.what();
  }
  record.write_seconds = seconds_since(write_start);
  record.seconds += record.write_seconds;
  running->output = RenderOutput{};
}

void Batch::write_in_background(std::unique_ptr<RunningJob> running,
                                const BatchCallbacks& callbacks) {
  // One write in flight: the previous job's files are done before this one's start.
  finish_write(callbacks);
  pending_ = std::make_unique<PendingWrite>();
  pending_->running = std::move(running);
  RunningJob* r = pending_->running.get();
  // Compressed on this one task of the batch's arena: it overlaps the next job's render,
  // and a pool of its own would take cores beyond --threads.
  arena_->execute([this, r] { pending_->group.run([this, r] { write_now(r); }); });
}

void Batch::finish_write(const BatchCallbacks& callbacks) {
  if (!pending_) return;
  arena_->execute([&] { pending_->group.wait(); });
  JobRecord& record = *pending_->running->record;
  pending_.reset();
  if (callbacks.job_finished) callbacks.job_finished(record);
}

}  // namespace prism
