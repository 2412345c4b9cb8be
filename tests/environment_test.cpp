// The environment as a light (renderer/shading/environment.h): the map's conventions and
// rotation, importance sampling against pdf() (chi-square), pdf() integrating to 1, samples
// landing in the texel they were drawn from, power, and the irradiance the ambient term of
// phong, shadow and whitted takes from it; then the session's reading of environment files
// (hostile ones refused in one line naming the file), the job fingerprint, and the default
// lighting of a file without lights.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "renderer/image/exr_file.h"
#include "renderer/shading/environment.h"
#include "scene_passes/scene_defaults.h"
#include "session/job_fingerprint.h"
#include "session/session.h"
#include "tests/chi_square.h"

namespace prism {
namespace {

namespace fs = std::filesystem;
constexpr double kPiD = std::numbers::pi;

// The direction at (s, t) of the map's frame: s along the row, t down from +Y.
V3f map_direction(double s, double t) {
  const double theta = kPiD * t, phi = 2 * kPiD * s - kPiD;
  return V3f(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
             float(std::sin(theta) * std::sin(phi)));
}

Image constant_map(int w, int h, float v) {
  Image map(w, h);
  for (size_t i = 0; i < map.rgba.size(); ++i) map.rgba[i] = (i % 4 == 3) ? 1.0f : v;
  return map;
}

// Every texel different: red its column, green its row, blue 1.
Image numbered_map(int w, int h) {
  Image map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = map.pixel(x, y);
      p[0] = float(x);
      p[1] = float(y);
      p[2] = 1.0f;
      p[3] = 1.0f;
    }
  return map;
}

// A gradient from a bright top to a dim bottom, with a sun of 4 texels 5000 times brighter:
// the kind of map importance sampling is for.
Image sun_map(int w, int h, float sun = 5000.0f) {
  Image map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = map.pixel(x, y);
      const float g = 0.05f + 1.0f * float(h - y) / float(h);
      p[0] = g * 0.6f;
      p[1] = g * 0.8f;
      p[2] = g;
      p[3] = 1.0f;
    }
  for (int y = h / 4; y < h / 4 + 2; ++y)
    for (int x = w / 3; x < w / 3 + 2; ++x) {
      float* p = map.pixel(x, y);
      p[0] = sun;
      p[1] = sun * 0.9f;
      p[2] = sun * 0.8f;
    }
  return map;
}

V3f texel(const Image& map, int x, int y) {
  const float* p = map.pixel(x, y);
  return V3f(p[0], p[1], p[2]);
}

TEST(Environment, MapConventions) {
  const Image map = numbered_map(16, 8);
  const Environment env(map, 0.0f, 1.0f);
  // Row 0 looks up, the last row down; the middle column along +X, 3/4 along +Z, 1/4 -Z.
  EXPECT_EQ(env.texel_of(V3f(0, 1, 0))[1], 0);
  EXPECT_EQ(env.texel_of(V3f(0, -1, 0))[1], 7);
  EXPECT_EQ(env.texel_of(V3f(1, 0.01f, 0).normalized()), (std::array<int, 2>{8, 3}));
  EXPECT_EQ(env.texel_of(V3f(-0.01f, 0.01f, 1).normalized()), (std::array<int, 2>{12, 3}));
  EXPECT_EQ(env.texel_of(V3f(0.01f, 0.01f, -1).normalized()), (std::array<int, 2>{4, 3}));
  // The radiance at every texel's centre is that texel, exactly.
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      EXPECT_EQ(env.radiance(map_direction((x + 0.5) / 16, (y + 0.5) / 8)), texel(map, x, y))
          << x << ", " << y;
  // Intensity scales the map.
  const Environment brighter(map, 0.0f, 2.5f);
  EXPECT_EQ(brighter.radiance(map_direction(3.5 / 16, 2.5 / 8)), texel(map, 3, 2) * 2.5f);
}

TEST(Environment, RotationTurnsTheMapAboutUp) {
  const Image map = numbered_map(32, 16);
  const Environment still(map, 0.0f, 1.0f);
  for (double degrees : {90.0, 37.0, -120.0}) {
    const double a = degrees * kPiD / 180.0;
    const Environment turned(map, float(a), 1.0f);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 32; ++x) {
        const V3f d = map_direction((x + 0.5) / 32, (y + 0.5) / 16);
        // Right-handed about +Y: x' = cos a x + sin a z, z' = -sin a x + cos a z.
        const V3f turned_d(float(std::cos(a) * d.x + std::sin(a) * d.z), d.y,
                           float(-std::sin(a) * d.x + std::cos(a) * d.z));
        EXPECT_EQ(turned.radiance(turned_d), still.radiance(d)) << degrees << ": " << x << "," << y;
      }
  }
  // 90 degrees brings what was seen along +Z round to +X (counter-clockwise from above).
  const Environment quarter(map, float(kPiD / 2), 1.0f);
  EXPECT_EQ(quarter.radiance(V3f(1, 0.01f, 0).normalized()),
            still.radiance(V3f(0.0f, 0.01f, 1).normalized()));
}

