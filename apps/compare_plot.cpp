#include "apps/compare_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "renderer/image/oiio_module.h"

namespace prism {
namespace {

struct Rgb {
  float r, g, b;
};

enum class Anchor { start, middle, end };

// What the plot needs from a drawing surface; coordinates in pixels of the 800x500 plot,
// y down.
class Canvas {
 public:
  virtual ~Canvas() = default;
  virtual void line(double x1, double y1, double x2, double y2, Rgb colour, double width) = 0;
  virtual void square(double cx, double cy, double half, Rgb colour, bool filled) = 0;
  // Filled; `half` from the centre to each corner.
  virtual void diamond(double cx, double cy, double half, Rgb colour) = 0;
  // `y` is the middle of the text's height.
  virtual void text(double x, double y, const std::string& text, int size, Anchor anchor,
                    Rgb colour) = 0;
};

class SvgCanvas : public Canvas {
 public:
  void line(double x1, double y1, double x2, double y2, Rgb c, double width) override {
    out_ << "<line x1=\"" << x1 << "\" y1=\"" << y1 << "\" x2=\"" << x2 << "\" y2=\"" << y2
         << "\" stroke=\"" << css(c) << "\" stroke-width=\"" << width
         << "\" stroke-linecap=\"round\"/>\n";
  }
  void square(double cx, double cy, double half, Rgb c, bool filled) override {
    out_ << "<rect x=\"" << cx - half << "\" y=\"" << cy - half << "\" width=\"" << 2 * half
         << "\" height=\"" << 2 * half << "\" "
         << (filled ? "fill=\"" + css(c) + "\"" : "fill=\"none\" stroke=\"" + css(c) + "\"")
         << "/>\n";
  }
  void diamond(double cx, double cy, double half, Rgb c) override {
    out_ << "<polygon points=\"" << cx << "," << cy - half << " " << cx + half << "," << cy << " "
         << cx << "," << cy + half << " " << cx - half << "," << cy << "\" fill=\"" << css(c)
         << "\"/>\n";
  }
  void text(double x, double y, const std::string& text, int size, Anchor anchor, Rgb c) override {
    const char* anchors[] = {"start", "middle", "end"};
    out_ << "<text x=\"" << x << "\" y=\"" << y << "\" font-size=\"" << size << "\" text-anchor=\""
         << anchors[static_cast<int>(anchor)] << "\" dominant-baseline=\"central\" fill=\""
         << css(c) << "\">" << xml_escape(text) << "</text>\n";
  }
  std::string document() const {
    std::ostringstream doc;
    doc << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kPlotWidth << "\" height=\""
        << kPlotHeight << "\" viewBox=\"0 0 " << kPlotWidth << " " << kPlotHeight
        << "\" font-family=\"DejaVu Sans, sans-serif\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << out_.str() << "</svg>\n";
    return doc.str();
  }

 private:
  static std::string css(Rgb c) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", static_cast<int>(c.r * 255 + 0.5f),
                  static_cast<int>(c.g * 255 + 0.5f), static_cast<int>(c.b * 255 + 0.5f));
    return buffer;
  }
  std::ostringstream out_;
};

// Draws on OpenImageIO's raster (loaded only now: renderer/image/oiio_module.h) at kScale
// times the size and shrinks once at the end, because its lines and boxes are not
// antialiased.
class ImageCanvas : public Canvas {
 public:
  static constexpr int kScale = 2;

  explicit ImageCanvas(const std::string& path)
      : raster_(oiio_module(path).make_canvas(kPlotWidth * kScale, kPlotHeight * kScale)) {}
  void line(double x1, double y1, double x2, double y2, Rgb c, double width) override {
    // A wide line as parallel one-pixel lines across its width.
    const double length = std::hypot(x2 - x1, y2 - y1);
    const double nx = length > 0 ? -(y2 - y1) / length : 0.0,
                 ny = length > 0 ? (x2 - x1) / length : 0.0;
    const int strokes = std::max(1, static_cast<int>(std::lround(width * kScale)));
    for (int i = 0; i < strokes; ++i) {
      const double o = (i - (strokes - 1) / 2.0) / kScale;
      raster_->line(px(x1 + nx * o), px(y1 + ny * o), px(x2 + nx * o), px(y2 + ny * o), rgb(c));
    }
  }
  void square(double cx, double cy, double half, Rgb c, bool filled) override {
    for (int ring = 0; ring < (filled ? 1 : kScale); ++ring)
      raster_->box(px(cx - half) + ring, px(cy - half) + ring, px(cx + half) - ring,
                   px(cy + half) - ring, rgb(c), filled);
  }
  void diamond(double cx, double cy, double half, Rgb c) override {
    // No filled polygons: one horizontal line per pixel row, narrowing to the corners.
    const int x = px(cx), y = px(cy), h = px(half);
    for (int dy = -h; dy <= h; ++dy) {
      const int w = h - std::abs(dy);
      raster_->line(x - w, y + dy, x + w, y + dy, rgb(c));
    }
  }
  void text(double x, double y, const std::string& text, int size, Anchor anchor, Rgb c) override {
    if (!has_font_) return;
    const TextAlign align[] = {TextAlign::left, TextAlign::centre, TextAlign::right};
    has_font_ =
        raster_->text(px(x), px(y), text, size * kScale, align[static_cast<int>(anchor)], rgb(c));
  }
  bool has_font() const { return has_font_; }
  void write(const std::string& path) { raster_->write_png(path, kPlotWidth, kPlotHeight); }

