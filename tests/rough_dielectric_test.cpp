// The rough dielectric of the path tracer (renderer/shading/rough_dielectric.h, through
// Bsdf::path_traced), tested as pbrt-v4's bsdfs_test tests its BxDFs: sample() against pdf()
// by a chi-square test over the whole sphere of directions (reflection and transmission),
// pdf() integrating to the share of samples that succeed, the albedo of a white dielectric,
// and the generalized reciprocity of the BTDF. And KHR_materials_volume under `path`: a
// sphere of index 1 in front of a uniform environment shows exp(-sigma_a chord) per channel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "renderer/shading/bsdf.h"
#include "renderer/shading/material.h"
#include "renderer/shading/rough_dielectric.h"
#include "tests/chi_square.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

// Clear glass of roughness^2 = alpha (metallic 0, transmission 1, white): the layer's GGX lobe
// covers only the opaque part, here nothing, so the BSDF is the rough dielectric alone.
BsdfLobes glass_lobes(float alpha, float ior = 1.5f, bool thin_walled = false) {
  BsdfLobes lobes;
  lobes.dielectric_f0 = V3f(dielectric_f0(ior));
  lobes.dielectric_f90 = 1.0f;
  lobes.specular_f0 = lobes.dielectric_f0;
  lobes.specular_f90 = V3f(1.0f);
  lobes.alpha = alpha;
  lobes.mirror = alpha < 0.01f;
  lobes.transmission = 1.0f;
  lobes.ior = ior;
  lobes.thin_walled = thin_walled;
  return lobes;
}

V3f view(float cos_theta) {
  return testing::DirectionGrid::direction(cos_theta, 0.3);
}

struct Histogram {
  double p_value = 0.0;
  double pdf_integral = 0.0;  // of pdf() over the sphere
  double accepted = 0.0;      // share of sample() calls that returned a direction
  double transmitted = 0.0;   // share of those below the surface
};

// sample() histogrammed on a (cos theta, phi) grid of the whole sphere against pdf()
// integrated over each cell by the midpoint rule on `sub` x `sub` points (the pdf of `claimed`
// instead, when given, to show that the test rejects a wrong density).
Histogram histogram(const Bsdf& bsdf, const V3f& wo, int samples, int sub,
                    const Bsdf* claimed = nullptr) {
  const Bsdf& density = claimed ? *claimed : bsdf;
  constexpr int kTheta = 20, kPhi = 40;
  const testing::DirectionGrid grid{kTheta, kPhi};
  std::vector<double> observed(grid.cells(), 0.0), expected(grid.cells(), 0.0);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  Histogram h;
  for (int i = 0; i < samples; ++i) {
    BsdfSample s;
    if (!bsdf.sample(wo, u01(rng), Imath::V2f(u01(rng), u01(rng)), false, &s)) continue;
    EXPECT_FALSE(s.specular());
    EXPECT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-4f * s.pdf);
    observed[grid.cell_of(s.wi)] += 1.0;
    h.accepted += 1.0;
    if (s.wi.z < 0.0f) h.transmitted += 1.0;
  }
  for (int t = 0; t < kTheta; ++t)
    for (int p = 0; p < kPhi; ++p) {
      double integral = 0.0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) integral += density.pdf(wo, grid.point(t, p, a, b, sub));
      const double cell = integral / (sub * sub) * grid.cell_solid_angle();
      h.pdf_integral += cell;
      expected[size_t(t * kPhi + p)] = cell * samples;
    }
  h.transmitted /= std::max(1.0, h.accepted);
  h.accepted /= samples;
  h.p_value = claimed ? testing::chi_square(observed, expected).p_value
                      : testing::chi_square_test(observed, expected);
  return h;
}

