// Area lights (renderer/shading/area_lights.h) and the choice among every light
// (renderer/shading/emitter_sampler.h): sample() draws directions with the density pdf()
// reports (a chi-square test over the sphere of directions, as for the BSDFs), the density
// integrates to 1 over the light's solid angle, and lights are chosen in proportion to power.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "renderer/image/colour.h"
#include "renderer/shading/area_lights.h"
#include "renderer/shading/emitter_sampler.h"
#include "tests/chi_square.h"

namespace prism {
namespace {

constexpr double kPiD = std::numbers::pi;

struct ChiSquare {
  double p_value = 0.0;
  double pdf_integral = 0.0;  // pdf() over the sphere of directions
};

// Histograms the light's sampled directions from `point` over a (cos theta, phi) grid and
// compares it with pdf() integrated over each cell, pooling cells expecting fewer than 5.
ChiSquare chi_square(const AreaLight& light, const V3f& point, int samples) {
  constexpr int kTheta = 80, kPhi = 160, kSub = 16;
  const testing::DirectionGrid grid{kTheta, kPhi};
  std::vector<double> observed(grid.cells(), 0.0), expected(grid.cells(), 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < samples; ++i) {
    LightSample s;
    if (!light.sample(point, Imath::V2f(u01(rng), u01(rng)), &s)) continue;
    observed[grid.cell_of(s.wi)] += 1.0;
  }
  ChiSquare result;
  const double cell = grid.cell_solid_angle();
  // The midpoint rule over a cell: 16 x 16 points, or 128 x 128 where the light's edge
  // crosses the cell (some points see it, some do not), whose coarse estimate would be off by
  // far more than the test's noise.
  const auto cell_mass = [&](int t, int p, int sub) {
    double integral = 0.0;
    bool some = false, all = true;
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const double value = light.pdf(point, grid.point(t, p, a, b, sub));
        integral += value;
        if (value > 0.0)
          some = true;
        else
          all = false;
      }
    return std::pair(integral / (sub * sub), some && !all);
  };
  for (int t = 0; t < kTheta; ++t)
    for (int p = 0; p < kPhi; ++p) {
      auto [mean, edge] = cell_mass(t, p, kSub);
      if (edge) mean = cell_mass(t, p, 8 * kSub).first;
      const double mass = mean * cell;
      result.pdf_integral += mass;
      expected[size_t(t * kPhi + p)] = mass * samples;
    }
  result.p_value = testing::chi_square(observed, expected).p_value;
  return result;
}

Material emitting(float radiance) {
  Material m;
  m.emissive = V3f(radiance);
  return m;
}

EmissivePrimitive triangle(const V3f& a, const V3f& b, const V3f& c) {
  EmissivePrimitive e;
  e.corners[0] = a;
  e.corners[1] = b;
  e.corners[2] = c;
  return e;
}

EmissivePrimitive sphere(const V3f& centre, float radius) {
  EmissivePrimitive e;
  e.shape = EmissivePrimitive::Shape::sphere;
  e.corners[0] = centre;
  e.radius = radius;
  return e;
}

TEST(AreaLights, TriangleSamplingMatchesPdfChiSquare) {
  const Material m = emitting(1.0f);
  const AreaLight light(
      triangle(V3f(-1.0f, -0.5f, 1.0f), V3f(1.5f, -0.2f, 1.2f), V3f(0.2f, 1.3f, 0.6f)), m);
  for (const V3f& point : {V3f(0.0f), V3f(0.3f, -0.4f, 2.5f), V3f(0.2f, 0.3f, -1.5f)}) {
    const ChiSquare c = chi_square(light, point, 1000000);
    std::printf("triangle from (%g, %g, %g): chi-square p = %.4f, pdf integral %.5f\n", point.x,
                point.y, point.z, c.p_value, c.pdf_integral);
    EXPECT_GT(c.p_value, 1e-3);
    EXPECT_NEAR(c.pdf_integral, 1.0, 0.01);
  }
}

TEST(AreaLights, SphereSamplingMatchesPdfChiSquare) {
  const Material m = emitting(1.0f);
  // Outside (the cone, wide and narrow, where the small-angle form takes over) and inside.
  struct Case {
    V3f centre;
    float radius;
  };
  for (const Case& k : {Case{V3f(0.0f, 0.0f, 2.0f), 1.0f}, Case{V3f(1.0f, 0.5f, -1.5f), 1.7f},
                        Case{V3f(0.0f, 0.0f, 1.0f), 2.0f}}) {
    const AreaLight light(sphere(k.centre, k.radius), m);
    const ChiSquare c = chi_square(light, V3f(0.0f), 1000000);
    std::printf("sphere r %g at distance %g: chi-square p = %.4f, pdf integral %.5f\n", k.radius,
                k.centre.length(), c.p_value, c.pdf_integral);
    EXPECT_GT(c.p_value, 1e-3);
    EXPECT_NEAR(c.pdf_integral, 1.0, 0.01);
  }
  // A sphere subtending less than 1.5 degrees: the density is the cone's, 1 / (2 pi (1 - cos)).
  const AreaLight small(sphere(V3f(0.0f, 0.0f, 100.0f), 1.0f), m);
  LightSample s;
  ASSERT_TRUE(small.sample(V3f(0.0f), Imath::V2f(0.3f, 0.6f), &s));
  const double cone = 2.0 * kPiD * (1.0 - std::sqrt(1.0 - 1e-4));
  EXPECT_NEAR(s.pdf * cone, 1.0, 1e-3);
  EXPECT_NEAR(small.pdf(V3f(0.0f), s.wi) * cone, 1.0, 1e-3);
}

// The triangle's solid angle at `point` by Van Oosterom and Strackee's formula, in double
// from the float corners (the chi-square test checks the sampler's density without it).
double solid_angle(const V3f& point, const V3f* corners) {
  Imath::V3d d[3];
  for (int i = 0; i < 3; ++i) d[i] = (Imath::V3d(corners[i]) - Imath::V3d(point)).normalized();
  const double triple = std::fabs(d[0].dot(d[1].cross(d[2])));
  return 2.0 * std::atan2(triple, 1.0 + d[0].dot(d[1]) + d[1].dot(d[2]) + d[2].dot(d[0]));
}

// Irradiance at `point` (surface normal `n`, facing the triangle) from a triangle of uniform
// radiance L: Lambert's polygon formula, L / 2 x sum over edges of the edge's angle times the
// cosine between n and the edge's plane normal.
double lambert_irradiance(const V3f& point, const V3f& n, const V3f* corners, double radiance) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Imath::V3d a = (Imath::V3d(corners[i]) - Imath::V3d(point)).normalized();
    const Imath::V3d b = (Imath::V3d(corners[(i + 1) % 3]) - Imath::V3d(point)).normalized();
    const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
    sum += angle * a.cross(b).normalized().dot(Imath::V3d(n));
  }
  return 0.5 * radiance * std::fabs(sum);
}

