#include "renderer/shading/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/sampling/piecewise_constant.h"

namespace prism {
namespace {

constexpr double kPi = std::numbers::pi;

// Luminance weights of Rec.709: only a sampling density, so any positive weights keep the
// estimate unbiased; these put the samples where the light is for the usual working spaces.
double luminance(const Imath::V3f& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// The real spherical harmonics of order <= 2 (Ramamoorthi and Hanrahan 2001, equation 3),
// ordered (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2) with y playing
// their z, and the clamped cosine's coefficients A_l for each.
constexpr double kY0 = 0.28209479177387814;   // 1 / (2 sqrt(pi))
constexpr double kY1 = 0.48860251190291992;   // sqrt(3 / (4 pi))
constexpr double kY2 = 1.0925484305920792;    // sqrt(15 / (4 pi))
constexpr double kY20 = 0.31539156525252005;  // sqrt(5 / (16 pi))
constexpr double kY22 = 0.54627421529603959;  // sqrt(15 / (16 pi))
constexpr double kA[9] = {kPi,     2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,
                          kPi / 4, kPi / 4,     kPi / 4,     kPi / 4};

// The integrals of the monomials the basis is made of over one texel, exactly: the map is
// constant over a texel, so its projection is exact too, not a midpoint rule.
struct MonomialIntegrals {
  double one, x, y, z, xy, yz, xz, xx, yy, zz;
};

// Over theta in [t0, t1] (from +Y) and phi in [p0, p1], x = sin t cos p, y = cos t,
// z = sin t sin p, with dw = sin t dt dp.
MonomialIntegrals texel_integrals(double t0, double t1, double p0, double p1) {
  const double c0 = std::cos(t0), c1 = std::cos(t1), s0 = std::sin(t0), s1 = std::sin(t1);
  const double a0 = c0 - c1;                                                         // sin
  const double ay = 0.5 * (s1 * s1 - s0 * s0);                                       // cos sin
  const double as = 0.5 * (t1 - t0) - 0.25 * (std::sin(2 * t1) - std::sin(2 * t0));  // sin^2
  const double ays = (s1 * s1 * s1 - s0 * s0 * s0) / 3;                              // cos sin^2
  const double ayy = (c0 * c0 * c0 - c1 * c1 * c1) / 3;                              // cos^2 sin
  const double ass = a0 - ayy;                                                       // sin^3
  const double dp = p1 - p0;
  const double cc = std::sin(p1) - std::sin(p0);  // cos
  const double cs = std::cos(p0) - std::cos(p1);  // sin
  const double c2 = 0.25 * (std::sin(2 * p1) - std::sin(2 * p0));
  const double ccc = 0.5 * dp + c2, css = 0.5 * dp - c2;  // cos^2, sin^2
  const double ccs = 0.5 * (std::sin(p1) * std::sin(p1) - std::sin(p0) * std::sin(p0));
  return {a0 * dp,  as * cc,   ay * dp,   as * cs,  ays * cc,
          ays * cs, ass * ccs, ass * ccc, ayy * dp, ass * css};
}

std::array<double, 9> basis_integrals(const MonomialIntegrals& m) {
  return {kY0 * m.one,
          kY1 * m.x,
          kY1 * m.y,
          kY1 * m.z,
          kY2 * m.xy,
          kY2 * m.xz,
          kY20 * (3 * m.yy - m.one),
          kY2 * m.yz,
          kY22 * (m.zz - m.xx)};
}

// The basis at a unit direction, in the same order and frame as basis_integrals.
std::array<double, 9> basis(double x, double y, double z) {
  return {kY0,
          kY1 * x,
          kY1 * y,
          kY1 * z,
          kY2 * x * y,
          kY2 * x * z,
          kY20 * (3 * y * y - 1),
          kY2 * y * z,
          kY22 * (z * z - x * x)};
}

}  // namespace

struct Environment::Map {
  int width = 0, height = 0;
  std::vector<Imath::V3f> texels;  // row-major, row 0 up, times the intensity
  PiecewiseConstant2D distribution;
  // The luminance above the mean (EnvironmentDensity::beside_bsdf); when no texel is above
  // it, the complete distribution stands in.
  PiecewiseConstant2D compensated;
  bool has_compensated = false;
  const PiecewiseConstant2D& by(EnvironmentDensity density) const {
    return density == EnvironmentDensity::beside_bsdf && has_compensated ? compensated
                                                                         : distribution;
  }
  double cos_rotation = 1.0, sin_rotation = 0.0;
  Imath::V3f integral{0.0f};               // of the radiance over the sphere
  std::array<Imath::V3f, 9> irradiance{};  // A_l times the radiance's coefficients