// Histograms sample() on a grid of half texels in (s, t) and compares it with pdf()
// integrated over each bin: pdf dw = pdf 2 pi^2 sin(theta) ds dt, constant over a half texel
// (the bins align with the texels), so a midpoint in (s, t) integrates it exactly.
// sample() against pdf() on sun_map(64, 32, sun) with `density`; the share of the samples
// that fell in the sun's texels goes to `sun_fraction`.
void expect_sampling_matches_pdf(EnvironmentDensity density, float sun_radiance,
                                 double* sun_fraction) {
  constexpr int kW = 64, kH = 32, kBinsX = 2 * kW, kBinsY = 2 * kH, kSamples = 2000000;
  const Environment env(sun_map(kW, kH, sun_radiance), 0.0f, 1.0f);
  std::vector<double> observed(kBinsX * kBinsY, 0.0), expected(kBinsX * kBinsY, 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int refused = 0;
  for (int i = 0; i < kSamples; ++i) {
    EnvironmentSample s;
    const Imath::V2f u(u01(rng), u01(rng));
    if (!env.sample(u, &s, density)) {
      // Only where rounding put wi across an edge into a texel the density leaves out: the
      // sample then reports that texel's zero density rather than another's.
      ASSERT_EQ(s.pdf, 0.0f) << u << " " << s.wi;
      ASSERT_EQ(env.pdf(s.wi, density), 0.0f) << u << " " << s.wi;
      ++refused;
      continue;
    }
    ASSERT_EQ(s.pdf, env.pdf(s.wi, density));
    const double sx = 0.5 + std::atan2(double(s.wi.z), double(s.wi.x)) / (2 * kPiD);
    const double ty = std::acos(std::clamp(double(s.wi.y), -1.0, 1.0)) / kPiD;
    const int bx = std::clamp(int(sx * kBinsX), 0, kBinsX - 1);
    const int by = std::clamp(int(ty * kBinsY), 0, kBinsY - 1);
    observed[size_t(by * kBinsX + bx)] += 1.0;
  }
  double total = 0.0;
  for (int by = 0; by < kBinsY; ++by)
    for (int bx = 0; bx < kBinsX; ++bx) {
      // The density per ds dt, pdf 2 pi^2 sin(theta), is constant over the bin: its
      // value at the middle times the bin's area in (s, t) is the bin's probability.
      const double s = (bx + 0.5) / kBinsX, t = (by + 0.5) / kBinsY;
      const double p = env.pdf(map_direction(s, t), density) * 2 * kPiD * kPiD * std::sin(kPiD * t);
      const double probability = p / (double(kBinsX) * kBinsY);
      expected[size_t(by * kBinsX + bx)] = probability * kSamples;
      total += probability;
    }
  EXPECT_NEAR(total, 1.0, 1e-5);
  const double p_value = testing::chi_square_test(observed, expected);
  double sun = 0.0;
  for (int by = kH / 2; by < kH / 2 + 4; ++by)
    for (int bx = 2 * (kW / 3); bx < 2 * (kW / 3) + 4; ++bx)
      sun += observed[size_t(by * kBinsX + bx)];
  *sun_fraction = sun / kSamples;
  std::printf(
      "environment chi-square (%s): p = %.4f over %d bins, %d samples; pdf sums to 1 %+.3g; "
      "%.4f of the samples in the sun, %d refused\n",
      density == EnvironmentDensity::complete ? "complete" : "beside a BSDF sample", p_value,
      kBinsX * kBinsY, kSamples, total - 1.0, *sun_fraction, refused);
  EXPECT_GT(p_value, 1e-3);
  EXPECT_LE(refused, 10);
}

TEST(Environment, SamplingMatchesPdfChiSquare) {
  double sun = 0.0;
  expect_sampling_matches_pdf(EnvironmentDensity::complete, 5000.0f, &sun);
  // The sun's 4 texels of 2048 hold most of the light, and most of the samples.
  EXPECT_GT(sun, 0.5);
}

// The density beside a BSDF sample: the same chi-square against its own pdf, nothing drawn
// where the map is at or below its mean luminance (the BSDF's samples find that light) and
// the rest in proportion to the excess, so even more of the samples in the sun. A map with no
// texel above its mean (uniform) and a uniform environment keep the complete density.
TEST(Environment, DensityBesideABsdfSampleLeavesOutWhatIsBelowTheMean) {
  // A sun 50 times the sky's brightest: a good part of the light, not nearly all of it.
  constexpr float kSun = 50.0f;
  double sun_complete = 0.0, sun_beside = 0.0;
  expect_sampling_matches_pdf(EnvironmentDensity::complete, kSun, &sun_complete);
  expect_sampling_matches_pdf(EnvironmentDensity::beside_bsdf, kSun, &sun_beside);
  EXPECT_GT(sun_beside, sun_complete * 1.5);

  const Image map = sun_map(64, 32, kSun);
  const Environment env(map, 0.0f, 1.0f);
  // The mean luminance over the sphere, texel by texel.
  double mean = 0.0;
  for (int y = 0; y < map.height; ++y) {
    const double dw = 2 * kPiD / map.width *
                      (std::cos(kPiD * y / map.height) - std::cos(kPiD * (y + 1) / map.height));
    for (int x = 0; x < map.width; ++x) {
      const V3f c = texel(map, x, y);
      mean += (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) * dw;
    }
  }
  mean /= 4 * kPiD;
  int above = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const V3f d = map_direction((x + 0.5) / map.width, (y + 0.5) / map.height);
      const V3f c = texel(map, x, y);
      const double l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
      const float p = env.pdf(d, EnvironmentDensity::beside_bsdf);
      if (l > mean * (1 + 1e-6)) {
        ++above;
        EXPECT_GT(p, 0.0f) << x << " " << y;
        // In proportion to the excess over the mean: the same ratio to the complete density
        // as the excess's to the luminance, up to one constant, checked against the sun's.
        const V3f sun = texel(map, 64 / 3, 32 / 4);
        const double sun_l = 0.2126 * sun.x + 0.7152 * sun.y + 0.0722 * sun.z;
        const V3f sun_d = map_direction((64 / 3 + 0.5) / 64, (32 / 4 + 0.5) / 32);
        const double ratio = p / env.pdf(d),
                     sun_ratio = env.pdf(sun_d, EnvironmentDensity::beside_bsdf) / env.pdf(sun_d);
        EXPECT_NEAR(ratio / sun_ratio, ((l - mean) / l) / ((sun_l - mean) / sun_l), 1e-4);
      } else if (l < mean * (1 - 1e-6)) {
        EXPECT_EQ(p, 0.0f) << x << " " << y;
      }
    }
  std::printf("mean luminance %.4f; %d of %d texels above it\n", mean, above,
              map.width * map.height);
  EXPECT_GT(above, 4);
  EXPECT_LT(above, map.width * map.height / 2);

  const Environment flat(constant_map(16, 8, 0.7f), 0.0f, 1.0f);
  const Environment uniform(V3f(0.7f));
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const V3f d =
        normalize(V3f(2.0f * u01(rng) - 1.0f, 2.0f * u01(rng) - 1.0f, 2.0f * u01(rng) - 1.0f));
    for (const Environment* e : {&flat, &uniform})
      ASSERT_EQ(e->pdf(d, EnvironmentDensity::beside_bsdf), e->pdf(d));
    EnvironmentSample a, b;
    const Imath::V2f u(u01(rng), u01(rng));
    ASSERT_TRUE(flat.sample(u, &a));
    ASSERT_TRUE(flat.sample(u, &b, EnvironmentDensity::beside_bsdf));
    ASSERT_EQ(a.wi, b.wi);
  }
}