// Every roughness from nearly smooth to 1, entering (eta 1.5) and leaving (1/1.5, where total
// internal reflection takes most grazing light), near-normal to grazing. The narrowest lobes get
// a finer quadrature (their peak is a few sub-cells wide otherwise). Nearer the pole than
// cos 0.9 the equal-area grid's cells are too wide in angle for the midpoint rule to
// integrate the alpha = 0.01 peaks (at cos 0.98: 1.32 for a density that integrates to 1).
TEST(RoughDielectric, SamplingMatchesPdfOverTheSphere) {
  for (bool inside : {false, true})
    for (float alpha : {0.01f, 0.1f, 0.3f, 0.6f, 1.0f})
      for (float cos_o : {0.9f, 0.6f, 0.2f}) {
        const Bsdf bsdf = Bsdf(V3f(0, 0, 1), glass_lobes(alpha)).path_traced(inside);
        ASSERT_EQ(bsdf.flags(), kGlossyReflection | kGlossyTransmission);
        const Histogram h = histogram(bsdf, view(cos_o), 300000,
                                      alpha < 0.05f  ? 128
                                      : alpha < 0.2f ? 48
                                                     : 24);
        SCOPED_TRACE(::testing::Message()
                     << "alpha " << alpha << " cos " << cos_o << " inside " << inside);
        std::printf(
            "rough dielectric alpha %.2f cos %.2f eta %.3f: p %.3g, pdf integral %.5f, "
            "accepted %.5f, transmitted %.4f\n",
            alpha, cos_o, inside ? 1 / 1.5 : 1.5, h.p_value, h.pdf_integral, h.accepted,
            h.transmitted);
        EXPECT_GT(h.p_value, 1e-3);
        EXPECT_LE(h.pdf_integral, 1.0 + 2e-3);
        // The density covers exactly the directions sample() returns.
        EXPECT_NEAR(h.pdf_integral, h.accepted, 5e-3);
      }
}

// The thin wall's mirrored lobe, and glass beside a diffuse base (transmission 0.5), where the
// choice among lobes is part of the density too.
TEST(RoughDielectric, ThinWalledAndMixedSamplingMatchPdf) {
  for (float alpha : {0.1f, 0.5f})
    for (float cos_o : {0.9f, 0.3f}) {
      SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " cos " << cos_o);
      const Bsdf thin = Bsdf(V3f(0, 0, 1), glass_lobes(alpha, 1.5f, true)).path_traced(true);
      const Histogram t = histogram(thin, view(cos_o), 300000, 24);
      EXPECT_GT(t.p_value, 1e-3);
      EXPECT_NEAR(t.pdf_integral, t.accepted, 5e-3);
      BsdfLobes mixed = glass_lobes(alpha);
      mixed.transmission = 0.5f;
      mixed.diffuse_albedo = V3f(0.4f);
      mixed.transmission_tint = V3f(0.8f, 0.6f, 0.4f);
      const Histogram m =
          histogram(Bsdf(V3f(0, 0, 1), mixed).path_traced(), view(cos_o), 300000, 24);
      EXPECT_GT(m.p_value, 1e-3);
      EXPECT_NEAR(m.pdf_integral, m.accepted, 5e-3);
    }
}

// Rough glass under a clearcoat and a sheen (clearcoat_sheen.h): the layers take their share
// of the choice above the surface, and below it the transmitted light is still picked within
// the base's share, so the density over the whole sphere is still what sample() draws.
TEST(RoughDielectric, CoatedAndSheenedGlassSamplingMatchesPdf) {
  for (float alpha : {0.1f, 0.5f})
    for (float cos_o : {0.9f, 0.3f}) {
      SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " cos " << cos_o);
      BsdfLobes lobes = glass_lobes(alpha);
      lobes.layers.clearcoat = 0.8f;
      lobes.layers.clearcoat_alpha = 0.09f;
      lobes.layers.sheen_colour = V3f(0.3f, 0.2f, 0.1f);
      lobes.layers.sheen_alpha = 0.25f;
      const Bsdf bsdf = Bsdf(V3f(0, 0, 1), lobes).path_traced();
      const Histogram h = histogram(bsdf, view(cos_o), 300000, alpha < 0.2f ? 48 : 24);
      EXPECT_GT(h.p_value, 1e-3);
      EXPECT_LE(h.pdf_integral, 1.0 + 2e-3);
      EXPECT_NEAR(h.pdf_integral, h.accepted, 5e-3);
      EXPECT_GT(h.transmitted, 0.2);  // the glass still passes light under the layers
    }
}

// The test has teeth: the same samples against the density of another roughness fail.
TEST(RoughDielectric, ChiSquareRejectsAnotherRoughness) {
  const Bsdf sampled = Bsdf(V3f(0, 0, 1), glass_lobes(0.3f)).path_traced();
  const Bsdf claimed = Bsdf(V3f(0, 0, 1), glass_lobes(0.33f)).path_traced();
  EXPECT_LT(histogram(sampled, view(0.7f), 300000, 24, &claimed).p_value, 1e-6);
}