// A triangle that subtends a fair solid angle is sampled uniformly within it: every sample's
// density is 1 / solid angle, and the estimator of the irradiance it gives a receiver, L cos
// theta / pdf, is then bounded by L x solid angle, so its standard deviation is at most half
// that (Popoviciu's inequality) however close the receiver is. Sampled by area, the receiver
// 0.05 below the panel would see 1 / d^2 spikes far above it. The mean is Lambert's formula.
TEST(AreaLights, CloseTriangleIsSampledUniformlyInSolidAngle) {
  constexpr float kRadiance = 3.0f;
  const Material m = emitting(kRadiance);
  const EmissivePrimitive panel =
      triangle(V3f(-1.0f, -1.0f, 1.0f), V3f(1.5f, -0.5f, 1.0f), V3f(0.0f, 1.2f, 1.0f));
  const AreaLight light(panel, m);
  const V3f n(0.0f, 0.0f, 1.0f);
  for (const V3f& point : {V3f(0.0f, 0.0f, 0.95f), V3f(0.9f, -0.8f, 0.9f), V3f(0.2f, 0.1f, 0.0f),
                           V3f(3.0f, 2.0f, 0.5f)}) {
    const double omega = solid_angle(point, panel.corners);
    const double exact = lambert_irradiance(point, n, panel.corners, kRadiance);
    constexpr int kSamples = 200000;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    double sum = 0.0, sum2 = 0.0, worst_density = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      LightSample s;
      ASSERT_TRUE(light.sample(point, Imath::V2f(u01(rng), u01(rng)), &s));
      worst_density = std::max(worst_density, std::fabs(s.pdf * omega - 1.0));
      EXPECT_NEAR(light.pdf(point, s.wi) * omega, 1.0, 1e-4);
      const double value = s.radiance.x * std::max(0.0f, dot(n, s.wi)) / s.pdf;
      sum += value;
      sum2 += value * value;
    }
    const double mean = sum / kSamples;
    const double sd = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean));
    std::printf(
        "panel from (%g, %g, %g): solid angle %.5f sr, density x solid angle off by %.2e; "
        "irradiance %.6f +- %.6f (Lambert %.6f), sd %.4f <= %.4f\n",
        point.x, point.y, point.z, omega, worst_density, mean, sd / std::sqrt(kSamples), exact, sd,
        0.5 * kRadiance * omega);
    EXPECT_LT(worst_density, 1e-4);
    EXPECT_NEAR(mean, exact, 4.0 * sd / std::sqrt(kSamples) + 1e-6 * exact);
    EXPECT_LE(sd, 0.5 * kRadiance * omega * (1.0 + 1e-6));
  }
}