// The test above would pass a sampler and pdf that agree with each other but not with the
// radiance: a pdf claiming uniform density fails it.
TEST(Environment, ChiSquareCatchesAWrongDensity) {
  constexpr int kW = 64, kH = 32, kSamples = 200000;
  const Environment env(sun_map(kW, kH), 0.0f, 1.0f);
  const Environment uniform(Imath::V3f(1.0f));
  std::vector<double> observed(kW * kH, 0.0), expected(kW * kH, 0.0);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < kSamples; ++i) {
    EnvironmentSample s;
    ASSERT_TRUE(env.sample(Imath::V2f(u01(rng), u01(rng)), &s));
    const std::array<int, 2> t = env.texel_of(s.wi);
    observed[size_t(t[1] * kW + t[0])] += 1.0;
  }
  for (int y = 0; y < kH; ++y) {
    const double dw = 2 * kPiD / kW * (std::cos(kPiD * y / kH) - std::cos(kPiD * (y + 1) / kH));
    for (int x = 0; x < kW; ++x)
      expected[size_t(y * kW + x)] = uniform.pdf(V3f(0, 1, 0)) * dw * kSamples;
  }
  EXPECT_LT(testing::chi_square_test(observed, expected), 1e-6);
}

// Over the whole sphere, in (s, t) with the density constant per texel: exactly 1, for the
// sun map, a map with black rows and a single bright texel.
TEST(Environment, PdfIntegratesToOne) {
  Image black_rows = sun_map(48, 24);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 48; ++x) std::fill_n(black_rows.pixel(x, y), 3, 0.0f);
  Image one = constant_map(48, 24, 0.0f);
  std::fill_n(one.pixel(7, 0), 3, 3.0f);  // at the pole, where sin(theta) is smallest
  for (const Image* map : {&black_rows, &one}) {
    const Environment env(*map, 0.3f, 1.0f);
    double integral = 0.0;
    constexpr int kSub = 2;
    const int w = map->width * kSub, h = map->height * kSub;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double s = (x + 0.5) / w, t = (y + 0.5) / h;
        // Turned into the world by the rotation, so that pdf() looks the map texel up.
        const V3f m = map_direction(s, t);
        const double a = 0.3;
        const V3f d(float(std::cos(a) * m.x + std::sin(a) * m.z), m.y,
                    float(-std::sin(a) * m.x + std::cos(a) * m.z));
        integral += env.pdf(d) * 2 * kPiD * kPiD * std::sin(kPiD * t) / (double(w) * h);
      }
    std::printf("environment pdf integral: 1 %+.3g\n", integral - 1.0);
    EXPECT_NEAR(integral, 1.0, 1e-5);
  }
}

