// `prism compare`'s time-versus-error plot: log-log, one curve per integrator and sphere mode,
// uniform points as squares labelled by their spp, adaptive ones as diamonds labelled by their
// target error, the Pareto front marked. The same drawing code writes the SVG
// and the PNG, through two small canvases.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace prism {

inline constexpr int kPlotWidth = 800;
inline constexpr int kPlotHeight = 500;

struct PlotPoint {
  int curve = 0;  // index into Plot::curves
  int spp = 1;
  std::optional<double> target_error;  // an adaptive render's; empty: uniform
  double seconds = 0.0;
  double error = 0.0;
  bool pareto = false;
};

struct Plot {
  std::string title;
  std::string error_label;  // "RMSE" or "relMSE"
  std::vector<std::string> curves;
  std::vector<PlotPoint> points;  // values <= 0 or not finite cannot go on log axes: skipped
};

// Marks the points that no other point beats in both time and error (each no worse and one
// strictly better). Points that cannot be plotted are never on the front.
void mark_pareto_front(std::vector<PlotPoint>* points);

// Both throw std::runtime_error("<path>: <reason>") when the file cannot be written.
void write_plot_svg(const std::string& path, const Plot& plot);
// Returns false (the plot drawn without its words) when OpenImageIO finds no font; the
// DejaVu Sans it asks for comes with Debian's fonts-dejavu-core.
bool write_plot_png(const std::string& path, const Plot& plot);

}  // namespace prism

namespace prism {

// &, <, >, " and ' as entities, for text in SVG and HTML.
std::string xml_escape(const std::string& text);

}  // namespace prism
