#include "apps/compare_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "apps/command_line.h"
#include "apps/compare_plot.h"

namespace prism {
namespace {

using nlohmann::json;

// Where a column appears: the machine-readable files carry everything, the tables for people
// (terminal, HTML) leave out what the page says once (the scene) and fold flags into a note.
// The terminal's table is a summary that fits 100 columns (kMaxTerminalColumns): what the
// HTML table adds there (rays by kind, the BVH's time, PSNR, memory) stays in the files.
enum Where {
  kFiles = 1,
  kHtml = 2,
  kTerminal = 4,
  kTables = kHtml | kTerminal,
  kFilesAndHtml = kFiles | kHtml,
  kEverywhere = kFiles | kTables
};
constexpr size_t kMaxTerminalColumns = 100;

struct Column {
  std::string key;     // JSON key and CSV header
  std::string header;  // terminal and HTML header
  int where;
  std::function<json(const CompareRow&, const CompareReport&)> value;
};

json optional(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

// JSON has no infinity: equal images (PSNR inf) and missing errors are both null.
json error_field(const CompareRow& r, double ChannelError::*field) {
  if (!r.error || !std::isfinite((*r.error).*field)) return nullptr;
  return (*r.error).*field;
}

// Camera rays over pixels, as RenderResult::mean_spp: one camera ray per sample. Empty for a
// --reference file without prism's metadata, which has no ray counts.
std::optional<double> mean_spp(const CompareRow& row, const CompareReport& report) {
  const double pixels = static_cast<double>(report.width) * report.height;
  if (row.rays[RayKind::camera] == 0 || pixels <= 0) return std::nullopt;
  return static_cast<double>(row.rays[RayKind::camera]) / pixels;
}

const std::vector<Column>& columns() {
  static const std::vector<Column> list = [] {
    std::vector<Column> list = {
        {"scene", "scene", kFiles, [](auto&, auto& rep) { return json(rep.scene); }},
        {"role", "role", kFiles,
         [](auto& r, auto&) { return json(r.reference ? "reference" : "test"); }},
        {"integrator", "integrator", kEverywhere,
         [](auto& r, auto&) { return json(r.integrator); }},
        {"spheres", "spheres", kEverywhere, [](auto& r, auto&) { return json(r.spheres); }},
        {"sampling", "sampling", kFiles,
         [](auto& r, auto&) { return json(r.target_error ? "adaptive" : "uniform"); }},
        {"target_error", "target error", kFiles,
         [](auto& r, auto&) { return optional(r.target_error); }},
        {"sampling_label", "sampling", kTables,
         [](auto& r, auto&) { return json(sampling_label(r)); }},
        {"spp", "spp", kEverywhere, [](auto& r, auto&) { return json(r.spp); }},
        {"mean_spp", "mean spp", kEverywhere,
         [](auto& r, auto& rep) { return optional(mean_spp(r, rep)); }},
        {"wall_seconds", "time s", kEverywhere, [](auto& r, auto&) { return json(r.seconds); }},
        {"bvh_build_seconds", "BVH s", kFilesAndHtml,
         [](auto& r, auto&) { return optional(r.bvh_seconds); }},
        {"rays_per_second", "rays/s", kEverywhere,
         [](auto& r, auto&) {
           return r.seconds > 0 ? json(static_cast<double>(r.rays.total()) / r.seconds)
                                : json(nullptr);
         }},
        {"rmse", "RMSE", kEverywhere,
         [](auto& r, auto&) { return error_field(r, &ChannelError::rmse); }},
        {"relmse", "relMSE", kEverywhere,
         [](auto& r, auto&) { return error_field(r, &ChannelError::relmse); }},
        {"psnr_db", "PSNR dB", kFilesAndHtml,
         [](auto& r, auto&) { return error_field(r, &ChannelError::psnr); }},
        {"peak_rss_mib", "peak MiB", kFilesAndHtml,
         [](auto& r, auto&) { return optional(r.peak_rss_mib); }},
        {"source", "source", kFiles, [](auto& r, auto&) { return json(r.source); }},
        {"pareto", "pareto", kFiles, [](auto& r, auto&) { return json(r.pareto); }},
        {"note", "note", kTables,
         [](auto& r, auto&) {
           if (r.reference) return json("reference (" + r.source + ")");
           return json(r.pareto ? "Pareto front" : "");
         }},
        {"image", "image", kFiles, [](auto& r, auto&) { return json(r.image); }},
        {"heatmap", "heat map", kFiles, [](auto& r, auto&) { return json(r.heatmap); }},
    };
    // One column per kind of ray, before rays/s.
    auto at = std::find_if(list.begin(), list.end(),
                           [](const Column& c) { return c.key == "rays_per_second"; });
    for (const EnumName<RayKind>& kind : kRayKindNames) {
      const RayKind k = kind.value;
      at = list.insert(at, Column{std::string("rays_") + kind.name, kind.name, kFilesAndHtml,
                                  [k](const CompareRow& r, const CompareReport&) {
                                    return json(r.rays[k]);
                                  }}) +
           1;
    }
    return list;
  }();
  return list;
}

// Names are read left to right; numbers line up on their last digit.
bool left_aligned(const std::string& header) {
  return header == "integrator" || header == "spheres" || header == "sampling" || header == "note";
}

// Four significant digits are plenty to read a table; the files keep full precision.
std::string for_people(const json& v) {
  if (v.is_null()) return "-";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v.get<double>());
  return buffer;
}

std::string csv_field(const json& v) {
  if (v.is_null()) return "";
  if (!v.is_string()) return v.dump();
  const std::string s = v.get<std::string>();
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw std::runtime_error(path + ": cannot write");
}

// The cells of the table for `where` (kHtml or kTerminal), header first.
std::vector<std::vector<std::string>> table_cells(const CompareReport& report, Where where) {
  std::vector<std::vector<std::string>> cells(1);
  for (const Column& c : columns())
    if (c.where & where) cells[0].push_back(c.header);
  for (const CompareRow& row : report.rows) {
    cells.emplace_back();
    for (const Column& c : columns())
      if (c.where & where) cells.back().push_back(for_people(c.value(row, report)));
  }
  return cells;
}

// One side-by-side: per integrator, of the rows `eligible` keeps, the one whose `figure` is
// nearest in ratio to `target(figures)` (each integrator's figures given).
template <typename Figure, typename Target>
SideBySide side_by_side(const CompareReport& report, Figure figure, Target target) {
  std::vector<std::string> integrators;
  std::string first_mode;
  std::vector<std::vector<size_t>> rows_of;
  for (size_t r = 0; r < report.rows.size(); ++r) {
    const CompareRow& row = report.rows[r];
    if (row.reference || !(figure(row) > 0.0)) continue;
    if (first_mode.empty()) first_mode = row.spheres;
    if (row.spheres != first_mode) continue;
    auto it = std::find(integrators.begin(), integrators.end(), row.integrator);
    if (it == integrators.end()) {
      integrators.push_back(row.integrator);
      rows_of.emplace_back();
      it = integrators.end() - 1;
    }
    rows_of[static_cast<size_t>(it - integrators.begin())].push_back(r);
  }
  SideBySide out;
  if (integrators.size() < 2) return out;
  std::vector<std::vector<double>> figures;
  for (const auto& rows : rows_of) {
    figures.emplace_back();
    for (size_t r : rows) figures.back().push_back(figure(report.rows[r]));
  }
  out.target = target(figures);
  for (const auto& rows : rows_of) {
    size_t best = rows[0];
    for (size_t r : rows)
      if (std::fabs(std::log(figure(report.rows[r]) / out.target)) <
          std::fabs(std::log(figure(report.rows[best]) / out.target)))
        best = r;
    out.rows.push_back(best);
  }
  return out;
}

}  // namespace

SideBySide equal_time(const CompareReport& report) {
  return side_by_side(
      report, [](const CompareRow& r) { return r.seconds; },
      [](const std::vector<std::vector<double>>& times) {
        double t = std::numeric_limits<double>::infinity();
        for (const auto& each : times) t = std::min(t, *std::max_element(each.begin(), each.end()));
        return t;
      });
}

SideBySide equal_error(const CompareReport& report) {
  return side_by_side(
      report, [&](const CompareRow& r) { return plot_error(r, report.plot_metric); },
      [](const std::vector<std::vector<double>>& errors) {
        double e = 0.0;
        for (const auto& each : errors)
          e = std::max(e, *std::min_element(each.begin(), each.end()));
        return e;
      });
}

std::string sampling_label(const CompareRow& row) {
  return row.target_error ? "adaptive " + format_error(*row.target_error) : "uniform";
}

double plot_error(const CompareRow& row, const std::string& metric) {
  if (!row.error) return std::numeric_limits<double>::quiet_NaN();
  return metric == "rmse" ? row.error->rmse : row.error->relmse;
}

void write_results_json(const std::string& path, const CompareReport& report) {
  json rows = json::array();
  for (const CompareRow& row : report.rows) {
    json r = json::object();
    for (const Column& c : columns())
      if (c.where & kFiles) r[c.key] = c.value(row, report);
    rows.push_back(r);
  }
  const json doc = {
      {"scene", report.scene},
      {"width", report.width},
      {"height", report.height},
      {"camera", report.camera},
      {"working_space", report.working_space},
      {"max_depth", report.max_depth},
      {"adaptive_min_spp", report.min_spp},
      {"plot_metric", report.plot_metric},
      {"heatmap_peak", report.heatmap_peak},
      {"warm_up_renders", report.warm_up_renders},
      {"equal_time", {{"seconds", equal_time(report).target}, {"rows", equal_time(report).rows}}},
      {"equal_error", {{"error", equal_error(report).target}, {"rows", equal_error(report).rows}}},
      {"references", report.reference_notes},
      {"rows", rows}};
  write_file(path, doc.dump(2) + "\n");
}

void write_results_csv(const std::string& path, const CompareReport& report) {
  std::string text;
  for (const Column& c : columns())
    if (c.where & kFiles) text += (text.empty() ? "" : ",") + std::string(c.key);
  text += "\n";
  for (const CompareRow& row : report.rows) {
    std::string line;
    for (const Column& c : columns())
      if (c.where & kFiles) line += (line.empty() ? "" : ",") + csv_field(c.value(row, report));
    text += line + "\n";
  }
  write_file(path, text);
}

void print_table(const CompareReport& report) {
  auto cells = table_cells(report, kTerminal);
  const auto drop = [&](size_t column) {
    for (auto& line : cells) line.erase(line.begin() + static_cast<std::ptrdiff_t>(column));
  };
  const auto find = [&](const std::string& header) {
    return static_cast<size_t>(std::find(cells[0].begin(), cells[0].end(), header) -
                               cells[0].begin());
  };
  // A column that says the same on every row is said once, above the table.
  const size_t spheres = find("spheres");
  if (spheres < cells[0].size() && cells.size() > 1 &&
      std::all_of(cells.begin() + 1, cells.end(),
                  [&](const auto& line) { return line[spheres] == cells[1][spheres]; })) {
    std::printf("spheres: %s\n", cells[1][spheres].c_str());
    drop(spheres);
  }
  const auto widths = [&] {
    std::vector<size_t> width(cells[0].size(), 0);
    for (const auto& line : cells)
      for (size_t i = 0; i < line.size(); ++i) width[i] = std::max(width[i], line[i].size());
    return width;
  };
  const auto total = [](const std::vector<size_t>& width) {
    size_t sum = 2 * (width.size() - 1);
    for (size_t w : width) sum += w;
    return sum;
  };
  // Long names (embree-points, adaptive 0.005) can still overflow: the least needed go first.
  for (const char* header : {"rays/s", "mean spp", "time s"}) {
    if (total(widths()) <= kMaxTerminalColumns) break;
    if (const size_t at = find(header); at < cells[0].size()) drop(at);
  }
  const std::vector<size_t> width = widths();
  for (const auto& line : cells) {
    std::string text;
    for (size_t i = 0; i < line.size(); ++i) {
      const bool left = left_aligned(cells[0][i]);
      const std::string pad(width[i] - line[i].size(), ' ');
      text +=
          (i ? "  " : "") + (left ? line[i] + (i + 1 == line.size() ? "" : pad) : pad + line[i]);
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();  // an empty note
    std::printf("%s\n", text.c_str());
  }
}

void write_index_html(const std::string& path, const CompareReport& report) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>prism "
          "compare: "
       << xml_escape(report.scene)
       << "</title>\n<style>\n"
          "body { font-family: 'DejaVu Sans', sans-serif; margin: 1.5em; color: #222; }\n"
          "table { border-collapse: collapse; font-size: 13px; }\n"
          "th, td { padding: 2px 8px; border-bottom: 1px solid #ddd; text-align: right; }\n"
          "th { background: #f0f0f0; }\n"
          ".name { text-align: left; }\n"
          ".images { display: flex; flex-wrap: wrap; gap: 12px; margin-bottom: 12px; }\n"
          "figure { margin: 0; }\n"
          "figure img { image-rendering: pixelated; border: 1px solid #ccc; }\n"
          "figcaption { font-size: 12px; }\n"
          "</style>\n</head>\n<body>\n<h1>prism compare</h1>\n<p>"
       << xml_escape(report.scene) << ", " << report.width << "x" << report.height << ", camera '"
       << xml_escape(report.camera) << "', " << xml_escape(report.working_space) << ", max depth "
       << report.max_depth << "</p>\n<ul>\n";
  for (const std::string& note : report.reference_notes)
    html << "<li>" << xml_escape(note) << "</li>\n";
  html << "</ul>\n<h2>Images</h2>\n";
  // One line per integrator, its reference first (a --reference file has a line of its own).
  // Small renders are shown magnified, whole pixels kept sharp, so noise can be seen.
  const int scale = std::max(1, 240 / std::max(1, report.width));
  std::vector<std::string> groups;
  for (const CompareRow& row : report.rows)
    if (std::find(groups.begin(), groups.end(), row.integrator) == groups.end())
      groups.push_back(row.integrator);
  for (const std::string& group : groups) {
    html << "<div class=\"images\">\n";
    for (const CompareRow& row : report.rows) {
      if (row.integrator != group) continue;
      std::string caption = (row.reference ? "reference: " : "") + row.integrator + ", " +
                            row.spheres + ", " + std::to_string(row.spp) + " spp";
      if (row.target_error)
        caption += " max, adaptive " + format_error(*row.target_error) + ", " +
                   for_people(optional(mean_spp(row, report))) + " mean";
      html << "<figure><img src=\"" << xml_escape(row.image) << "\" width=\""
           << report.width * scale << "\" height=\"" << report.height * scale << "\" alt=\""
           << xml_escape(caption) << "\"><figcaption>" << xml_escape(caption);
      if (row.error)
        html << "<br>RMSE " << format_error(row.error->rmse) << ", relMSE "
             << format_error(row.error->relmse);
      html << "</figcaption></figure>\n";
    }
    html << "</div>\n";
  }
  // Equal time and equal error: what each integrator makes of the same budget, and what it
  // costs to reach the same error, each image above its heat map against the reference.
  const auto figures = [&](const char* title, const SideBySide& side, const std::string& what) {
    if (side.rows.empty()) return;
    html << "<h2>" << title << " (" << what << ")</h2>\n<div class=\"images\">\n";
    for (size_t r : side.rows) {
      const CompareRow& row = report.rows[r];
      std::string caption = row.integrator + ", " + sampling_label(row) + ", " +
                            std::to_string(row.spp) + " spp: " + format_error(row.seconds) + " s";
      if (row.error)
        caption += ", " + std::string(report.plot_metric == "rmse" ? "RMSE " : "relMSE ") +
                   format_error(plot_error(row, report.plot_metric));
      html << "<figure><img src=\"" << xml_escape(row.image) << "\" width=\""
           << report.width * scale << "\" height=\"" << report.height * scale << "\" alt=\""
           << xml_escape(caption) << "\"><br><img src=\"" << xml_escape(row.heatmap)
           << "\" width=\"" << report.width * scale << "\" height=\"" << report.height * scale
           << "\" alt=\"error heat map\"><figcaption>" << xml_escape(caption)
           << "</figcaption></figure>\n";
    }
    html << "</div>\n";
  };
  html << "<p>Heat maps: the absolute error against the reference, black at 0 through blue, "
          "magenta, red and yellow to white at "
       << format_error(report.heatmap_peak) << " (the reference's mean); non-finite green.</p>\n";
  figures("Equal time", equal_time(report),
          "nearest to " + format_error(equal_time(report).target) + " s");
  figures("Equal error", equal_error(report),
          "nearest to " + report.plot_metric + " " + format_error(equal_error(report).target));
  html << "<h2>Time against error</h2>\n<img class=\"plot\" src=\"plot.svg\" width=\"" << kPlotWidth
       << "\" height=\"" << kPlotHeight << "\" alt=\"wall seconds against " << report.plot_metric
       << ", log-log\">\n<h2>Results</h2>\n<table>\n";
  const auto cells = table_cells(report, kHtml);
  for (size_t r = 0; r < cells.size(); ++r) {
    html << "<tr>";
    for (size_t i = 0; i < cells[r].size(); ++i) {
      const char* tag = r == 0 ? "th" : "td";
      const bool name = left_aligned(cells[0][i]);
      html << "<" << tag << (name ? " class=\"name\"" : "") << ">" << xml_escape(cells[r][i])
           << "</" << tag << ">";
    }
    html << "</tr>\n";
  }
  html << "</table>\n";
  html << "</body>\n</html>\n";
  write_file(path, html.str());
}

}  // namespace prism