TEST(Environment, SampleLandsInTheTexelItCameFrom) {
  // One lit texel: every sample must fall in it and carry its radiance.
  Image one = constant_map(40, 20, 0.0f);
  std::fill_n(one.pixel(29, 13), 3, 2.0f);
  const Environment env(one, 1.1f, 1.0f);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < 20000; ++i) {
    EnvironmentSample s;
    ASSERT_TRUE(env.sample(Imath::V2f(u01(rng), u01(rng)), &s));
    ASSERT_EQ(env.texel_of(s.wi), (std::array<int, 2>{29, 13}));
    ASSERT_EQ(s.radiance, V3f(2.0f));
  }
  // On any map, sample() reports exactly what radiance() and pdf() say of its direction.
  const Environment sun(sun_map(64, 32), 2.0f, 1.5f);
  for (int i = 0; i < 20000; ++i) {
    EnvironmentSample s;
    ASSERT_TRUE(sun.sample(Imath::V2f(u01(rng), u01(rng)), &s));
    ASSERT_NEAR(s.wi.length(), 1.0f, 1e-6f);
    ASSERT_EQ(s.radiance, sun.radiance(s.wi));
    ASSERT_EQ(s.pdf, sun.pdf(s.wi));
    ASSERT_GT(s.pdf, 0.0f);
  }
  // radiance_and_pdf() is the two lookups in one, in every direction, for a map and for a
  // uniform environment.
  const Environment uniform(V3f(0.5f, 0.25f, 1.0f));
  for (int i = 0; i < 20000; ++i) {
    const V3f d =
        normalize(V3f(2.0f * u01(rng) - 1.0f, 2.0f * u01(rng) - 1.0f, 2.0f * u01(rng) - 1.0f));
    for (const Environment* e : {&sun, &uniform}) {
      float pdf = -1.0f;
      ASSERT_EQ(e->radiance_and_pdf(d, &pdf), e->radiance(d));
      ASSERT_EQ(pdf, e->pdf(d));
    }
  }
}