// The albedo of a white, non-absorbing dielectric, E[f |cos| / pdf] over sample(), with the
// transmitted samples' radiance scaling undone (times eta^2: the flux that crosses, which is
// what must not exceed what arrived). Close to 1 where the microfacets are nearly flat; single
// scattering loses the light that meets a second microfacet, most at grazing views of rough
// glass. Returns the mean and its standard error.
std::pair<double, double> albedo(const Bsdf& bsdf, const V3f& wo, float eta, int samples) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    BsdfSample s;
    double w = 0.0;
    if (bsdf.sample(wo, u01(rng), Imath::V2f(u01(rng), u01(rng)), false, &s)) {
      w = s.f.x * std::fabs(s.wi.z) / s.pdf;
      if (s.wi.z < 0.0f) w *= double(eta) * eta;
    }
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / samples;
  return {mean, std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples)};
}

TEST(RoughDielectric, WhiteDielectricAlbedoIsAtMostOneAndNearOneWhenSmooth) {
  double worst_loss = 0.0;
  for (bool inside : {false, true})
    for (float alpha : {0.01f, 0.1f, 0.3f, 0.6f, 1.0f})
      for (float cos_o : {1.0f, 0.7f, 0.4f, 0.1f}) {
        const Bsdf bsdf = Bsdf(V3f(0, 0, 1), glass_lobes(alpha)).path_traced(inside);
        const float eta = inside ? 1.0f / 1.5f : 1.5f;
        const auto [mean, error] = albedo(bsdf, view(cos_o), eta, 200000);
        SCOPED_TRACE(::testing::Message()
                     << "alpha " << alpha << " cos " << cos_o << " inside " << inside);
        std::printf("white dielectric albedo alpha %.2f cos %.1f eta %.3f: %.5f +- %.5f\n", alpha,
                    cos_o, eta, mean, error);
        EXPECT_LE(mean, 1.0 + 4.0 * error);
        if (alpha <= 0.01f) {
          EXPECT_GT(mean, 0.99);
        }
        worst_loss = std::max(worst_loss, 1.0 - mean);
      }
  std::printf("white dielectric: largest single-scattering loss %.4f\n", worst_loss);
  // Worst from inside at alpha = 1 and normal view: 58 % lost (0.418 kept), most of it to
  // total internal reflection off one microfacet into another (docs/accuracy.md).
  EXPECT_LT(worst_loss, 0.6);
}

// Veach's generalized reciprocity for refraction in radiance units, f(wo, wi) / eta_o^2 =
// f(wi, wo) / eta_i^2 (eta_o, eta_i: the indices on wo's and wi's sides); the reversed pair is
// evaluated from wi's side, the frame turned over and eta inverted. Reflection is reciprocal.
TEST(RoughDielectric, GeneralizedReciprocity) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const auto flip = [](const V3f& w) { return V3f(w.x, w.y, -w.z); };
  int transmissions = 0;
  for (float alpha : {0.05f, 0.3f, 0.8f})
    for (float eta : {1.5f, 1.0f / 1.5f, 2.4f}) {
      const RoughDielectric forward{alpha, eta, false};
      const RoughDielectric backward{alpha, 1.0f / eta, false};
      for (int i = 0; i < 2000; ++i) {
        const V3f wo = testing::DirectionGrid::direction(0.05 + 0.95 * u01(rng), 6.283 * u01(rng));
        const V3f wi = testing::DirectionGrid::direction(-1.0 + 2.0 * u01(rng), 6.283 * u01(rng));
        const float f = forward.eval(wo, wi);
        if (wi.z > 0.0f) {
          EXPECT_NEAR(f, forward.eval(wi, wo), 1e-5f * std::max(1.0f, f));
          continue;
        }
        const float back = backward.eval(flip(wi), flip(wo));
        if (f == 0.0f && back == 0.0f) continue;
        ++transmissions;
        // Index on wo's side 1, on wi's side eta.
        EXPECT_NEAR(f, back / (eta * eta), 2e-4f * std::max(1.0f, f))
            << "alpha " << alpha << " eta " << eta;
      }
    }
  EXPECT_GT(transmissions, 2000);
}

// The smooth limit is today's delta dielectric: below kMinGgxAlpha the path tracer's BSDF keeps
// the delta lobes, and at ior 1 (nothing bends) so does a rough one.
TEST(RoughDielectric, SmoothAndIndexOneStayDelta) {
  for (const BsdfLobes& lobes : {glass_lobes(0.0f), glass_lobes(0.25f, 1.0f)}) {
    const uint8_t flags = Bsdf(V3f(0, 0, 1), lobes).path_traced().flags();
    EXPECT_TRUE(flags & kSpecularTransmission);
    EXPECT_FALSE(flags & kGlossyTransmission);
  }
  // A thin wall of index 1 is the mirrored GGX lobe, not a delta: nothing degenerates.
  EXPECT_EQ(Bsdf(V3f(0, 0, 1), glass_lobes(0.25f, 1.0f, true)).path_traced().flags(),
            kGlossyReflection | kGlossyTransmission);
}