// A small triangle far away (compared with its edges) is sampled by area: the density is
// d^2 / (A cos), and the irradiance estimate agrees with Lambert's formula. (It subtends less
// than one cell of the chi-square grid, so that test cannot see it.)
TEST(AreaLights, FarTriangleIsSampledByArea) {
  const Material m = emitting(1.0f);
  const EmissivePrimitive small =
      triangle(V3f(0.0f, 0.0f, 20.0f), V3f(0.3f, 0.0f, 20.0f), V3f(0.0f, 0.3f, 20.0f));
  const AreaLight light(small, m);
  const V3f point(0.1f, 0.05f, 0.0f), n(0.0f, 0.0f, 1.0f);
  ASSERT_LT(solid_angle(point, small.corners), 1e-3);
  constexpr int kSamples = 100000;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    LightSample s;
    ASSERT_TRUE(light.sample(point, Imath::V2f(u01(rng), u01(rng)), &s));
    const double area_density = double(s.distance) * s.distance / (light.area() * s.wi.z);
    EXPECT_NEAR(s.pdf / area_density, 1.0, 1e-5);
    const double value = s.radiance.x * std::max(0.0f, dot(n, s.wi)) / s.pdf;
    sum += value;
    sum2 += value * value;
  }
  const double mean = sum / kSamples;
  const double se = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
  const double exact = lambert_irradiance(point, n, small.corners, 1.0);
  std::printf("small far triangle: irradiance %.8f +- %.8f (Lambert %.8f)\n", mean, se, exact);
  EXPECT_NEAR(mean, exact, 4.0 * se + 1e-5 * exact);
}

TEST(AreaLights, PowerIsPiAreaRadiance) {
  const Material m = emitting(2.0f);
  const AreaLight t(triangle(V3f(0.0f), V3f(2.0f, 0.0f, 0.0f), V3f(0.0f, 1.0f, 0.0f)), m);
  EXPECT_FLOAT_EQ(t.area(), 1.0f);
  EXPECT_NEAR(t.power().x, 2.0 * kPiD * 1.0 * 2.0, 1e-4);  // both faces
  const AreaLight s(sphere(V3f(0.0f), 0.5f), m);
  EXPECT_NEAR(s.power().x, kPiD * (4.0 * kPiD * 0.25) * 2.0, 1e-4);
}

// One table over punctual, area and environment lights: each chosen with probability power /
// total, checked exactly through pmf and empirically over stratified u.
TEST(EmitterSampler, ChoosesEveryKindInProportionToPower) {
  const Material bright = emitting(3.0f), dim = emitting(0.5f);
  std::vector<AreaLight> area;
  area.emplace_back(triangle(V3f(0.0f), V3f(1.0f, 0.0f, 0.0f), V3f(0.0f, 1.0f, 0.0f)), bright);
  area.emplace_back(triangle(V3f(0.0f), V3f(3.0f, 0.0f, 0.0f), V3f(0.0f, 1.0f, 0.0f)), dim);
  area.emplace_back(sphere(V3f(0.0f), 0.2f), bright);
  std::vector<LightSource> punctual;
  Light point;
  point.intensity = 2.0f;
  punctual.emplace_back(point, ColourPipeline(WorkingSpace::linear_rec709));
  const Environment environment(V3f(0.01f));
  const float radius = 2.0f;
  const EmitterSampler sampler(punctual, area, environment, radius);
  std::vector<double> power = {punctual[0].power(radius).x};
  for (const AreaLight& a : area) power.push_back(a.power().x);
  power.push_back(environment.power(radius).x);
  double total = 0.0;
  for (double p : power) total += p;
  constexpr int kDraws = 1 << 20;
  std::vector<double> drawn(power.size(), 0.0);
  for (int i = 0; i < kDraws; ++i) {
    ChosenEmitter c;
    ASSERT_TRUE(sampler.sample((i + 0.5f) / kDraws, V3f(0.0f, 0.0f, 1.0f), &c));
    const size_t slot = c.kind == EmitterKind::punctual ? 0
                        : c.kind == EmitterKind::area   ? 1 + c.index
                                                        : power.size() - 1;
    drawn[slot] += 1.0;
  }
  const V3f at(0.0f, 0.0f, 1.0f);
  EXPECT_FALSE(sampler.splits_near());  // a sphere among the area lights
  const float pmfs[] = {0.0f, sampler.pmf_area(0, at), sampler.pmf_area(1, at),
                        sampler.pmf_area(2, at), sampler.pmf_environment()};
  for (size_t i = 0; i < power.size(); ++i) {
    std::printf("light %zu: power share %.5f, drawn %.5f, pmf %.5f\n", i, power[i] / total,
                drawn[i] / kDraws, i == 0 ? power[0] / total : pmfs[i]);
    EXPECT_NEAR(drawn[i] / kDraws, power[i] / total, 2.0 / kDraws + 1e-6);
    if (i > 0) {
      EXPECT_NEAR(pmfs[i], power[i] / total, 1e-6);
    }
  }
  // A black environment is never chosen.
  const EmitterSampler dark(punctual, area, Environment(), radius);
  EXPECT_EQ(dark.pmf_environment(), 0.0f);
}