// sample() takes the texel it drew without looking wi up again when wi is far enough from
// the texel's edges for rounding not to matter. On a map of a real size, rotated, with every
// texel's radiance different (red its column + 1, green its row + 1), the texel it reports
// must be the one the lookup finds: at random, and where it is hardest, on the two sides of
// a texel edge as close as float samples can get to it (found by bisection on u, in steps of
// one float), for column edges and row edges, the poles' rows included.
TEST(Environment, SampleReportsTheTexelTheLookupFindsOnALargeMap) {
  Image map = numbered_map(512, 256);
  for (size_t i = 0; i < map.rgba.size(); ++i)
    if (i % 4 < 2) map.rgba[i] += 1.0f;  // no black column or row: every texel is drawn
  const Environment env(map, 0.7f, 1.0f);
  const auto expect_agreement = [&](const Imath::V2f& u) {
    EnvironmentSample s;
    if (!env.sample(u, &s)) return false;
    float pdf = -1.0f;
    const V3f radiance = env.radiance_and_pdf(s.wi, &pdf);
    EXPECT_EQ(s.radiance, radiance) << u << " " << s.wi;
    EXPECT_EQ(s.pdf, pdf) << u << " " << s.wi;
    return s.radiance == radiance && s.pdf == pdf;
  };
  const auto texel_at = [&](const Imath::V2f& u) {
    EnvironmentSample s;
    env.sample(u, &s);
    return env.texel_of(s.wi);
  };
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) ASSERT_TRUE(expect_agreement(Imath::V2f(u01(rng), u01(rng))));

  int edges = 0, polar_edges = 0;
  for (int i = 0; i < 600; ++i) {
    const int axis = i % 2;  // 0: across a column edge (u.x), 1: across a row edge (u.y)
    Imath::V2f lo(u01(rng), u01(rng));
    Imath::V2f hi = lo;
    hi[axis] = std::min(lo[axis] + 0.004f, 0.99999f);
    if (i % 10 == 1) {  // across the first or last rows, a few 1e-5 of the marginal each
      lo.y = u01(rng) < 0.5f ? 1e-6f : 0.99990f;
      hi.y = lo.y + 9e-5f;
    }
    if (texel_at(lo)[axis] == texel_at(hi)[axis]) continue;
    while (std::nextafter(lo[axis], 1.0f) < hi[axis]) {
      Imath::V2f mid = lo;
      mid[axis] = 0.5f * (lo[axis] + hi[axis]);
      (texel_at(mid)[axis] == texel_at(lo)[axis] ? lo : hi) = mid;
    }
    ASSERT_TRUE(expect_agreement(lo));
    ASSERT_TRUE(expect_agreement(hi));
    ++edges;
    polar_edges += texel_at(lo)[1] < 4 || texel_at(lo)[1] > 251;
  }
  EXPECT_GT(edges, 400);
  EXPECT_GT(polar_edges, 10);
}

TEST(Environment, BlackMapsAndUniformEnvironments) {
  const Environment black(constant_map(8, 4, 0.0f), 0.0f, 1.0f);
  EXPECT_TRUE(black.black());
  EnvironmentSample s;
  EXPECT_FALSE(black.sample(Imath::V2f(0.5f), &s));
  EXPECT_EQ(black.pdf(V3f(0, 0, 1)), 0.0f);
  EXPECT_TRUE(Environment().black());
  EXPECT_FALSE(Environment(constant_map(8, 4, 1.0f), 0.0f, 1.0f).black());
  // A constant map is the uniform environment of its value: same power, same irradiance.
  const Environment map(constant_map(64, 32, 0.7f), 0.4f, 1.0f);
  const Environment uniform(Imath::V3f(0.7f));
  const V3f expected_power(float(0.7 * 4 * kPiD * kPiD * 2.0 * 2.0));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(uniform.power(2.0f)[k], expected_power[k], 1e-5f * expected_power[k]);
    EXPECT_NEAR(map.power(2.0f)[k], expected_power[k], 1e-5f * expected_power[k]);
  }
  for (const V3f& n : {V3f(0, 1, 0), V3f(1, 0, 0), V3f(0.3f, -0.5f, 0.81f).normalized()}) {
    EXPECT_NEAR(uniform.irradiance(n).x, float(0.7 * kPiD), 1e-6f);
    EXPECT_NEAR(map.irradiance(n).x, float(0.7 * kPiD), 1e-5f);
  }
  // Hidden: the camera sees black, everything else the radiance.
  Environment hidden(Imath::V3f(0.7f));
  hidden.set_hidden_from_camera(true);
  EXPECT_EQ(hidden.background(V3f(0, 0, 1)), V3f(0.0f));
  EXPECT_EQ(hidden.radiance(V3f(0, 0, 1)), V3f(0.7f));
}

TEST(Environment, PowerOfAMapIsItsRadianceIntegral) {
  // Upper hemisphere 1, lower 0: the integral is 2 pi, the power 2 pi * pi r^2.
  Image sky = constant_map(32, 16, 0.0f);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 32; ++x) std::fill_n(sky.pixel(x, y), 3, 1.0f);
  const Environment env(sky, 0.0f, 1.0f);
  EXPECT_NEAR(env.power(1.0f).y, float(2 * kPiD * kPiD), 1e-5f);
}

