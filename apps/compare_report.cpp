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
enum Where { kFiles = 1, kTables = 2, kEverywhere = kFiles | kTables };

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
        {"bvh_build_seconds", "BVH s", kEverywhere,
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
        {"psnr_db", "PSNR dB", kEverywhere,
         [](auto& r, auto&) { return error_field(r, &ChannelError::psnr); }},
        {"peak_rss_mib", "peak MiB", kEverywhere,
         [](auto& r, auto&) { return optional(r.peak_rss_mib); }},
        {"source", "source", kFiles, [](auto& r, auto&) { return json(r.source); }},
        {"pareto", "pareto", kFiles, [](auto& r, auto&) { return json(r.pareto); }},
        {"note", "note", kTables,
         [](auto& r, auto&) {
           if (r.reference) return json("reference (" + r.source + ")");
           return json(r.pareto ? "Pareto front" : "");
         }},
        {"image", "image", kFiles, [](auto& r, auto&) { return json(r.image); }},
    };
    // One column per kind of ray, before rays/s.
    auto at = std::find_if(list.begin(), list.end(),
                           [](const Column& c) { return c.key == "rays_per_second"; });
    for (const EnumName<RayKind>& kind : kRayKindNames) {
      const RayKind k = kind.value;
      at = list.insert(at, Column{std::string("rays_") + kind.name, kind.name, kEverywhere,
                                  [k](const CompareRow& r, const CompareReport&) {
                                    return json(r.rays[k]);
                                  }}) +
           1;
    }
    return list;
  }();
  return list;
}

// The first columns of the tables (integrator, spheres, sampling) are names, read left to
// right, as is the note at the end; numbers line up on their last digit.
constexpr size_t kNameColumns = 3;
bool left_aligned(size_t column, size_t columns) {
  return column < kNameColumns || column + 1 == columns;
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

// The tables' cells, header first.
std::vector<std::vector<std::string>> table_cells(const CompareReport& report) {
  std::vector<std::vector<std::string>> cells(1);
  for (const Column& c : columns())
    if (c.where & kTables) cells[0].push_back(c.header);
  for (const CompareRow& row : report.rows) {
    cells.emplace_back();
    for (const Column& c : columns())
      if (c.where & kTables) cells.back().push_back(for_people(c.value(row, report)));
  }
  return cells;
}

}  // namespace

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
  const json doc = {{"scene", report.scene},
                    {"width", report.width},
                    {"height", report.height},
                    {"camera", report.camera},
                    {"working_space", report.working_space},
                    {"max_depth", report.max_depth},
                    {"adaptive_min_spp", report.min_spp},
                    {"plot_metric", report.plot_metric},
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
  const auto cells = table_cells(report);
  std::vector<size_t> width(cells[0].size(), 0);
  for (const auto& line : cells)
    for (size_t i = 0; i < line.size(); ++i) width[i] = std::max(width[i], line[i].size());
  for (const auto& line : cells) {
    std::string text;
    for (size_t i = 0; i < line.size(); ++i) {
      const bool left = left_aligned(i, line.size());
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
  html << "<h2>Time against error</h2>\n<img class=\"plot\" src=\"plot.svg\" width=\"" << kPlotWidth
       << "\" height=\"" << kPlotHeight << "\" alt=\"wall seconds against " << report.plot_metric
       << ", log-log\">\n<h2>Results</h2>\n<table>\n";
  const auto cells = table_cells(report);
  for (size_t r = 0; r < cells.size(); ++r) {
    html << "<tr>";
    for (size_t i = 0; i < cells[r].size(); ++i) {
      const char* tag = r == 0 ? "th" : "td";
      const bool name = left_aligned(i, cells[r].size());
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