// A panel of two triangles (a unit square split along its diagonal) is few enough lights for
// the choice to be split near each point: from a point close beside one half that half is
// chosen more often, in exactly the proportion pmf_area reports, and the two probabilities add
// up to the area lights' share whatever the point.
TEST(EmitterSampler, SplitsAFewTrianglesBySolidAngleNearThePoint) {
  const Material white = emitting(1.0f);
  std::vector<AreaLight> area;
  area.emplace_back(triangle(V3f(0.0f), V3f(1.0f, 0.0f, 0.0f), V3f(1.0f, 1.0f, 0.0f)), white);
  area.emplace_back(triangle(V3f(0.0f), V3f(1.0f, 1.0f, 0.0f), V3f(0.0f, 1.0f, 0.0f)), white);
  std::vector<LightSource> punctual;
  Light point;
  point.intensity = 1.0f;
  punctual.emplace_back(point, ColourPipeline(WorkingSpace::linear_rec709));
  const EmitterSampler sampler(punctual, area, Environment(), 2.0f);
  ASSERT_TRUE(sampler.splits_near());
  // The area lights' share of the choice is by power, as without the split.
  const double panel = area[0].power().x + area[1].power().x;
  const double area_share = panel / (panel + punctual[0].power(2.0f).x);
  // Beside the first half, a tenth of the square's side below it: it subtends far more.
  const V3f beside(0.9f, 0.1f, -0.1f);
  const float p0 = sampler.pmf_area(0, beside), p1 = sampler.pmf_area(1, beside);
  std::printf("beside the first half: pmf %.5f and %.5f, sum %.6f (share %.6f)\n", p0, p1, p0 + p1,
              area_share);
  EXPECT_GT(p0, 3.0f * p1);
  EXPECT_NEAR(p0 + p1, area_share, 1e-6);
  // Above the centre both halves subtend the same angle.
  const V3f above(0.5f, 0.5f, -0.5f);
  EXPECT_NEAR(sampler.pmf_area(0, above), sampler.pmf_area(1, above), 1e-6);
  EXPECT_NEAR(sampler.pmf_area(0, above) + sampler.pmf_area(1, above), area_share, 1e-6);

  constexpr int kDraws = 1 << 18;
  int drawn[2] = {0, 0};
  for (int i = 0; i < kDraws; ++i) {
    ChosenEmitter c;
    ASSERT_TRUE(sampler.sample((i + 0.5f) / kDraws, beside, &c));
    if (c.kind != EmitterKind::area) continue;
    ASSERT_LT(c.index, 2u);
    ++drawn[c.index];
    EXPECT_TRUE(c.has_view);
    EXPECT_FLOAT_EQ(c.pmf, c.index == 0 ? p0 : p1);
  }
  std::printf("drawn %.5f and %.5f of the draws\n", double(drawn[0]) / kDraws,
              double(drawn[1]) / kDraws);
  EXPECT_NEAR(double(drawn[0]) / kDraws, p0, 4.0 / kDraws);
  EXPECT_NEAR(double(drawn[1]) / kDraws, p1, 4.0 / kDraws);
  // The chosen half's sample, from the view the choice formed, is the one of its own.
  LightSample with_view, without;
  const Imath::V2f u(0.3f, 0.7f);
  ASSERT_TRUE(area[0].sample(beside, area[0].view_from(beside), u, &with_view));
  ASSERT_TRUE(area[0].sample(beside, u, &without));
  EXPECT_EQ(with_view.wi, without.wi);
  EXPECT_EQ(with_view.pdf, without.pdf);
}

}  // namespace
}  // namespace prism