  // World direction -> the map's frame: turned back by the rotation.
  void to_map(const Imath::V3f& d, double* x, double* y, double* z) const {
    *x = cos_rotation * d.x - sin_rotation * d.z;
    *y = d.y;
    *z = sin_rotation * d.x + cos_rotation * d.z;
  }
  size_t texel_at(size_t column, size_t row) const {
    return row * static_cast<size_t>(width) + column;
  }
  size_t texel_index(const Imath::V3f& d, int* column = nullptr, int* row = nullptr) const {
    double x, y, z;
    to_map(d, &x, &y, &z);
    const double s = 0.5 + std::atan2(z, x) / (2 * kPi);
    const double t = std::acos(std::clamp(y, -1.0, 1.0)) / kPi;
    const int c = std::clamp(static_cast<int>(s * width), 0, width - 1);
    const int r = std::clamp(static_cast<int>(t * height), 0, height - 1);
    if (column) *column = c;
    if (row) *row = r;
    return texel_at(static_cast<size_t>(c), static_cast<size_t>(r));
  }
};

Environment::Environment(const Imath::V3f& radiance)
    : radiance_(radiance), black_(radiance.x <= 0.0f && radiance.y <= 0.0f && radiance.z <= 0.0f) {}

Environment::Environment(const Image& image, float rotation_radians, float intensity) {
  if (image.width < 1 || image.height < 1) throw std::invalid_argument("the map is empty");
  auto map = std::make_shared<Map>();
  map->width = image.width;
  map->height = image.height;
  map->cos_rotation = std::cos(static_cast<double>(rotation_radians));
  map->sin_rotation = std::sin(static_cast<double>(rotation_radians));
  const size_t w = static_cast<size_t>(image.width), h = static_cast<size_t>(image.height);
  map->texels.resize(w * h);
  std::vector<double> weights(w * h), solid_angles(h);
  std::array<double, 9> sh[3] = {};
  double integral[3] = {0.0, 0.0, 0.0};
  const double dphi = 2 * kPi / static_cast<double>(w);
  for (size_t r = 0; r < h; ++r) {
    const double t0 = kPi * static_cast<double>(r) / static_cast<double>(h);
    const double t1 = kPi * static_cast<double>(r + 1) / static_cast<double>(h);
    const double solid_angle = dphi * (std::cos(t0) - std::cos(t1));
    solid_angles[r] = solid_angle;
    for (size_t c = 0; c < w; ++c) {
      const float* p = image.pixel(static_cast<int>(c), static_cast<int>(r));
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(p[k]) || p[k] < 0.0f) {
          static const char* kChannel[] = {"red", "green", "blue"};
          throw std::invalid_argument(
              "texel (" + std::to_string(c) + ", " + std::to_string(r) + ") has " +
              (std::isfinite(p[k]) ? std::string("a negative ") : std::string("a non-finite ")) +
              kChannel[k] + " value; an environment's radiance must be finite and >= 0");
        }
      }
      const Imath::V3f texel = Imath::V3f(p[0], p[1], p[2]) * intensity;
      if (!std::isfinite(texel.x) || !std::isfinite(texel.y) || !std::isfinite(texel.z))
        throw std::invalid_argument("texel (" + std::to_string(c) + ", " + std::to_string(r) +
                                    ") times the intensity is not finite");
      map->texels[r * w + c] = texel;
      weights[r * w + c] = luminance(texel) * solid_angle;
      const double p0 = -kPi + dphi * static_cast<double>(c);
      const std::array<double, 9> y = basis_integrals(texel_integrals(t0, t1, p0, p0 + dphi));
      for (int k = 0; k < 3; ++k) {
        integral[k] += texel[k] * solid_angle;
        for (int i = 0; i < 9; ++i) sh[k][i] += texel[k] * y[i];
      }
    }
  }
  map->distribution = PiecewiseConstant2D(weights, w, h);
  // The mean luminance over the sphere (the weights are luminance times solid angle), then
  // each texel's luminance above it times its solid angle.
  double mean = 0.0;
  for (double weight : weights) mean += weight;
  mean /= 4 * kPi;
  std::vector<double> excess(w * h);
  double excess_total = 0.0;
  for (size_t r = 0; r < h; ++r)
    for (size_t c = 0; c < w; ++c) {
      const double above = luminance(map->texels[r * w + c]) - mean;
      excess[r * w + c] = above > 0.0 ? above * solid_angles[r] : 0.0;
      excess_total += excess[r * w + c];
    }
  map->has_compensated = excess_total > 0.0;
  if (map->has_compensated) map->compensated = PiecewiseConstant2D(excess, w, h);
  map->integral = Imath::V3f(static_cast<float>(integral[0]), static_cast<float>(integral[1]),
                             static_cast<float>(integral[2]));
  for (int i = 0; i < 9; ++i)
    map->irradiance[i] =
        Imath::V3f(static_cast<float>(kA[i] * sh[0][i]), static_cast<float>(kA[i] * sh[1][i]),
                   static_cast<float>(kA[i] * sh[2][i]));
  black_ = !(map->distribution.total() > 0.0);
  map_ = std::move(map);
}

