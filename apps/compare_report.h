// What `prism compare` writes into its report directory (results.json, results.csv,
// index.html) and prints on the terminal, all from one list of columns.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "renderer/image/image_metrics.h"
#include "renderer/integrator.h"

namespace prism {

struct CompareRow {
  bool reference = false;  // the row of a reference render (its error columns are empty)
  std::string integrator;
  std::string spheres;
  int spp = 1;  // an adaptive render's cap: the most samples a pixel may take
  // Adaptive sampling's target error (docs/sampling.md); empty: every pixel takes `spp`.
  std::optional<double> target_error;
  double seconds = 0.0;               // the timed render, after a warm-up
  std::optional<double> bvh_seconds;  // building the RenderScene for this sphere mode
  RayCounters rays;
  std::optional<ChannelError> error;   // overall RGB error against the reference
  std::optional<double> peak_rss_mib;  // the process's high-water mark after this render
  std::string source = "rendered";     // references: "rendered", "cache" or "file"
  bool pareto = false;                 // on the time-versus-error Pareto front
  std::string image;                   // path of the PNG, relative to the report directory
  std::string heatmap;                 // test rows: the error heat map's PNG, relative as `image`
};

// The rows to set side by side, one per integrator (the first sphere mode's uniform and
// adaptive rows): at equal time, each integrator's row whose time is nearest (in ratio) to
// `target`, the longest time every integrator reached; at equal error, nearest to the
// lowest error every integrator reached. Empty with fewer than two integrators.
struct SideBySide {
  double target = 0.0;
  std::vector<size_t> rows;  // indices into CompareReport::rows, in integrator order
};

struct CompareReport {
  std::string scene;
  int width = 0, height = 0;
  std::string camera;
  std::string working_space;
  int max_depth = 0;
  int min_spp = 0;                           // the adaptive rows' samples before deciding
  std::string plot_metric;                   // "rmse" or "relmse"
  std::vector<std::string> reference_notes;  // one line per reference: where it came from
  std::vector<CompareRow> rows;
  // The heat maps' scale: an absolute error of this much is white (the reference's mean).
  double heatmap_peak = 0.0;
  int warm_up_renders = 0;  // untimed 1-spp renders, one per BVH built
};

SideBySide equal_time(const CompareReport& report);
SideBySide equal_error(const CompareReport& report);

// "uniform", or "adaptive 0.05" with the target error.
std::string sampling_label(const CompareRow& row);

// The figure of `row` that the plot and the Pareto front use (NaN without an error).
double plot_error(const CompareRow& row, const std::string& metric);

void write_results_json(const std::string& path, const CompareReport& report);
void write_results_csv(const std::string& path, const CompareReport& report);
void write_index_html(const std::string& path, const CompareReport& report);
// The table with aligned columns, on stdout.
void print_table(const CompareReport& report);

}  // namespace prism
