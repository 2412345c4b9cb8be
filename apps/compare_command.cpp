#include "apps/compare_command.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <type_traits>

#include "apps/compare_plot.h"
#include "apps/compare_report.h"
#include "apps/progress_bar.h"
#include "apps/reference_cache.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/image_output.h"
#include "renderer/version.h"
#include "session/session.h"

namespace prism {
namespace {

// The sample stream a rendered reference draws (RenderSettings::seed): 1, or 2 when the
// compared renders (seed 0 unless --seed) draw 1, so that it never shares their samples.
uint32_t reference_seed(int compared_seed) {
  return compared_seed == 1 ? 2 : 1;
}

namespace fs = std::filesystem;

// The process's peak resident set so far (Linux reports ru_maxrss in KiB). A high-water
// mark: it never goes down, so a row shows the most the process has needed up to then.
double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// "mesh:2" -> "mesh2": a file name without characters some file systems refuse.
std::string file_safe(const std::string& text) {
  std::string out;
  for (char c : text)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') out += c;
  return out;
}

template <typename T>
void refuse_duplicates(const std::vector<T>& values, const std::string& option) {
  std::set<T> seen;
  for (const T& v : values)
    if (!seen.insert(v).second) {
      if constexpr (std::is_same_v<T, std::string>)
        throw UsageError(option + " " + v + ": given twice");
      else if constexpr (std::is_floating_point_v<T>)
        throw UsageError(option + " " + format_error(v) + ": given twice");
      else
        throw UsageError(option + " " + std::to_string(v) + ": given twice");
    }
}

// The report directory may exist (it is then reused), but not as a file, and its parent must.
void check_report_dir(const std::string& dir) {
  if (dir.empty()) throw UsageError("-o: the report directory must not be empty");
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw UsageError("-o " + dir + ": exists and is not a directory");
  const fs::path parent = fs::absolute(dir).parent_path();
  if (!fs::is_directory(parent))
    throw UsageError("-o " + dir + ": directory " + parent.string() + " does not exist");
}

class Comparison {
 public:
  Comparison(const CompareOptions& o, Session& session, const RenderJob& base)
      : o_(o), session_(session), base_(base) {}

  CompareReport run(const std::vector<const IntegratorInfo*>& integrators,
                    const std::vector<SphereOptions>& modes, const RecordedRender* file_reference);

 private:
  // The job of one row: the integrator (with those of the command line's parameters it
  // takes), the sphere mode and the samples, uniform or, with a target error, adaptive with
  // `spp` the cap.
  RenderJob job_for(const IntegratorInfo& integrator, const SphereOptions& spheres, int spp,
                    std::optional<double> target_error = std::nullopt) const;
  // Renders the job timed, the BVH built before and its build time returned in
  // `bvh_seconds`. The first render of each BVH is preceded by an untimed one of one sample
  // per pixel, so that first-touch page faults and cold caches stay out of every row.
  RenderOutput render_timed(const RenderJob& job, std::optional<double>* bvh_seconds);
  // Writes images/<stem>.exr (with `metadata`, or else as a copy of the file `copy_of`) and
  // its PNG preview, and points the row at the PNG.
  void save(const std::string& stem, const Image& image, const RenderMetadata* metadata,
            const std::string& copy_of, WorkingSpace space, CompareRow* row);
  // The line names the item under way from its start, with its tiles' share and an ETA
  // from the time the items so far took; `finished` counts it done.
  void starting(const std::string& what);
  void finished() { ++done_; }
  void draw(double fraction);