Imath::V3f Environment::map_radiance(const Imath::V3f& direction) const {
  return map_->texels[map_->texel_index(direction)];
}

std::array<int, 2> Environment::texel_of(const Imath::V3f& direction) const {
  std::array<int, 2> texel{0, 0};
  if (map_) map_->texel_index(direction, &texel[0], &texel[1]);
  return texel;
}

bool Environment::sample(const Imath::V2f& u, EnvironmentSample* out,
                         EnvironmentDensity density) const {
  if (black_) return false;
  if (!map_) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
    out->wi = Imath::V3f(r * std::cos(phi), r * std::sin(phi), z);
    out->radiance = radiance_;
    out->pdf = 1.0f / (4.0f * std::numbers::pi_v<float>);
    return true;
  }
  double s = 0.0, t = 0.0, texel_density = 0.0;
  size_t column = 0, row = 0;
  map_->by(density).sample(u.x, u.y, &s, &t, &column, &row, &texel_density);
  const double theta = kPi * t, phi = 2 * kPi * s - kPi;
  const double sin_theta = std::sin(theta);
  const double x = sin_theta * std::cos(phi), y = std::cos(theta), z = sin_theta * std::sin(phi);
  // Back to the world: turned by the rotation.
  const Imath::V3f wi(static_cast<float>(map_->cos_rotation * x + map_->sin_rotation * z),
                      static_cast<float>(y),
                      static_cast<float>(-map_->sin_rotation * x + map_->cos_rotation * z));
  out->wi = wi.normalized();
  // radiance() and pdf() look wi up again, and the three must agree exactly even where
  // rounding puts wi on the far side of a texel's edge. Rounding wi to float and normalising
  // it moves it by less than 5e-7; the lookup's atan2 and acos turn that into at most
  // 5e-7 / sin(theta) radians. Away from the edges by four times that, in texels, the lookup
  // finds the sampled texel, so its two inverse trigonometric calls are skipped; nearer, or
  // near a pole, wi is looked up as radiance() would.
  const double margin_s = 4 * 5e-7 / (2 * kPi * sin_theta) * map_->width;
  const double margin_t = 4 * 5e-7 / (kPi * sin_theta) * map_->height;
  const double in_s = s * map_->width - static_cast<double>(column);
  const double in_t = t * map_->height - static_cast<double>(row);
  if (sin_theta > 0.0 && in_s > margin_s && in_s < 1.0 - margin_s && in_t > margin_t &&
      in_t < 1.0 - margin_t) {
    out->pdf = map_pdf(out->wi, static_cast<int>(column), static_cast<int>(row), density);
    out->radiance = map_->texels[map_->texel_at(column, row)];
  } else {
    out->radiance = radiance_and_pdf(out->wi, &out->pdf, density);
  }
  return out->pdf > 0.0f;
}

