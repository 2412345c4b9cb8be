#include "apps/diff_command.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "apps/command_line.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/image_output.h"

namespace prism {
namespace {

// Six significant digits, as idiff prints, so the two can be compared by eye and by script.
std::string number(double v) {
  if (std::isnan(v)) return "n/a";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

double pick(const ChannelError& e, const std::string& metric) {
  if (metric == "relmse") return e.relmse;
  if (metric == "psnr") return e.psnr;
  if (metric == "max") return e.max_abs;
  return e.rmse;
}

void print_table(const DiffOptions& o, const Image& image, const ImageError& e) {
  std::printf("%s vs reference %s: %dx%d, %llu pixels compared\n", o.image_path.c_str(),
              o.reference_path.c_str(), image.width, image.height,
              static_cast<unsigned long long>(e.compared_pixels));
  std::printf("%-8s %12s %12s %12s %12s  %s\n", "channel", "RMSE", "relMSE", "PSNR (dB)",
              "max error", "at (x, y)");
  const char* names[] = {"R", "G", "B"};
  auto row = [](const char* name, const ChannelError& c, const std::string& where) {
    std::printf("%-8s %12s %12s %12s %12s  %s\n", name, number(c.rmse).c_str(),
                number(c.relmse).c_str(), number(c.psnr).c_str(), number(c.max_abs).c_str(),
                where.c_str());
  };
  for (size_t c = 0; c < 3; ++c) {
    const ChannelError& ch = e.channel[c];
    row(names[c], ch,
        ch.max_x < 0 ? "-"
                     : "(" + std::to_string(ch.max_x) + ", " + std::to_string(ch.max_y) + ")");
  }
  const ChannelError& all = e.overall;
  row("RGB", all,
      all.max_x < 0 ? "-"
                    : "(" + std::to_string(all.max_x) + ", " + std::to_string(all.max_y) + ", " +
                          names[e.max_channel] + ")");
  std::printf("non-finite pixels: %llu in %s, %llu in %s (left out of the metrics)\n",
              static_cast<unsigned long long>(e.non_finite_a), o.image_path.c_str(),
              static_cast<unsigned long long>(e.non_finite_b), o.reference_path.c_str());
  std::printf("relMSE epsilon %g, PSNR peak %g\n", kRelMseEpsilon, kPsnrPeak);
}

int run(const DiffOptions& o) {
  if (o.has_fail_above && !std::isfinite(o.fail_above))
    throw std::runtime_error("--fail-above: must be a finite number");
  const auto check_extension = [](const std::string& path, const char* option, ImageFormat want,
                                  const char* extension) {
    ImageFormat format{};
    if (!path.empty() && (!image_format_for_path(path, &format) || format != want))
      throw std::runtime_error(std::string(option) + " " + path + ": the file name must end in " +
                               extension);
  };
  check_extension(o.difference_path, "-o", ImageFormat::exr, ".exr");
  check_extension(o.heatmap_path, "--heatmap", ImageFormat::png, ".png");
  if (!(o.heatmap_peak >= 0.0) || !std::isfinite(o.heatmap_peak))
    throw std::runtime_error("--heatmap-peak: must be a finite error >= 0");
  const Image image = read_exr(o.image_path);
  const Image reference = read_exr(o.reference_path);
  if (image.width != reference.width || image.height != reference.height)
    throw std::runtime_error(o.image_path + " is " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + " but " + o.reference_path + " is " +
                             std::to_string(reference.width) + "x" +
                             std::to_string(reference.height));
  const ImageError e = compare_images(image, reference);
  if (!o.difference_path.empty() || !o.heatmap_path.empty()) {
    const Image difference = difference_image(image, reference);
    if (!o.difference_path.empty()) {
      RenderMetadata metadata;
      metadata.integrator = "diff";
      metadata.scene_path = o.image_path + " - " + o.reference_path;
      write_exr(o.difference_path, difference, ColourPipeline(WorkingSpace::linear_rec709),
                metadata, ExrPixelType::float32);
    }
    if (!o.heatmap_path.empty()) {
      const double peak = o.heatmap_peak > 0.0 ? o.heatmap_peak : e.overall.max_abs;
      write_display_png(o.heatmap_path, error_heatmap(difference, static_cast<float>(peak)));
      if (!o.quiet)
        std::printf("heat map %s: white at an error of %s\n", o.heatmap_path.c_str(),
                    number(peak).c_str());
    }
  }

  if (!o.quiet && (o.metric == "all" || o.verbose)) print_table(o, image, e);
  if (!o.quiet && o.metric != "all") std::printf("%s\n", number(pick(e.overall, o.metric)).c_str());
  if (!o.has_fail_above) return 0;

  // With the whole table, the threshold applies to RMSE.
  const std::string metric = o.metric == "all" ? "rmse" : o.metric;
  const double value = pick(e.overall, metric);
  // PSNR grows as images get closer, so "past" the threshold means below it. No pixel to
  // compare (NaN) fails too: nothing was shown to be close.
  const bool past = metric == "psnr" ? !(value >= o.fail_above) : !(value <= o.fail_above);
  if (past && !o.quiet)
    std::fprintf(stderr, "prism: diff: %s %s is %s --fail-above %s\n", metric.c_str(),
                 number(value).c_str(), metric == "psnr" ? "below" : "above",
                 number(o.fail_above).c_str());
  return past ? 1 : 0;
}

}  // namespace

CLI::App* add_diff_command(CLI::App& app, DiffOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "diff", "Compare an image with a reference: RMSE, relMSE, PSNR and maximum error");
  cmd->footer(
      "relMSE is the mean of (a-b)^2/(b^2+0.01), b the reference (epsilon 0.01, as pbrt and "
      "Mitsuba). PSNR is 10 log10(1/MSE) dB (peak 1), inf for equal images. Alpha is left "
      "out; pixels with a NaN or infinity are counted and left out. Exit 0; 1 when the metric "
      "is past --fail-above; 2 when the images cannot be compared. See docs/metrics.md.");
  cmd->add_option("image", o->image_path, "Image to test (.exr)")->required();
  cmd->add_option("reference", o->reference_path, "Reference image (.exr), the b in relMSE")
      ->required();
  cmd->add_option("--metric", o->metric,
                  "rmse | relmse | psnr | max: print only that overall number; all: the "
                  "whole table")
      ->check(CLI::IsMember({"rmse", "relmse", "psnr", "max", "all"}))
      ->capture_default_str();
  cmd->add_option_function<double>(
      "--fail-above",
      [o](const double& x) {
        o->fail_above = x;
        o->has_fail_above = true;
      },
      "Exit 1 when the metric (rmse with --metric all) is above X; for psnr, below X");
  cmd->add_option("-o,--output", o->difference_path,
                  "Also write the difference |image - reference| per channel to this EXR (as "
                  "idiff -o)");
  cmd->add_option("--heatmap", o->heatmap_path,
                  "Also write a false-colour PNG of each pixel's largest channel error: black, "
                  "blue, magenta, red, yellow, white at --heatmap-peak; non-finite green");
  cmd->add_option("--heatmap-peak", o->heatmap_peak,
                  "The error the heat map draws white (default: the largest in the image)");
  add_verbosity_flags(cmd, &o->quiet, &o->verbose,
                      "Print nothing but errors: the exit code tells (with --fail-above)",
                      "The whole table, also with one --metric (then its number last)");
  return cmd;
}

int run_diff(const DiffOptions& options) {
  // Whatever goes wrong here (an unreadable file, different sizes) is about the input: the
  // images could not be compared at all, which scripts must tell apart from "too different".
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "prism: error: %s\n", e.what());
    return 2;
  }
}

}  // namespace prism