// A unit sphere of `material` at the origin, seen head-on by an orthographic camera 2.4 high,
// in front of a uniform environment of 1.
SceneDescription sphere_scene(const MaterialDescription& material) {
  SceneDescription scene;
  scene.materials.push_back(material);
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, material.name});
  scene.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.2));
  return scene;
}

// A sphere of radius 1, index 1 (no refraction, no reflection) with KHR_materials_volume in
// front of a uniform environment of 1: a camera ray through the pixel at distance r from the
// centre travels the chord 2 sqrt(1 - r^2) inside, and arrives with exp(-sigma_a chord) =
// colour^(chord / distance) per channel.
TEST(RoughDielectric, VolumeAbsorptionIsBeerLambertAlongTheChord) {
  for (float roughness : {0.0f, 0.5f}) {
    MaterialDescription glass;
    glass.name = "volume";
    glass.metallic = 0.0f;
    glass.roughness = roughness;
    glass.transmission = 1.0f;
    glass.ior = 1.0f;
    glass.thickness = 1.0f;
    glass.attenuation_distance = 0.8f;
    glass.attenuation_colour = C3f(0.5f, 0.25f, 0.9f);
    const SceneDescription scene = sphere_scene(glass);
    testing::TestSettings settings;
    settings.width = settings.height = 41;
    settings.background = V3f(1.0f);
    const auto r = testing::render_scene(scene, "path", settings);
    double worst = 0.0;
    int inside = 0;
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x) {
        // Pixel centres of the 2.4 x 2.4 view.
        const double px = (x + 0.5) / settings.width * 2.4 - 1.2;
        const double py = 1.2 - (y + 0.5) / settings.height * 2.4;
        const double r2 = px * px + py * py;
        const double chord = r2 < 1.0 ? 2.0 * std::sqrt(1.0 - r2) : 0.0;
        if (r2 > 0.98 && r2 < 1.02) continue;  // the rim, where the chord is steepest
        if (chord > 0.0) ++inside;
        const float* pixel = r.image.pixel(x, y);
        for (int c = 0; c < 3; ++c) {
          const double expected = std::pow(double(glass.attenuation_colour[c]), chord / 0.8);
          worst = std::max(worst, std::fabs(pixel[c] - expected));
        }
      }
    std::printf("volume sphere roughness %.1f: %d pixels inside, worst |L - exp(-sigma d)| %.3g\n",
                roughness, inside, worst);
    EXPECT_GT(inside, 800);
    // The exit point is found from an origin moved off the surface by up to 256 ulps of its
    // coordinates (offset_ray_origin), a few 1e-5 of the chord.
    EXPECT_LT(worst, 2e-4);
  }
}

// Rough glass with a volume that absorbs nothing, in a white furnace: the path tracer's image
// of it never exceeds 1 and loses only what single scattering loses.
TEST(RoughDielectric, RoughGlassSphereInAWhiteFurnace) {
  MaterialDescription glass;
  glass.name = "glass";
  glass.metallic = 0.0f;
  glass.roughness = 0.3f;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  glass.thickness = 1.0f;
  const SceneDescription scene = sphere_scene(glass);
  testing::TestSettings settings;
  settings.width = settings.height = 24;
  settings.spp = 64;
  settings.max_depth = 64;
  settings.background = V3f(1.0f);
  const auto r = testing::render_scene(scene, "path", settings);
  double sum = 0.0, high = 0.0;
  int n = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const double px = (x + 0.5) / settings.width * 2.4 - 1.2;
      const double py = 1.2 - (y + 0.5) / settings.height * 2.4;
      if (px * px + py * py > 0.8) continue;
      sum += r.image.pixel(x, y)[0];
      high = std::max(high, double(r.image.pixel(x, y)[0]));
      ++n;
    }
  const double mean = sum / n;
  std::printf(
      "rough glass sphere (r 0.3, ior 1.5) in a white furnace: mean %.4f over %d pixels, "
      "brightest %.4f\n",
      mean, n, high);
  EXPECT_LE(mean, 1.0 + 5e-3);
  EXPECT_GT(mean, 0.9);
}

}  // namespace
}  // namespace prism