  const CompareOptions& o_;
  Session& session_;
  const RenderJob& base_;
  double bvh_seconds_ = 0.0;  // of the render scene built last
  bool warmed_up_ = false;    // that render scene has rendered once
  int warm_ups_ = 0;
  int done_ = 0, total_ = 0;
  std::string current_;
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_draw_{};
};

RenderJob Comparison::job_for(const IntegratorInfo& integrator, const SphereOptions& spheres,
                              int spp, std::optional<double> target_error) const {
  RenderJob job = base_;
  job.integrator = integrator.name;
  job.integrator_parameters.clear();
  for (const auto& [name, value] : base_.integrator_parameters)
    if (takes_parameter(integrator, name)) job.integrator_parameters[name] = value;
  job.spheres = spheres;
  job.film.spp = spp;
  job.film.seed = static_cast<uint32_t>(o_.seed);
  if (target_error) {
    job.film.target_error = static_cast<float>(*target_error);
    job.film.min_spp = o_.min_spp;
  }
  return job;
}

RenderOutput Comparison::render_timed(const RenderJob& job, std::optional<double>* bvh_seconds) {
  double built = 0.0;
  session_.render_scene(job, &built);
  if (built > 0.0) {
    bvh_seconds_ = built;
    warmed_up_ = false;
  }
  *bvh_seconds = bvh_seconds_;
  if (!warmed_up_) {
    RenderJob warm_up = job;
    warm_up.film.spp = 1;
    warm_up.film.target_error = 0.0f;
    warm_up.film.time_limit_seconds = 0.0;
    session_.render(warm_up, JobCallbacks{});
    warmed_up_ = true;
    ++warm_ups_;
  }
  JobCallbacks callbacks;
  callbacks.progress = [&](int done, int total) {
    if (total > 0) draw(static_cast<double>(done) / total);
  };
  return session_.render(job, callbacks);
}

void Comparison::save(const std::string& stem, const Image& image, const RenderMetadata* metadata,
                      const std::string& copy_of, WorkingSpace space, CompareRow* row) {
  const ColourPipeline& colour = session_.colour(space);
  const fs::path images = fs::path(o_.report_dir) / "images";
  const std::string exr = (images / (stem + ".exr")).string();
  if (metadata)
    write_exr(exr, image, colour, *metadata, ExrPixelType::float32);
  else
    fs::copy_file(copy_of, exr, fs::copy_options::overwrite_existing);
  write_png_preview((images / (stem + ".png")).string(), image, colour);
  row->image = "images/" + stem + ".png";
}

void Comparison::starting(const std::string& what) {
  current_ = what;
  last_draw_ = {};
  draw(0.0);
}

void Comparison::draw(double fraction) {
  if (o_.quiet || !isatty(fileno(stderr))) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // a render's workers report tiles at once: one draws
  const auto now = std::chrono::steady_clock::now();
  if (fraction > 0.0 && now - last_draw_ < std::chrono::milliseconds(250)) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double items = done_ + fraction;
  char eta[32] = "?";
  if (items > 0.0) std::snprintf(eta, sizeof eta, "%.0fs", elapsed * (total_ - items) / items);
  std::string line = "prism: compare " + std::to_string(done_ + 1) + "/" + std::to_string(total_) +
                     " " + std::to_string(static_cast<int>(fraction * 100)) + "%, ETA " + eta +
                     ": " + current_;
  const size_t width = static_cast<size_t>(std::max(20, terminal_columns() - 1));
  if (line.size() > width) line.resize(width);
  std::fprintf(stderr, "\r%s\033[K", line.c_str());
  std::fflush(stderr);
}

CompareReport Comparison::run(const std::vector<const IntegratorInfo*>& integrators,
                              const std::vector<SphereOptions>& modes,
                              const RecordedRender* file_reference) {
  CompareReport report;
  const RenderSettings film = session_.film(base_);
  const CameraDescription camera = session_.camera(base_);
  const int camera_index = base_.frame_scene ? -1 : session_.camera_index(base_.camera);
  report.scene = o_.scene.scene_path;
  report.width = film.width;
  report.height = film.height;
  report.camera = camera.name;
  report.working_space = to_string(base_.working_space);
  const auto depth = base_.integrator_parameters.find("max-depth");
  report.max_depth =
      depth != base_.integrator_parameters.end() ? static_cast<int>(depth->second) : 5;
  report.min_spp = o_.min_spp;
  report.plot_metric = o_.plot_metric;
  const size_t runs = o_.spp.size() + o_.target_errors.size();

  // References first: every other row is measured against one. By default one converged
  // `path` render, the unbiased answer, so each row's error is its bias and its noise
  // together; with --reference-integrator self, each integrator's own.
  const bool own_references = o_.reference_integrator == "self";
  std::vector<const IntegratorInfo*> reference_integrators = integrators;
  if (!own_references)
    reference_integrators = {
        &parse_integrator_option(o_.reference_integrator, "--reference-integrator")};
  if (file_reference) reference_integrators.clear();
  total_ =
      static_cast<int>(integrators.size() * modes.size() * runs + reference_integrators.size());
  std::map<std::string, Image> references;
  SphereOptions analytic;
  for (const IntegratorInfo* integrator : reference_integrators) {
    const std::string name = integrator->name;
    CompareRow row;
    row.reference = true;
    row.integrator = name;
    row.spheres = to_string(analytic);
    starting(name + " reference");
    row.spp = o_.reference_spp;
    const std::string cache_dir = reference_cache_dir();
    RenderJob job = job_for(*integrator, analytic, o_.reference_spp);
    // Its own sample stream: with the renders' seed, the reference's first samples would be
    // the compared render's own (path's wholly, every integrator's pixel positions), and
    // their noise would drop out of the error measured against it.
    job.film.seed = reference_seed(o_.seed);
    const ParameterValues parameters(integrator->parameters, job.integrator_parameters);
    const ReferenceKey key = reference_key(o_.scene.scene_path, job, session_.film(job), parameters,
                                           camera, camera_index);
    const std::string cache_path = cached_reference_path(cache_dir, key);
    const std::string whose = own_references ? name : name + ", for every integrator";
    RenderResult result;
    if (std::optional<RecordedRender> cached = find_cached_reference(cache_dir, key)) {
      references[name] = std::move(cached->image);
      result.seconds = cached->seconds;
      result.rays = cached->rays;
      row.source = "cache";
      report.reference_notes.push_back(whose + ": analytic spheres, " +
                                       std::to_string(o_.reference_spp) + " spp, from the cache " +
                                       cache_path);
    } else {
      RenderOutput out = render_timed(job, &row.bvh_seconds);
      result = out.result;
      row.peak_rss_mib = peak_rss_mib();
      fs::create_directories(cache_dir);
      out.metadata.extra.push_back(reference_metadata_entry(key));
      write_exr(cache_path, out.image, session_.colour(job.working_space), out.metadata,
                ExrPixelType::float32);
      references[name] = std::move(out.image);
      report.reference_notes.push_back(
          whose + ": analytic spheres, " + std::to_string(o_.reference_spp) + " spp, rendered in " +
          format_error(result.seconds) + " s and cached as " + cache_path);
      const CacheSweep sweep = bound_reference_cache(
          cache_dir, static_cast<uint64_t>(o_.cache_limit_gib * double(uint64_t{1} << 30)),
          cache_path);
      if (sweep.removed > 0)
        report.reference_notes.push_back("cache over --cache-limit " +
                                         format_error(o_.cache_limit_gib) + " GiB: removed the " +
                                         std::to_string(sweep.removed) + " least recently used (" +
                                         with_commas(sweep.removed_bytes) + " bytes)");
    }
    row.seconds = result.seconds;
    row.rays = result.rays;
    save(name + "-reference", references[name], nullptr, cache_path, base_.working_space, &row);
    report.rows.push_back(row);
    finished();
  }
  // The image a row of `integrator` is measured against.
  const auto reference_for = [&](const std::string& integrator) -> const Image& {
    if (file_reference) return file_reference->image;
    return references.at(own_references ? integrator : reference_integrators[0]->name);
  };
  // One scale for every heat map, so that they compare: the (first) reference's mean.
  {
    const Image& first = reference_for(integrators[0]->name);
    double sum = 0.0;
    for (size_t i = 0; i < first.rgba.size(); i += 4)
      sum += first.rgba[i] + first.rgba[i + 1] + first.rgba[i + 2];
    const double mean = sum / (3.0 * std::max<size_t>(1, first.rgba.size() / 4));
    report.heatmap_peak = mean > 0.0 && std::isfinite(mean) ? mean : 1.0;
  }
  if (file_reference) {
    CompareRow row;
    row.reference = true;
    row.integrator = "-";
    row.spheres = "-";
    row.spp = file_reference->spp;
    row.seconds = file_reference->seconds;
    row.rays = file_reference->rays;
    row.source = "file";
    save("reference", file_reference->image, nullptr, o_.reference_path, base_.working_space, &row);
    report.rows.push_back(row);
    report.reference_notes.push_back("all integrators: the file " + o_.reference_path);
  }

  // Then every combination, one BVH per sphere mode; rows ordered as the options list them,
  // each curve's uniform runs before its adaptive ones.
  const int cap = *std::max_element(o_.spp.begin(), o_.spp.end());
  std::vector<std::pair<std::tuple<size_t, size_t, size_t>, CompareRow>> tests;
  for (size_t m = 0; m < modes.size(); ++m) {
    for (size_t i = 0; i < integrators.size(); ++i) {
      for (size_t k = 0; k < runs; ++k) {
        CompareRow row;
        row.integrator = integrators[i]->name;
        row.spheres = to_string(modes[m]);
        const bool uniform = k < o_.spp.size();
        row.spp = uniform ? o_.spp[k] : cap;
        if (!uniform) row.target_error = o_.target_errors[k - o_.spp.size()];
        const RenderJob job = job_for(*integrators[i], modes[m], row.spp, row.target_error);
        const std::string spp_text = std::to_string(row.spp) + "spp";
        const std::string name = row.integrator + "-" + file_safe(row.spheres) + "-" +
                                 (uniform ? "" : file_safe(sampling_label(row)) + "-") + spp_text;
        starting(row.integrator + ", " + row.spheres + ", " + sampling_label(row) + ", " +
                 std::to_string(row.spp) + " spp");
        const RenderOutput out = render_timed(job, &row.bvh_seconds);
        row.seconds = out.result.seconds;
        row.rays = out.result.rays;
        row.peak_rss_mib = peak_rss_mib();
        const Image& reference = reference_for(row.integrator);
        row.error = compare_images(out.image, reference).overall;
        save(name, out.image, &out.metadata, "", job.working_space, &row);
        row.heatmap = "images/" + name + "-error.png";
        write_display_png(
            (fs::path(o_.report_dir) / row.heatmap).string(),
            error_heatmap(difference_image(out.image, reference), float(report.heatmap_peak)));
        if (o_.verbose)
          std::fprintf(stderr, "\r\033[Kprism: compare: %s, %s, %s: %.4g s, RMSE %s, relMSE %s\n",
                       row.integrator.c_str(), row.spheres.c_str(), sampling_label(row).c_str(),
                       row.seconds, format_error(row.error->rmse).c_str(),
                       format_error(row.error->relmse).c_str());
        tests.push_back({{i, m, k}, row});
        finished();
      }
    }
  }
  if (!o_.quiet && isatty(fileno(stderr))) std::fprintf(stderr, "\r\033[K");
  std::stable_sort(tests.begin(), tests.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, row] : tests) report.rows.push_back(std::move(row));
  report.warm_up_renders = warm_ups_;
  return report;
}

// The plot's points, one curve per integrator and sphere mode; marks the Pareto front on
// the rows too, so the tables show it.
Plot make_plot(CompareReport* report) {
  Plot plot;
  plot.title = "prism compare: " + fs::path(report->scene).filename().string() + ", " +
               std::to_string(report->width) + "x" + std::to_string(report->height);
  plot.error_label = report->plot_metric == "rmse" ? "RMSE" : "relMSE";
  std::vector<size_t> row_of_point;
  for (size_t r = 0; r < report->rows.size(); ++r) {
    const CompareRow& row = report->rows[r];
    if (row.reference) continue;
    const std::string curve = row.integrator + ", " + row.spheres;
    auto it = std::find(plot.curves.begin(), plot.curves.end(), curve);
    if (it == plot.curves.end()) it = plot.curves.insert(plot.curves.end(), curve);
    plot.points.push_back({static_cast<int>(it - plot.curves.begin()), row.spp, row.target_error,
                           row.seconds, plot_error(row, report->plot_metric), false});
    row_of_point.push_back(r);
  }
  mark_pareto_front(&plot.points);
  for (size_t p = 0; p < plot.points.size(); ++p)
    report->rows[row_of_point[p]].pareto = plot.points[p].pareto;
  return plot;
}

int run(const CompareOptions& o) {
  std::vector<const IntegratorInfo*> integrators;
  for (const std::string& name : o.integrators)
    integrators.push_back(&parse_integrator_option(name, "--integrator"));
  refuse_duplicates(o.integrators, "--integrator");
  std::vector<SphereOptions> modes;
  std::vector<std::string> mode_names;
  for (const std::string& text : o.spheres) {
    modes.push_back(parse_spheres_option(text, "--spheres"));
    mode_names.push_back(to_string(modes.back()));
  }
  refuse_duplicates(mode_names, "--spheres");
  refuse_duplicates(o.spp, "--spp");
  refuse_duplicates(o.target_errors, "--target-error");
  // As `prism render` says it: the rounds double from --min-spp (docs/sampling.md).
  if ((o.min_spp & (o.min_spp - 1)) != 0)
    throw UsageError("--min-spp " + std::to_string(o.min_spp) + ": must be a power of two");
  RenderJob base = base_job(o.scene);
  // A parameter none of the integrators takes would change nothing: say so.
  for (const auto& [name, value] : base.integrator_parameters) {
    bool taken = false;
    for (const IntegratorInfo* info : integrators) taken = taken || takes_parameter(*info, name);
    if (!taken) throw UsageError("--" + name + ": none of the integrators compared takes it");
  }
  if (o.reference_integrator != "self")
    parse_integrator_option(o.reference_integrator, "--reference-integrator");
  check_report_dir(o.report_dir);
  // Read before the scene, so a wrong path costs nothing.
  std::optional<RecordedRender> file_reference;
  if (!o.reference_path.empty()) {
    try {
      file_reference = read_recorded_render(o.reference_path);
    } catch (const std::exception& e) {
      throw UsageError(std::string("--reference ") + e.what());
    }
  } else {
    reference_cache_dir();  // fails now, not after the first renders, when there is none
  }

  const bool terminal = !o.quiet && isatty(fileno(stderr));
  if (terminal) std::fprintf(stderr, "prism: compare: loading %s", o.scene.scene_path.c_str());
  Session session(scene_request(o.scene, SphereDetectionFlags{}), session_options(o.scene));
  if (terminal) std::fprintf(stderr, "\r\033[K");
  print_warnings(o.scene.scene_path, session.warnings());
  print_warnings(o.scene.scene_path, session.job_warnings(base));
  if (file_reference) {
    const RenderSettings film = session.film(base);
    if (file_reference->image.width != film.width || file_reference->image.height != film.height)
      throw UsageError("--reference " + o.reference_path + " is " +
                       std::to_string(file_reference->image.width) + "x" +
                       std::to_string(file_reference->image.height) + " but the render is " +
                       std::to_string(film.width) + "x" + std::to_string(film.height));
  }
  fs::create_directories(fs::path(o.report_dir) / "images");

  Comparison comparison(o, session, base);
  CompareReport report =
      comparison.run(integrators, modes, file_reference ? &*file_reference : nullptr);
  const Plot plot = make_plot(&report);

  const fs::path dir(o.report_dir);
  write_plot_svg((dir / "plot.svg").string(), plot);
  if (!write_plot_png((dir / "plot.png").string(), plot))
    std::fprintf(stderr,
                 "prism: warning: %s: drawn without its labels: OpenImageIO found no DejaVuSans "
                 "font (Debian package fonts-dejavu-core)\n",
                 (dir / "plot.png").c_str());
  write_results_json((dir / "results.json").string(), report);
  write_results_csv((dir / "results.csv").string(), report);
  write_index_html((dir / "index.html").string(), report);

  if (o.quiet) return 0;
  std::printf("compared %s, %dx%d, camera '%s'\n", o.scene.scene_path.c_str(), report.width,
              report.height, report.camera.c_str());
  for (const std::string& note : report.reference_notes)
    std::printf("reference %s\n", note.c_str());
  print_table(report);
  std::printf("wrote %s (results.json, results.csv, plot.svg, plot.png, images/)\n",
              (dir / "index.html").c_str());
  return 0;
}

}  // namespace