// The irradiance of a map that is 1 above the horizon and 0 below is pi (1 + n_y) / 2
// exactly, and the nine harmonics hold it exactly: its only even part is the constant and the
// clamped cosine has no odd part above order 1. So any error here is the projection's.
TEST(Environment, IrradianceOfAnalyticMaps) {
  Image sky = constant_map(64, 32, 0.0f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 64; ++x) std::fill_n(sky.pixel(x, y), 3, 1.0f);
  std::mt19937 rng(10);
  std::normal_distribution<float> g;
  double worst_hemisphere = 0.0, worst_sky = 0.0;
  for (float rotation : {0.0f, 1.3f}) {
    const Environment env(sky, rotation, 1.0f);
    for (int i = 0; i < 200; ++i) {
      const V3f n = V3f(g(rng), g(rng), g(rng)).normalized();
      const double exact = kPiD * (1.0 + n.y) / 2;
      EXPECT_NEAR(env.irradiance(n).x, exact, 2e-6) << n;
      worst_hemisphere = std::max(worst_hemisphere, std::fabs(env.irradiance(n).x - exact));
    }
  }
  // The default sky: linear in y, L = m + b y with m = (zenith + nadir) / 2 and
  // b = (zenith - nadir) / 2, whose irradiance is pi m + (2 pi / 3) b n_y. Its rows keep each
  // row's mean, so the constant part is exact and the linear part differs by b times the
  // variance of y within the rows: at most b (1/2) 4 pi (pi / 256)^2 / 12 = 7.9e-5 b.
  const float zenith = 0.15f, nadir = 0.05f, m = 0.1f, b = 0.05f;
  const Environment default_sky = gradient_sky(zenith, nadir);
  for (int i = 0; i < 200; ++i) {
    const V3f n = V3f(g(rng), g(rng), g(rng)).normalized();
    const double exact = kPiD * m + 2 * kPiD / 3 * b * n.y;
    EXPECT_NEAR(default_sky.irradiance(n).x, exact, 7.9e-5 * b + 1e-6) << n;
    worst_sky = std::max(worst_sky, std::fabs(default_sky.irradiance(n).x - exact));
  }
  std::printf("environment irradiance: hemisphere worst %.3g of pi, default sky worst %.3g\n",
              worst_hemisphere / kPiD, worst_sky);
  EXPECT_NEAR(default_sky.radiance(V3f(0, 1, 0)).x, zenith, 1e-3f);
  EXPECT_NEAR(default_sky.radiance(V3f(0, -1, 0)).x, nadir, 1e-3f);
}

TEST(Environment, RefusesTexelsThatAreNotRadiances) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(), -0.5f};
  for (float v : bad) {
    Image map = constant_map(8, 4, 1.0f);
    map.pixel(5, 2)[1] = v;
    try {
      Environment env(map, 0.0f, 1.0f);
      ADD_FAILURE() << "accepted " << v;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("texel (5, 2)"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("green"), std::string::npos) << e.what();
    }
  }
  // Finite texels that the intensity makes infinite.
  EXPECT_THROW(Environment(constant_map(8, 4, 3e38f), 0.0f, 10.0f), std::invalid_argument);
  EXPECT_THROW(Environment(Image(), 0.0f, 1.0f), std::invalid_argument);
}

// --- The session: environment files, the fingerprint, the ambient term ---