Imath::V3f Environment::radiance_and_pdf(const Imath::V3f& wi, float* pdf,
                                         EnvironmentDensity density) const {
  if (black_ || !map_) {
    *pdf = this->pdf(wi, density);
    return radiance(wi);
  }
  int column = 0, row = 0;
  const size_t texel = map_->texel_index(wi, &column, &row);
  *pdf = map_pdf(wi, column, row, density);
  return map_->texels[texel];
}

float Environment::pdf(const Imath::V3f& wi, EnvironmentDensity density) const {
  if (black_) return 0.0f;
  if (!map_) return 1.0f / (4.0f * std::numbers::pi_v<float>);
  int column = 0, row = 0;
  map_->texel_index(wi, &column, &row);
  return map_pdf(wi, column, row, density);
}

float Environment::map_pdf(const Imath::V3f& wi, int column, int row,
                           EnvironmentDensity density) const {
  // From x and z, not sqrt(1 - y^2): near the poles y rounds to 1 while x and z still say
  // how far from the pole the direction is.
  const double sin_theta = std::hypot(double(wi.x), double(wi.z));
  if (sin_theta <= 0.0) return 0.0f;
  // (s, t) -> direction stretches area by dw = 2 pi^2 sin(theta) ds dt.
  return static_cast<float>(
      map_->by(density).density(static_cast<size_t>(column), static_cast<size_t>(row)) /
      (2 * kPi * kPi * sin_theta));
}

Imath::V3f Environment::power(float scene_radius) const {
  const float pi = std::numbers::pi_v<float>;
  const Imath::V3f integral = map_ ? map_->integral : radiance_ * (4.0f * pi);
  return integral * (pi * scene_radius * scene_radius);
}

Imath::V3f Environment::irradiance(const Imath::V3f& normal) const {
  if (!map_) return radiance_ * std::numbers::pi_v<float>;
  double x, y, z;
  map_->to_map(normal, &x, &y, &z);
  const std::array<double, 9> b = basis(x, y, z);
  double e[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 9; ++i)
    for (int k = 0; k < 3; ++k) e[k] += map_->irradiance[i][k] * b[i];
  return Imath::V3f(static_cast<float>(std::max(0.0, e[0])),
                    static_cast<float>(std::max(0.0, e[1])),
                    static_cast<float>(std::max(0.0, e[2])));
}

Environment gradient_sky(float zenith, float nadir) {
  constexpr int kRows = 256;
  Image map(1, kRows);
  for (int r = 0; r < kRows; ++r) {
    const double t0 = kPi * r / kRows, t1 = kPi * (r + 1) / kRows;
    // The mean of y = cos(theta) over the row's solid angle.
    const double mean_y = 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) /
                          (std::cos(t0) - std::cos(t1));
    const float v = static_cast<float>(nadir + (zenith - nadir) * 0.5 * (1.0 + mean_y));
    float* p = map.pixel(0, r);
    p[0] = p[1] = p[2] = v;
    p[3] = 1.0f;
  }
  return Environment(map, 0.0f, 1.0f);
}

}  // namespace prism