 private:
  static int px(double v) { return static_cast<int>(std::lround(v * kScale)); }
  static std::array<float, 3> rgb(Rgb c) { return {c.r, c.g, c.b}; }
  std::unique_ptr<RasterCanvas> raster_;
  bool has_font_ = true;
};

// Distinct on white and for the colour-blind (Okabe and Ito's palette), then darker repeats.
Rgb curve_colour(int i) {
  static const Rgb palette[] = {{0.00f, 0.45f, 0.70f}, {0.84f, 0.37f, 0.00f}, {0.00f, 0.62f, 0.45f},
                                {0.80f, 0.47f, 0.65f}, {0.94f, 0.89f, 0.26f}, {0.34f, 0.71f, 0.91f},
                                {0.90f, 0.62f, 0.00f}, {0.0f, 0.0f, 0.0f}};
  const Rgb c = palette[i % 8];
  const float shade = (i / 8) % 2 ? 0.6f : 1.0f;
  return {c.r * shade, c.g * shade, c.b * shade};
}

bool plottable(const PlotPoint& p) {
  return std::isfinite(p.seconds) && std::isfinite(p.error) && p.seconds > 0 && p.error > 0;
}

// A log axis over whole decades covering [lo, hi], with 2 and 5 between when it spans few.
struct LogAxis {
  double lo_exp = 0, hi_exp = 1;
  LogAxis(double lo, double hi) {
    lo_exp = std::floor(std::log10(lo));
    hi_exp = std::ceil(std::log10(hi));
    if (hi_exp <= lo_exp) hi_exp = lo_exp + 1;
  }
  double fraction(double v) const { return (std::log10(v) - lo_exp) / (hi_exp - lo_exp); }
  std::vector<double> ticks() const {
    std::vector<double> t;
    const bool minor = hi_exp - lo_exp <= 2;
    for (double e = lo_exp; e <= hi_exp; ++e) {
      const double decade = std::pow(10.0, e);
      t.push_back(decade);
      if (minor && e < hi_exp) {
        t.push_back(2 * decade);
        t.push_back(5 * decade);
      }
    }
    return t;
  }
};