const std::string kSpheres = std::string(PRISM_SOURCE_DIR) + "/scenes/spheres.gltf";

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("prism_env_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

void write_map(const std::string& path, const Image& map) {
  write_exr_file(path, map, ExrHeader{}, ExrWriteOptions{});
}

// The one-line RequestError a job with environment `path` gets from the session.
std::string environment_error(const std::string& path, double memory_gib = 8.0) {
  SceneRequest request;
  request.path = kSpheres;
  SessionOptions options;
  options.memory_budget_bytes = uint64_t(memory_gib * double(uint64_t{1} << 30));
  Session session(request, options);
  RenderJob job;
  job.environment.path = path;
  job.width = 16;
  job.height = 12;
  try {
    session.check(job);
  } catch (const RequestError& e) {
    EXPECT_EQ(e.field, "environment");
    return e.what();
  }
  return "";
}

TEST(EnvironmentFiles, HostileFilesAreRefusedInOneLine) {
  TempDir dir;
  const std::string missing = dir.file("missing.exr");
  const std::string text = dir.file("notes.hdr");
  std::ofstream(text) << "not an image\n";
  const std::string png = dir.file("map.exr.png");
  std::ofstream(png, std::ios::binary) << "\x89PNG\r\n\x1a\n";
  const std::string nan = dir.file("nan.exr");
  Image map = constant_map(16, 8, 1.0f);
  map.pixel(3, 4)[0] = std::numeric_limits<float>::quiet_NaN();
  write_map(nan, map);
  const std::string negative = dir.file("negative.exr");
  map = constant_map(16, 8, 1.0f);
  map.pixel(9, 1)[2] = -1.0f;
  write_map(negative, map);
  const std::string big = dir.file("big.exr");
  write_map(big, constant_map(512, 256, 1.0f));
  const std::string truncated = dir.file("truncated.exr");
  {
    std::ifstream in(big, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const struct {
    std::string path, expected;
    double memory_gib;
  } cases[] = {
      {missing, "no such file", 8.0},
      {dir.path.string(), "not a regular file", 8.0},
      {text, "not an environment map", 8.0},
      {png, "not an environment map", 8.0},
      {nan, "texel (3, 4) has a non-finite red value", 8.0},
      {negative, "texel (9, 1) has a negative blue value", 8.0},
      // 512 x 256 texels at 44 bytes each is 5.8 MB, over a budget of 4 MiB.
      {big, "larger than Prism reads here", 4.0 / 1024},
      {truncated, "", 8.0},
  };
  for (const auto& c : cases) {
    const std::string message = environment_error(c.path, c.memory_gib);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(c.path, 0), 0u) << "names the file first: " << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
  // The same map within the budget is accepted.
  EXPECT_EQ(environment_error(big), "");
}

TEST(EnvironmentFiles, RadianceHdrIsReadThroughOpenImageIO) {
  TempDir dir;
  const std::string hdr = dir.file("sky.hdr");
  {
    std::vector<float> rgb(8 * 4 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.25f * float(1 + (i / 3) % 5);
    auto out = OIIO::ImageOutput::create(hdr);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(hdr, OIIO::ImageSpec(8, 4, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()));
    out->close();
  }
  SceneRequest request;
  request.path = kSpheres;
  Session session(request, SessionOptions{});
  RenderJob job;
  job.environment.path = hdr;
  const Environment& env = session.environment(job);
  ASSERT_FALSE(env.black());
  // Texel (2, 1) is pixel 10: 0.25 * (1 + 10 % 5); RGBE keeps 8 bits of mantissa.
  EXPECT_NEAR(env.radiance(map_direction(2.5 / 8, 1.5 / 4)).x, 0.25f, 0.25f / 128);
}

TEST(EnvironmentFiles, FingerprintHoldsTheMapsContents) {
  TempDir dir;
  const std::string path = dir.file("sky.exr");
  write_map(path, constant_map(8, 4, 1.0f));
  SceneRequest scene;
  scene.path = kSpheres;
  RenderJob job;
  job.environment.path = path;
  const std::string before = canonical_settings(scene, job, ExrPixelType::float32);
  write_map(path, constant_map(8, 4, 2.0f));
  const std::string after = canonical_settings(scene, job, ExrPixelType::float32);
  EXPECT_NE(before, after);
  job.environment.rotation_degrees = 10.0f;
  EXPECT_NE(canonical_settings(scene, job, ExrPixelType::float32), after);
  job.environment.rotation_degrees = 0.0f;
  EXPECT_EQ(canonical_settings(scene, job, ExrPixelType::float32), after);
  job.environment.hidden = true;
  EXPECT_NE(canonical_settings(scene, job, ExrPixelType::float32), after);
}

// Renders spheres.gltf with `integrator` and the job's environment.
Image render_spheres(const std::string& integrator, const RenderJob& base) {
  SceneRequest request;
  request.path = kSpheres;
  SessionOptions options;
  options.threads = 2;
  Session session(request, options);
  RenderJob job = base;
  job.integrator = integrator;
  job.width = 64;
  job.height = 48;
  job.film.spp = 1;
  return session.render(job).image;
}

// Under a uniform environment L, E(N) / pi is L for every normal, so the environment adds to
// the ambient term exactly what --ambient L adds; a hidden environment leaves the backdrop
// black (alpha 0) and the lighting as it was.
TEST(EnvironmentAmbient, UniformEnvironmentIsTheAmbientTerm) {
  for (const char* integrator : {"phong", "shadow", "whitted"}) {
    RenderJob environment;
    environment.background = V3f(0.4f);
    environment.environment.hidden = true;
    RenderJob ambient;
    ambient.integrator_parameters["ambient"] = 0.4;
    const Image a = render_spheres(integrator, environment);
    const Image b = render_spheres(integrator, ambient);
    ASSERT_EQ(a.rgba.size(), b.rgba.size());
    int lit = 0;
    for (size_t i = 0; i < a.rgba.size(); i += 4) {
      EXPECT_EQ(a.rgba[i + 3], b.rgba[i + 3]);
      if (a.rgba[i + 3] == 0.0f) {
        EXPECT_EQ(a.rgba[i], 0.0f);  // hidden: the camera sees black
        continue;
      }
      // whitted's mirrors see the environment itself where --ambient sees nothing.
      if (std::string(integrator) == "whitted") continue;
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(a.rgba[i + k], b.rgba[i + k], 1e-6f * (1 + b.rgba[i + k]));
      ++lit;
    }
    if (std::string(integrator) != "whitted") {
      EXPECT_GT(lit, 100);
    }
  }
}

// --- Default lighting ---

const std::string kBoxTextured =
    std::string(PRISM_ASSIMP_GLTF2_DIR) + "/BoxTextured-glTF/BoxTextured.gltf";

TEST(DefaultLighting, KeyLightReachesEveryFaceTheDefaultCameraSees) {
  SceneRequest request;
  request.path = kBoxTextured;
  Session session(request, SessionOptions{});
  const SceneDescription& scene = session.scene();
  ASSERT_EQ(scene.lights.size(), 1u);
  ASSERT_TRUE(scene.default_lighting);
  const M44d& m = scene.cameras.at(0).camera_to_world;
  const V3d eye(m[3][0], m[3][1], m[3][2]);
  const Imath::Box3d box = world_bounds(scene);
  const V3d to_light = -scene.lights[0].direction;
  int seen = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      V3d n(0.0), centre = box.center();
      n[axis] = sign;
      centre[axis] = sign > 0 ? box.max[axis] : box.min[axis];
      if ((eye - centre).dot(n) <= 0.0) continue;  // the camera does not see this face
      ++seen;
      EXPECT_GT(n.dot(to_light), 0.2) << "face " << axis << " " << sign;
    }
  EXPECT_EQ(seen, 3);
  EXPECT_NE(scene.warnings.back().find("key light of pi lux from over the camera's right "
                                       "shoulder and a grey sky of radiance 0.15 at the zenith "
                                       "to 0.05 at the nadir, not seen by the camera"),
            std::string::npos)
      << scene.warnings.back();
}

TEST(DefaultLighting, NoPixelOfBoxTexturedIsBlack) {
  SceneRequest request;
  request.path = kBoxTextured;
  SessionOptions options;
  options.threads = 2;
  Session session(request, options);
  for (const char* integrator : {"phong", "shadow", "whitted"}) {
    RenderJob job;
    job.integrator = integrator;
    job.width = 80;
    job.height = 60;
    job.film.spp = 1;
    const Image image = session.render(job).image;
    int covered = 0;
    float darkest = 1e30f;
    for (size_t i = 0; i < image.rgba.size(); i += 4) {
      if (image.rgba[i + 3] == 0.0f) {
        // The default sky is not the backdrop.
        EXPECT_EQ(image.rgba[i] + image.rgba[i + 1] + image.rgba[i + 2], 0.0f);
        continue;
      }
      ++covered;
      darkest = std::min(darkest, image.rgba[i] + image.rgba[i + 1] + image.rgba[i + 2]);
    }
    EXPECT_GT(covered, 500) << integrator;
    EXPECT_GT(darkest, 0.0f) << integrator;
  }
}

SceneDescription emissive_panel_scene(C3f emissive) {
  SceneDescription scene;
  MaterialDescription panel;
  panel.emissive = emissive;
  scene.materials.push_back(panel);
  Primitive p;
  p.positions = {V3f(-1, 1, -1), V3f(1, 1, -1), V3f(0, 1, 1)};
  p.indices = {0, 1, 2};
  p.material = 0;
  Mesh mesh;
  mesh.primitives.push_back(p);
  scene.meshes.push_back(mesh);
  scene.instances.push_back(MeshInstance{0, M44d(), "panel"});
  return scene;
}

TEST(DefaultLighting, EmissiveGeometryIsLight) {
  SceneDescription lit = emissive_panel_scene(C3f(0.0f, 2.0f, 0.0f));
  add_scene_defaults(&lit);
  EXPECT_TRUE(lit.lights.empty());
  EXPECT_FALSE(lit.default_lighting);
  EXPECT_FALSE(lit.default_sky);
  EXPECT_EQ(lit.cameras.size(), 1u);  // a camera is still added
  // A black emissive factor emits nothing: the defaults are added.
  SceneDescription dark = emissive_panel_scene(C3f(0.0f));
  add_scene_defaults(&dark);
  EXPECT_EQ(dark.lights.size(), 1u);
  EXPECT_TRUE(dark.default_sky);
  // An emissive sphere counts too.
  SceneDescription sphere;
  MaterialDescription glow;
  glow.emissive = C3f(1.0f);
  sphere.materials.push_back(glow);
  sphere.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "glow"});
  add_scene_defaults(&sphere);
  EXPECT_TRUE(sphere.lights.empty());
}

}  // namespace
}  // namespace prism