CLI::App* add_compare_command(CLI::App& app, CompareOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Render every integrator x sphere mode x spp, time each and measure its error against a "
      "reference; write a report directory");
  cmd->footer(
      "Each BVH's first render is preceded by an untimed one of 1 spp, so that cold caches "
      "stay out of the figures; BVH build time is reported apart. Without --reference, every "
      "row is measured against one path render with analytic spheres at --reference-spp "
      "(--reference-integrator), cached in $XDG_CACHE_HOME/prism/references (or "
      "~/.cache/prism/references). See docs/compare.md.");
  add_scene_options(cmd, &o->scene);
  cmd->add_option("-o,--output", o->report_dir,
                  "Report directory (created; files in it are replaced)")
      ->required();
  // Named as render's; the plural is the spelling earlier versions took.
  cmd->add_option("--integrator,--integrators", o->integrators,
                  "One or comma-separated: " + integrator_choices(", "))
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--spp", o->spp, "Comma-separated samples per pixel")
      ->delimiter(',')
      ->check(whole_number(1, 1 << 16))
      ->capture_default_str();
  CLI::Option* target_errors =
      cmd->add_option("--target-error,--target-errors", o->target_errors,
                      "Comma-separated target errors: one adaptive render each (docs/sampling.md), "
                      "with the largest --spp as the most samples a pixel takes")
          ->delimiter(',')
          ->check(kPositiveFinite);
  cmd->add_option("--min-spp", o->min_spp,
                  "Adaptive renders: samples every pixel takes before the first decision (a "
                  "power of two)")
      ->check(whole_number(1, 1 << 16))
      ->capture_default_str()
      ->needs(target_errors);  // alone it would change nothing
  cmd->add_option("--spheres", o->spheres,
                  "Comma-separated sphere modes: analytic, mesh[:LEVEL], embree-points")
      ->delimiter(',')
      ->capture_default_str();
  CLI::Option* reference =
      cmd->add_option("--reference", o->reference_path,
                      "Reference image (.exr) for every integrator, of the render's size");
  cmd->add_option("--reference-integrator", o->reference_integrator,
                  "Without --reference: the integrator of the one rendered reference every row "
                  "is measured against (path: the unbiased answer, so errors include each "
                  "integrator's bias), or self: each integrator against its own converged render "
                  "(noise alone)")
      ->excludes(reference)
      ->capture_default_str();
  cmd->add_option("--reference-spp", o->reference_spp,
                  "Samples per pixel of the rendered references (analytic spheres)")
      ->check(whole_number(1, 1 << 16))
      ->excludes(reference)
      ->capture_default_str();
  add_seed_option(cmd, &o->seed,
                  "Sample streams of the compared renders: 0 is every render's by default; "
                  "another draws independent noise (e.g. repeats for the spread of each "
                  "error). A rendered reference draws a stream of its own");
  cmd->add_option("--cache-limit", o->cache_limit_gib,
                  "GiB the reference cache may hold; the least recently used references go first")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  // Runs as soon as it is parsed, so it needs no scene or report directory.
  cmd->add_flag_callback(
         "--clear-cache",
         [] {
           const int code = run_reporting_errors([] {
             const std::string dir = reference_cache_dir();
             const CacheSweep sweep = clear_reference_cache(dir);
             std::printf("removed %d cached references (%s bytes) from %s\n", sweep.removed,
                         with_commas(sweep.removed_bytes).c_str(), dir.c_str());
             return 0;
           });
           if (code != 0) throw CLI::RuntimeError(code);
           throw CLI::Success();
         },
         "Remove every cached reference and exit")
      ->trigger_on_parse();
  cmd->add_option("--plot-metric", o->plot_metric, "Error on the plot's y axis: rmse | relmse")
      ->check(CLI::IsMember({"rmse", "relmse"}))
      ->capture_default_str();
  add_verbosity_flags(cmd, &o->quiet, &o->verbose,
                      "No progress and no table (the report is written)",
                      "A line per render as it finishes: its time and error");
  return cmd;
}

int run_compare(const CompareOptions& options) {
  return run_reporting_errors([&] { return run(options); });
}

}  // namespace prism