std::string tick_label(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

void draw_plot(const Plot& plot, Canvas& canvas) {
  constexpr double left = 80, right = kPlotWidth - 210, top = 50, bottom = kPlotHeight - 60;
  constexpr Rgb black{0, 0, 0}, grid{0.88f, 0.88f, 0.88f}, front{0.75f, 0.75f, 0.75f};
  canvas.text((left + right) / 2, 20, plot.title, 15, Anchor::middle, black);

  std::vector<PlotPoint> points;
  for (const PlotPoint& p : plot.points)
    if (plottable(p)) points.push_back(p);
  if (points.empty()) {
    canvas.text((left + right) / 2, (top + bottom) / 2, "no point with time and error > 0", 13,
                Anchor::middle, black);
    return;
  }
  auto [tmin, tmax] = std::minmax_element(points.begin(), points.end(),
                                          [](auto& a, auto& b) { return a.seconds < b.seconds; });
  auto [emin, emax] = std::minmax_element(points.begin(), points.end(),
                                          [](auto& a, auto& b) { return a.error < b.error; });
  const LogAxis xaxis(tmin->seconds, tmax->seconds), yaxis(emin->error, emax->error);
  auto X = [&](double t) { return left + xaxis.fraction(t) * (right - left); };
  auto Y = [&](double e) { return bottom - yaxis.fraction(e) * (bottom - top); };

  for (double t : xaxis.ticks()) {
    canvas.line(X(t), top, X(t), bottom, grid, 1);
    canvas.text(X(t), bottom + 12, tick_label(t), 11, Anchor::middle, black);
  }
  for (double e : yaxis.ticks()) {
    canvas.line(left, Y(e), right, Y(e), grid, 1);
    canvas.text(left - 6, Y(e), tick_label(e), 11, Anchor::end, black);
  }
  canvas.line(left, top, right, top, black, 1);
  canvas.line(left, bottom, right, bottom, black, 1);
  canvas.line(left, top, left, bottom, black, 1);
  canvas.line(right, top, right, bottom, black, 1);
  canvas.text((left + right) / 2, bottom + 36, "wall seconds (log scale)", 13, Anchor::middle,
              black);
  canvas.text(left, top - 14, plot.error_label + " against the reference (log scale)", 13,
              Anchor::start, black);

  // The front first, wide and pale, so the curves are drawn over it.
  std::vector<PlotPoint> pareto;
  for (const PlotPoint& p : points)
    if (p.pareto) pareto.push_back(p);
  std::sort(pareto.begin(), pareto.end(), [](auto& a, auto& b) { return a.seconds < b.seconds; });
  for (size_t i = 1; i < pareto.size(); ++i)
    canvas.line(X(pareto[i - 1].seconds), Y(pareto[i - 1].error), X(pareto[i].seconds),
                Y(pareto[i].error), front, 8);
  for (const PlotPoint& p : pareto) canvas.square(X(p.seconds), Y(p.error), 8, black, false);

  for (int c = 0; c < static_cast<int>(plot.curves.size()); ++c) {
    // The uniform points joined by spp; the adaptive ones stand apart, each its own trade-off.
    std::vector<PlotPoint> curve, adaptive;
    for (const PlotPoint& p : points)
      if (p.curve == c) (p.target_error ? adaptive : curve).push_back(p);
    std::sort(curve.begin(), curve.end(), [](auto& a, auto& b) { return a.spp < b.spp; });
    const Rgb colour = curve_colour(c);
    for (size_t i = 1; i < curve.size(); ++i)
      canvas.line(X(curve[i - 1].seconds), Y(curve[i - 1].error), X(curve[i].seconds),
                  Y(curve[i].error), colour, 2);
    for (const PlotPoint& p : curve) {
      canvas.square(X(p.seconds), Y(p.error), 4, colour, true);
      canvas.text(X(p.seconds) + 9, Y(p.error) - 9, std::to_string(p.spp), 10, Anchor::start,
                  colour);
    }
    for (const PlotPoint& p : adaptive) {
      canvas.diamond(X(p.seconds), Y(p.error), 6, colour);
      canvas.text(X(p.seconds) + 9, Y(p.error) + 9, "e " + tick_label(*p.target_error), 10,
                  Anchor::start, colour);
    }
    const double ly = top + 10 + 20 * c;
    canvas.line(right + 15, ly, right + 40, ly, colour, 2);
    canvas.square(right + 27.5, ly, 4, colour, true);
    canvas.text(right + 48, ly, plot.curves[static_cast<size_t>(c)], 12, Anchor::start, colour);
  }
  const double ly = top + 10 + 20 * static_cast<double>(plot.curves.size());
  canvas.line(right + 15, ly, right + 40, ly, front, 8);
  canvas.square(right + 27.5, ly, 8, black, false);
  canvas.text(right + 48, ly, "Pareto front", 12, Anchor::start, black);
  canvas.text(right + 15, ly + 22, "squares: uniform, by spp", 11, Anchor::start, black);
  if (std::any_of(points.begin(), points.end(), [](auto& p) { return p.target_error; })) {
    canvas.diamond(right + 20, ly + 40, 5, black);
    canvas.text(right + 30, ly + 40, "adaptive, e target error", 11, Anchor::start, black);
  }
}

}  // namespace

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void mark_pareto_front(std::vector<PlotPoint>* points) {
  for (PlotPoint& p : *points) {
    p.pareto = plottable(p);
    for (const PlotPoint& q : *points) {
      if (!p.pareto) break;
      if (plottable(q) && q.seconds <= p.seconds && q.error <= p.error &&
          (q.seconds < p.seconds || q.error < p.error))
        p.pareto = false;
    }
  }
}

void write_plot_svg(const std::string& path, const Plot& plot) {
  SvgCanvas canvas;
  draw_plot(plot, canvas);
  std::ofstream out(path, std::ios::binary);
  out << canvas.document();
  if (!out.flush()) throw std::runtime_error(path + ": cannot write");
}

bool write_plot_png(const std::string& path, const Plot& plot) {
  ImageCanvas canvas(path);
  draw_plot(plot, canvas);
  canvas.write(path);
  return canvas.has_font();
}

}  // namespace prism
