// The BSDF interface (renderer/shading/bsdf.h): sample() draws directions with exactly the
// density pdf() reports (a chi-square test over the sphere, as pbrt-v4's bsdfs_test does),
// pdf() integrates to the non-delta lobes' share, eval() is reciprocal, and the delta lobes
// carry the Fresnel weights of the analytic formulas. And the light interface: punctual
// lights' sample() and power(), and the power-proportional light sampler.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "renderer/image/colour.h"
#include "renderer/shading/bsdf.h"
#include "renderer/shading/light_sampler.h"
#include "renderer/shading/lights.h"
#include "tests/chi_square.h"
#include "tests/gltf_brdf_reference.h"

namespace prism {
namespace {

constexpr double kPiD = std::numbers::pi;

V3f spherical(double cos_theta, double phi) {
  return testing::DirectionGrid::direction(cos_theta, phi);
}

// The lecture model: Lambert rho_d / pi plus the normalised Phong lobe ks (n + 2)/(2 pi) (R.V)^n.
Bsdf phong_bsdf(float rho_d, float ks, float n) {
  BsdfLobes lobes;
  lobes.model = BrdfModel::lecture;
  lobes.diffuse_albedo = V3f(rho_d);
  lobes.specular_f0 = V3f(ks);
  lobes.specular_f90 = V3f(ks);
  lobes.phong_exponent = n;
  return Bsdf(V3f(0.0f, 0.0f, 1.0f), lobes);
}

// glTF's model for a material of base colour rho, metallic m and roughness r (ior 1.5, no
// extensions), as renderer/shading/material.cpp maps it.
BsdfLobes gltf_lobes(float rho, float metallic, float roughness, float transmission = 0.0f) {
  BsdfLobes lobes;
  const float d = 1.0f - metallic;
  lobes.diffuse_albedo = V3f(rho * d * (1.0f - transmission));
  lobes.dielectric_f0 = V3f(0.04f);
  lobes.dielectric_f90 = 1.0f;
  lobes.specular_f0 = V3f(0.04f * d + rho * metallic);
  lobes.specular_f90 = V3f(d + metallic);
  lobes.alpha = roughness * roughness;
  lobes.mirror = roughness <= 0.1f;
  lobes.transmission = d * transmission;
  lobes.transmission_tint = V3f(rho);
  return lobes;
}
Bsdf gltf_bsdf(float rho, float metallic, float roughness, float transmission = 0.0f) {
  return Bsdf(V3f(0.0f, 0.0f, 1.0f), gltf_lobes(rho, metallic, roughness, transmission));
}

// Histograms sample() over a (cos theta, phi) grid of the whole sphere and compares it with
// pdf() integrated over each cell (midpoint rule on a 4 x 4 sub-grid), merging cells whose
// expected count is below 5 as the chi-square test needs; returns the p-value.
double chi_square_test(const Bsdf& bsdf, const V3f& wo, int samples,
                       const Bsdf* claimed_pdf = nullptr) {
  const Bsdf& density = claimed_pdf ? *claimed_pdf : bsdf;
  constexpr int kTheta = 20, kPhi = 40, kSub = 24;
  const testing::DirectionGrid grid{kTheta, kPhi};
  std::vector<double> observed(grid.cells(), 0.0), expected(grid.cells(), 0.0);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < samples; ++i) {
    BsdfSample s;
    if (!bsdf.sample(wo, u01(rng), Imath::V2f(u01(rng), u01(rng)), false, &s)) continue;
    if (s.specular()) continue;
    observed[grid.cell_of(s.wi)] += 1.0;
  }
  for (int t = 0; t < kTheta; ++t)
    for (int p = 0; p < kPhi; ++p) {
      double integral = 0.0;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) integral += density.pdf(wo, grid.point(t, p, a, b, kSub));
      const double cell = grid.cell_solid_angle();
      expected[size_t(t * kPhi + p)] = integral / (kSub * kSub) * cell * samples;
    }
  return testing::chi_square_test(observed, expected);
}

TEST(Bsdf, SamplingMatchesPdfChiSquare) {
  // Diffuse alone, Phong alone at several exponents, and mixtures, at normal and grazing
  // views. 1e-3 per test (14 tests: a false alarm once in 70 runs of a correct sampler,
  // with the fixed seed never).
  const float exponents[] = {1.0f, 10.0f, 100.0f};
  const V3f views[] = {V3f(0, 0, 1), normalize(V3f(0.7f, 0.1f, 0.3f))};
  for (const V3f& wo : views) {
    EXPECT_GT(chi_square_test(phong_bsdf(0.8f, 0.0f, 1.0f), wo, 400000), 1e-3);
    for (float n : exponents) {
      SCOPED_TRACE(n);
      EXPECT_GT(chi_square_test(phong_bsdf(0.0f, 0.5f, n), wo, 400000), 1e-3);
      EXPECT_GT(chi_square_test(phong_bsdf(0.4f, 0.2f, n), wo, 400000), 1e-3);
    }
  }
}

// The test has teeth: a sampler whose directions follow another exponent than its pdf
// claims (10 against 12) is rejected.
TEST(Bsdf, ChiSquareRejectsAMismatchedPdf) {
  const Bsdf sampled = phong_bsdf(0.0f, 0.5f, 10.0f);
  const Bsdf claimed = phong_bsdf(0.0f, 0.5f, 12.0f);
  EXPECT_LT(chi_square_test(sampled, V3f(0, 0, 1), 400000, &claimed), 1e-6);
}

// The integral of pdf(wo, .) over the upper hemisphere by the midpoint rule in
// (cos theta, phi), t x p cells.
double hemisphere_pdf_integral(const Bsdf& bsdf, const V3f& wo, int t_cells, int p_cells) {
  double total = 0.0;
  for (int t = 0; t < t_cells; ++t)
    for (int p = 0; p < p_cells; ++p)
      total += bsdf.pdf(wo, spherical((t + 0.5) / t_cells, (p + 0.5) * 2 * kPiD / p_cells));
  return total * (1.0 / t_cells) * (2 * kPiD / p_cells);
}

TEST(Bsdf, PdfIntegratesToTheNonDeltaShare) {
  const V3f wo = normalize(V3f(0.3f, -0.2f, 0.9f));
  for (float n : {0.5f, 8.0f, 64.0f}) {
    const Bsdf bsdf = phong_bsdf(0.5f, 0.3f, n);
    const double total = hemisphere_pdf_integral(bsdf, wo, 400, 800);
    // Below the horizon the Phong lobe about R loses some of its mass: at most 1.
    EXPECT_LE(total, 1.0 + 2e-3) << n;
    if (n <= 0.5f) {
      EXPECT_GT(total, 0.9) << n;
    }
  }
  // No delta lobes: the diffuse pdf alone integrates to 1.
  EXPECT_NEAR(hemisphere_pdf_integral(phong_bsdf(0.7f, 0.0f, 1.0f), wo, 400, 400), 1.0, 1e-4);
}

TEST(Bsdf, SampleAgreesWithEvalAndPdfAndEvalIsReciprocal) {
  const Bsdf bsdf = phong_bsdf(0.3f, 0.4f, 20.0f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const V3f wo = normalize(V3f(0.2f, 0.4f, 0.8f));
  int taken = 0;
  for (int i = 0; i < 2000; ++i) {
    BsdfSample s;
    if (!bsdf.sample(wo, u01(rng), Imath::V2f(u01(rng), u01(rng)), false, &s)) continue;
    ++taken;
    EXPECT_GT(s.wi.z, 0.0f);
    const V3f f = bsdf.eval(wo, s.wi);
    EXPECT_FLOAT_EQ(s.f.x, f.x);
    EXPECT_FLOAT_EQ(s.pdf, bsdf.pdf(wo, s.wi));
    const V3f back = bsdf.eval(s.wi, wo);
    EXPECT_NEAR(back.x, f.x, 1e-5f * std::max(1.0f, f.x));
  }
  EXPECT_GT(taken, 1800);
  EXPECT_EQ(bsdf.flags(), kDiffuseReflection | kGlossyReflection);
}

// Lambert: eval is rho / pi, whatever the directions, and zero below the surface.
TEST(Bsdf, LambertValue) {
  const Bsdf bsdf = phong_bsdf(0.6f, 0.0f, 1.0f);
  EXPECT_FLOAT_EQ(bsdf.eval(V3f(0, 0, 1), normalize(V3f(1, 1, 1))).x, 0.6f / float(kPiD));
  EXPECT_EQ(bsdf.eval(V3f(0, 0, 1), V3f(0, 0, -1)).x, 0.0f);
}

// glTF's model without a specular layer (F0 = F90 = 0) is Lambert, which Bsdf evaluates by a
// shortcut: rho / pi, cos / pi, albedo rho, cosine sampling. The same material with a layer of
// F0 = F90 = 10^-30 takes the general formulas (GGX, Fresnel, the lobe choice): they must
// agree to float rounding, and the shortcut must match its own eval and pdf exactly.
TEST(Bsdf, GltfLambertShortcutEqualsTheGeneralFormulas) {
  BsdfLobes lambert;
  lambert.diffuse_albedo = V3f(0.7f, 0.4f, 0.2f);
  lambert.alpha = 0.5f;
  BsdfLobes faint = lambert;
  faint.specular_f0 = faint.specular_f90 = V3f(1e-30f);
  const V3f n(0.0f, 0.0f, 1.0f);
  const Bsdf fast = Bsdf(n, lambert).path_traced(), general = Bsdf(n, faint).path_traced();
  EXPECT_EQ(fast.flags(), kDiffuseReflection);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const V3f wo = spherical(u01(rng), 2.0 * kPiD * u01(rng));
    const V3f wi = spherical(2.0f * u01(rng) - 1.0f, 2.0 * kPiD * u01(rng));
    const V3f f = fast.eval(wo, wi), g = general.eval(wo, wi);
    const float cos_wi = dot(fast.normal_towards(wo), wi);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(f[c], g[c], 1e-6f * g[c] + 1e-30f);
      EXPECT_EQ(f[c], cos_wi > 0.0f ? lambert.diffuse_albedo[c] / float(kPiD) : 0.0f);
    }
    EXPECT_NEAR(fast.pdf(wo, wi), general.pdf(wo, wi), 1e-6f * general.pdf(wo, wi) + 1e-30f);
    const V3f a = fast.albedo(wo, n, false, AlbedoScope::all_lobes),
              b = general.albedo(wo, n, false, AlbedoScope::all_lobes);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6f);
    BsdfSample sf, sg;
    const float u_lobe = u01(rng);
    const Imath::V2f u(u01(rng), u01(rng));
    const bool ok_f = fast.sample(wo, u_lobe, u, false, &sf);
    const bool ok_g = general.sample(wo, u_lobe, u, false, &sg);
    ASSERT_EQ(ok_f, ok_g);
    if (!ok_f) continue;
    ++compared;
    EXPECT_EQ(sf.lobe, kDiffuseReflection);
    EXPECT_EQ(sf.wi, sg.wi);  // both the cosine lobe of the same u
    EXPECT_NEAR(sf.pdf, sg.pdf, 1e-6f * sg.pdf);
    EXPECT_EQ(sf.pdf, fast.pdf(wo, sf.wi));
    EXPECT_EQ(sf.f, fast.eval(wo, sf.wi));
  }
  EXPECT_GT(compared, 1900);
}

// A clear dielectric of ior 1.5: head-on F = ((n - 1) / (n + 1))^2 = 0.04 reflected and 0.96
// refracted straight through; past the critical angle from inside, total internal
// reflection (one lobe, weight 1).
TEST(Bsdf, DielectricDeltaLobesCarryFresnel) {
  BsdfLobes glass;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  const Bsdf bsdf(V3f(0, 0, 1), glass);
  EXPECT_EQ(bsdf.flags(), kSpecularReflection | kSpecularTransmission);
  SpecularLobe lobes[2];
  const V3f n(0, 0, 1);
  ASSERT_EQ(2, (bsdf.specular_lobes<true, true>(V3f(0, 0, 1), n, false, lobes)));
  EXPECT_TRUE(lobes[0].transmission);
  EXPECT_NEAR(lobes[0].weight().x, 0.96f, 1e-6f);
  EXPECT_NEAR(lobes[0].wi.z, -1.0f, 1e-6f);
  EXPECT_FALSE(lobes[1].transmission);
  EXPECT_NEAR(lobes[1].weight().x, 0.04f, 1e-6f);
  EXPECT_NEAR(lobes[1].wi.z, 1.0f, 1e-6f);
  // From inside (back face), 60 degrees from the normal: sin 60 * 1.5 > 1.
  const V3f wo = V3f(std::sin(1.0472f), 0.0f, std::cos(1.0472f));
  ASSERT_EQ(1, (bsdf.specular_lobes<true, true>(wo, n, true, lobes)));
  EXPECT_FALSE(lobes[0].transmission);
  EXPECT_FLOAT_EQ(lobes[0].weight().x, 1.0f);
  // Sampling picks the lobes in proportion to their weights, with those probabilities, and
  // its estimate f |cos| / pdf is the lobe's weight over that probability: unbiased, the
  // expectation over both choices being the sum of the weights.
  SpecularLobe normal_lobes[2];
  ASSERT_EQ(2, (bsdf.specular_lobes<true, true>(V3f(0, 0, 1), n, false, normal_lobes)));
  BsdfSample s;
  ASSERT_TRUE(bsdf.sample(V3f(0, 0, 1), 0.5f, Imath::V2f(0.5f), false, &s));
  EXPECT_EQ(s.lobe, kSpecularTransmission);
  EXPECT_NEAR(s.pdf, 0.96f, 1e-6f);
  EXPECT_NEAR(s.f.x * std::fabs(s.wi.z) / s.pdf, normal_lobes[0].weight().x / 0.96f, 1e-5f);
  ASSERT_TRUE(bsdf.sample(V3f(0, 0, 1), 0.99f, Imath::V2f(0.5f), false, &s));
  EXPECT_EQ(s.lobe, kSpecularReflection);
  EXPECT_NEAR(s.pdf, 0.04f, 1e-6f);
  EXPECT_NEAR(s.f.x * std::fabs(s.wi.z) / s.pdf, normal_lobes[1].weight().x / 0.04f, 1e-4f);
}

// A perfect mirror of F0 = 1 reflects everything at every angle (Schlick with F0 = 1).
TEST(Bsdf, MirrorWeightIsSchlick) {
  BsdfLobes mirror;
  mirror.mirror = true;
  mirror.specular_f0 = V3f(0.5f);
  mirror.specular_f90 = V3f(1.0f);
  const Bsdf bsdf(V3f(0, 0, 1), mirror);
  SpecularLobe lobes[2];
  const V3f wo = normalize(V3f(0.6f, 0.0f, 0.8f));  // cos 0.8
  ASSERT_EQ(1, (bsdf.specular_lobes<true, true>(wo, V3f(0, 0, 1), false, lobes)));
  const float schlick = 0.5f + 0.5f * std::pow(1.0f - 0.8f, 5.0f);
  EXPECT_NEAR(lobes[0].weight().x, schlick, 1e-6f);
  EXPECT_NEAR(lobes[0].wi.x, -0.6f, 1e-6f);
  EXPECT_NEAR(lobes[0].wi.z, 0.8f, 1e-6f);
  // Specialised away, the lobe is not there.
  EXPECT_EQ(0, (bsdf.specular_lobes<false, true>(wo, V3f(0, 0, 1), false, lobes)));
}

TEST(Bsdf, GltfBrdfEqualsAppendixB) {
  double worst = 0.0;
  for (float roughness : {0.3f, 0.5f, 0.7f, 1.0f})
    for (float metallic : {0.0f, 0.5f, 1.0f})
      for (double theta_o : {0.0, 0.5, 1.2})
        for (double theta_i : {0.1, 0.7, 1.4})
          for (double phi : {0.0, 2.0, 3.14159}) {
            const V3f wo = spherical(std::cos(theta_o), 0.0);
            const V3f wi = spherical(std::cos(theta_i), phi);
            const Bsdf bsdf = gltf_bsdf(0.7f, metallic, roughness);
            const double ref =
                testing::appendix_b_brdf(0.7, metallic, double(roughness) * roughness, V3d(0, 0, 1),
                                         V3d(wo.x, wo.y, wo.z), V3d(wi.x, wi.y, wi.z));
            const double got = bsdf.eval(wo, wi).x;
            worst = std::max(worst, std::fabs(got - ref) / ref);
          }
  EXPECT_LT(worst, 1e-5) << "worst relative difference from Appendix B";
}

TEST(Bsdf, GgxIsReciprocal) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (float roughness : {0.2f, 0.6f, 1.0f}) {
    const Bsdf bsdf = gltf_bsdf(0.5f, 0.3f, roughness);
    for (int i = 0; i < 500; ++i) {
      const V3f wo = spherical(u01(rng), 2 * kPiD * u01(rng));
      const V3f wi = spherical(u01(rng), 2 * kPiD * u01(rng));
      const V3f a = bsdf.eval(wo, wi), b = bsdf.eval(wi, wo);
      EXPECT_NEAR(a.x, b.x, 1e-5f * std::max(1.0f, a.x));
    }
  }
}

TEST(Bsdf, GgxSamplingMatchesPdfChiSquare) {
  // The visible-normal sampler against its pdf, alone (metal) and mixed with Lambert, from
  // alpha 0.09 (roughness 0.3) to 1, at normal and grazing views. Sharper lobes fall inside
  // one sub-cell of this test's 20 x 40 bins near the pole, so its expected counts would be
  // wrong, not the sampler.
  const V3f views[] = {V3f(0, 0, 1), normalize(V3f(0.7f, 0.1f, 0.3f)),
                       normalize(V3f(0.95f, 0.0f, 0.1f))};
  for (const V3f& wo : views)
    for (float roughness : {0.3f, 0.45f, 0.6f, 1.0f}) {
      SCOPED_TRACE(roughness);
      EXPECT_GT(chi_square_test(gltf_bsdf(1.0f, 1.0f, roughness), wo, 400000), 1e-3);
      EXPECT_GT(chi_square_test(gltf_bsdf(0.6f, 0.0f, roughness), wo, 400000), 1e-3);
    }
}

TEST(Bsdf, GgxPdfIntegratesToAtMostOne) {
  const V3f wo = normalize(V3f(0.5f, -0.2f, 0.6f));
  for (float roughness : {0.2f, 0.5f, 1.0f}) {
    const Bsdf bsdf = gltf_bsdf(1.0f, 1.0f, roughness);
    const double total = hemisphere_pdf_integral(bsdf, wo, 800, 800);
    // What the visible normals reflect below the horizon is lost, so at most 1; and at
    // least the lobe's albedo, whose estimator G2 / G1 is at most 1 per sample kept.
    EXPECT_LE(total, 1.0 + 2e-3) << roughness;
    EXPECT_GE(total, ggx_albedo(wo.z, roughness * roughness).e - 2e-3) << roughness;
  }
}

// The tabulated albedo of the GGX lobe against a brute-force integral of eval() over the
// hemisphere (a white metal: F = 1, so f = D V).
TEST(Bsdf, GgxAlbedoTableMatchesTheIntegralOfEval) {
  for (float roughness : {0.25f, 0.5f, 0.8f, 1.0f})
    for (float cos_v : {0.15f, 0.5f, 0.9f}) {
      const Bsdf metal = gltf_bsdf(1.0f, 1.0f, roughness);
      const V3f wo = spherical(cos_v, 0.0);
      double total = 0.0;
      constexpr int kT = 1000, kP = 1000;
      for (int t = 0; t < kT; ++t)
        for (int p = 0; p < kP; ++p) {
          const double cos_i = (t + 0.5) / kT;
          total += metal.eval(wo, spherical(cos_i, (p + 0.5) * 2 * kPiD / kP)).x * cos_i;
        }
      total *= (1.0 / kT) * (2 * kPiD / kP);
      const GgxAlbedo table = ggx_albedo(cos_v, roughness * roughness);
      EXPECT_NEAR(table.e, total, 3e-3) << roughness << " " << cos_v;
      EXPECT_LE(table.e, 1.0f);
    }
}

// At alpha = 1, D = 1 / pi and V = 1 / (2 (cos_l + cos_v)), so the albedo has a closed form:
// E(mu) = integral over mu' of mu' / (mu' + mu) = 1 - mu ln((1 + mu) / mu).
TEST(Bsdf, GgxAlbedoAtUnitRoughnessIsAnalytic) {
  for (double mu : {0.05, 0.1, 0.3, 0.5, 0.77, 1.0}) {
    const double exact = 1.0 - mu * std::log((1.0 + mu) / mu);
    EXPECT_NEAR(integrate_ggx_albedo(float(mu), 1.0f, 128).e, exact, 1e-4) << mu;
    EXPECT_NEAR(ggx_albedo(float(mu), 1.0f).e, exact, mu < 0.1 ? 5e-3 : 1e-3) << mu;
  }
}

// The ambient albedo: at most 1 at every viewing angle for every material, exactly 1 for the
// white lossless ones, and the whitted split (the non-delta lobes plus the delta lobes'
// weights) adds up to the whole.
TEST(Bsdf, AlbedoNeverExceedsOneAndIsOneForWhiteLosslessMaterials) {
  struct Case {
    const char* name;
    BsdfLobes lobes;
    bool lossless;
  };
  BsdfLobes tinted_glass = gltf_lobes(0.6f, 0.0f, 0.0f, 1.0f);
  const Case cases[] = {
      {"lambert",
       [] {
         BsdfLobes l;
         l.diffuse_albedo = V3f(1.0f);
         return l;
       }(),
       true},
      {"rough dielectric", gltf_lobes(1.0f, 0.0f, 0.5f), true},
      {"smooth dielectric", gltf_lobes(1.0f, 0.0f, 0.0f), true},
      {"rough metal", gltf_lobes(1.0f, 1.0f, 0.5f), false},
      {"smooth metal", gltf_lobes(1.0f, 1.0f, 0.05f), true},
      {"glass", gltf_lobes(1.0f, 0.0f, 0.0f, 1.0f), true},
      {"rough glass", gltf_lobes(1.0f, 0.0f, 0.6f, 1.0f), true},
      {"tinted glass", tinted_glass, false},
      {"half metal", gltf_lobes(1.0f, 0.5f, 0.3f, 0.5f), false},
      {"lecture",
       [] {
         BsdfLobes l = gltf_lobes(1.0f, 0.0f, 0.05f);
         l.model = BrdfModel::lecture;
         return l;
       }(),
       true},
  };
  const V3f n(0, 0, 1);
  for (const Case& c : cases)
    for (bool back_face : {false, true})
      for (int k = 0; k <= 100; ++k) {
        const float cos_v = std::max(1e-4f, k / 100.0f);
        const V3f wo = spherical(cos_v, 0.3);
        const Bsdf bsdf(n, c.lobes);
        const V3f all = bsdf.albedo(wo, n, back_face, AlbedoScope::all_lobes);
        SCOPED_TRACE(::testing::Message() << c.name << " cos " << cos_v << " back " << back_face);
        EXPECT_LE(std::max({all.x, all.y, all.z}), 1.0f + 1e-5f);
        if (c.lossless) {
          EXPECT_NEAR(all.x, 1.0f, 1e-5f);
        }
        V3f split = bsdf.albedo(wo, n, back_face, AlbedoScope::without_delta_lobes);
        SpecularLobe lobes[2];
        const int count = bsdf.specular_lobes<true, true>(wo, n, back_face, lobes);
        for (int i = 0; i < count; ++i) split += lobes[i].weight();
        EXPECT_NEAR(split.x, all.x, 1e-6f);
      }
}

// The BSDF a path tracer samples (Bsdf::path_traced): a delta mirror only below kMinGgxAlpha,
// whose eval() then has no GGX lobe (the mirror ray carries the layer's light), and GGX above,
// where the Whitted integrators' mirror stops at roughness 0.1. The Monte Carlo albedo
// E[f cos / pdf] of a white metal's samples (a white furnace of the BSDF alone) never exceeds 1
// and matches the tabulated albedo() the ambient term uses. (A white dielectric's does not:
// glTF's fresnel_mix weighs the diffuse base by 1 - F(V.H) per direction, which at grazing
// views lets it reflect more than 1 -- docs/accuracy.md has the figures.)
// The mean of sample()'s weight f cos / pdf (red) over `samples` uniform random numbers, its
// standard error, and how often each lobe was chosen (its direction kept or not).
struct SampledAlbedo {
  double mean = 0.0, error = 0.0;
  int glossy = 0;
};
SampledAlbedo sample_albedo(const Bsdf& bsdf, const V3f& wo, int samples, std::mt19937* rng) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  SampledAlbedo a;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    BsdfSample b;
    double w = 0.0;
    // The lobe is set once chosen, also when its direction then falls below the surface.
    if (bsdf.sample(wo, u01(*rng), Imath::V2f(u01(*rng), u01(*rng)), false, &b))
      w = b.f.x * std::fabs(b.wi.z) / b.pdf;
    if (b.lobe == kGlossyReflection) ++a.glossy;
    sum += w;
    sum2 += w * w;
  }
  a.mean = sum / samples;
  a.error = std::sqrt(std::max(0.0, sum2 / samples - a.mean * a.mean) / samples);
  return a;
}

TEST(Bsdf, PathTracedBsdfFurnace) {
  const V3f n(0, 0, 1);
  const Bsdf mirror = gltf_bsdf(0.9f, 1.0f, 0.0f).path_traced();
  EXPECT_TRUE(mirror.flags() & kSpecularReflection);
  const V3f wo = normalize(V3f(0.4f, 0.1f, 0.8f));
  EXPECT_EQ(mirror.eval(wo, reflect(-wo, n)), V3f(0.0f));  // metal: no diffuse, no GGX
  BsdfSample s;
  ASSERT_TRUE(mirror.sample(wo, 0.5f, Imath::V2f(0.3f, 0.7f), false, &s));
  EXPECT_TRUE(s.specular());
  const float schlick = 0.9f + 0.1f * std::pow(1.0f - wo.z, 5.0f);
  EXPECT_NEAR(s.f.x * std::fabs(s.wi.z) / s.pdf, schlick, 1e-5f);
  EXPECT_FALSE(gltf_bsdf(0.9f, 1.0f, 0.1f).path_traced().flags() & kSpecularReflection);

  std::mt19937 rng(99);
  for (float metallic : {1.0f})
    for (float roughness : {0.0f, 0.1f, 0.3f, 0.6f, 1.0f})
      for (float cos_v : {0.2f, 0.7f, 1.0f}) {
        const Bsdf bsdf = gltf_bsdf(1.0f, metallic, roughness).path_traced();
        const V3f view = spherical(cos_v, 0.4);
        const SampledAlbedo sampled = sample_albedo(bsdf, view, 200000, &rng);
        const double mean = sampled.mean, error = sampled.error;
        const double table = bsdf.albedo(view, n, false, AlbedoScope::all_lobes).x;
        SCOPED_TRACE(::testing::Message()
                     << "metallic " << metallic << " roughness " << roughness << " cos " << cos_v);
        std::printf("path BSDF furnace m %.0f r %.1f cos %.1f: %.5f +- %.5f (albedo table %.5f)\n",
                    metallic, roughness, cos_v, mean, error, table);
        EXPECT_LE(mean, 1.0 + 4.0 * error);
        // The table is interpolated on a 32 x 32 grid (ggx_albedo.h): 5e-3 is its stated error.
        EXPECT_NEAR(mean, table, 4.0 * error + 5e-3);
      }
}

// An opaque glTF dielectric splits its samples between the diffuse base and the GGX layer in
// proportion to their albedos at wo, not by the layer's F90 of 1 (which sent two samples in
// three to a layer that reflects 4 to 10 % of the light): the share that sample() gives the
// layer is its tabulated albedo's share, and the mean weight f cos / pdf is still the albedo,
// integrated independently of the sampling (eval over a uniform hemisphere grid).
TEST(Bsdf, LobeChoiceFollowsTheLobesAlbedos) {
  const V3f n(0, 0, 1);
  std::mt19937 rng(41);
  for (float roughness : {0.35f, 0.6f, 1.0f})
    for (float cos_v : {0.15f, 0.6f, 1.0f}) {
      SCOPED_TRACE(::testing::Message() << "roughness " << roughness << " cos " << cos_v);
      const Bsdf bsdf = gltf_bsdf(0.5f, 0.0f, roughness).path_traced();
      const V3f wo = spherical(cos_v, 1.1);
      const GgxAlbedo table = ggx_albedo(cos_v, roughness * roughness);
      const double layer = 0.04 * table.e + 0.96 * table.e_schlick;
      const double expected_share = layer / (layer + 0.5 * (1.0 - layer));
      constexpr int kSamples = 400000;
      const SampledAlbedo sampled = sample_albedo(bsdf, wo, kSamples, &rng);
      const double share = double(sampled.glossy) / kSamples;
      const double share_error = std::sqrt(expected_share * (1 - expected_share) / kSamples);
      const double mean = sampled.mean, error = sampled.error;
      constexpr int kGrid = 400;
      double integral = 0.0;
      for (int a = 0; a < kGrid; ++a)
        for (int c = 0; c < kGrid; ++c) {
          const double ct = (a + 0.5) / kGrid, phi = 2 * kPiD * (c + 0.5) / kGrid;
          integral += bsdf.eval(wo, spherical(ct, phi), n).x * ct;
        }
      integral *= 2 * kPiD / (double(kGrid) * kGrid);
      std::printf(
          "dielectric r %.2f cos %.2f: layer share %.4f (albedos' %.4f), albedo %.5f +- %.5f "
          "(integral of eval %.5f)\n",
          roughness, cos_v, share, expected_share, mean, error, integral);
      EXPECT_NEAR(share, expected_share, 4 * share_error);
      EXPECT_LT(share, 0.5);  // never the two in three of the F90 rule
      EXPECT_NEAR(mean, integral, 4 * error + 2e-3 * integral);
    }
}

Light punctual(LightType type, float intensity) {
  Light l;
  l.type = type;
  l.intensity = intensity;
  l.position = V3d(0, 2, 0);
  l.direction = V3d(0, -1, 0);
  l.inner_cone_angle = 0.0;
  l.outer_cone_angle = kPiD / 4;
  return l;
}

// A point light of I candela: sample() gives I / d^2 along the unit direction with pdf 1
// (a delta light), and its power is 4 pi I.
TEST(Lights, PunctualSampleAndPower) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const LightSource point(punctual(LightType::point, 3.0f), colour);
  LightSample s;
  ASSERT_TRUE(point.sample(V3f(0, 0, 0), Imath::V2f(0.5f), &s));
  EXPECT_NEAR(s.radiance.x, 3.0f / 4.0f, 1e-6f);
  EXPECT_FLOAT_EQ(s.wi.y, 1.0f);
  EXPECT_FLOAT_EQ(s.distance, 2.0f);
  EXPECT_EQ(s.pdf, 1.0f);
  EXPECT_TRUE(point.is_delta());
  EXPECT_EQ(point.pdf(V3f(0.0f), V3f(0, 1, 0)), 0.0f);
  EXPECT_EQ(point.emitted(V3f(0.0f), V3f(0, 1, 0)).x, 0.0f);
  EXPECT_NEAR(point.power(1.0f).x, 4.0f * float(kPiD) * 3.0f, 1e-4f);
  // A sun of E lux over a scene of radius r: E pi r^2.
  const LightSource sun(punctual(LightType::directional, 2.0f), colour);
  EXPECT_NEAR(sun.power(10.0f).x, 2.0f * float(kPiD) * 100.0f, 1e-3f);
  // A spot with no smooth band (inner 0): 2 pi (1 - cos_outer / 2 - 1 / 2) I.
  const LightSource spot(punctual(LightType::spot, 1.0f), colour);
  EXPECT_NEAR(spot.power(1.0f).x,
              2.0f * float(kPiD) * (1.0f - 0.5f * (1.0f + std::cos(float(kPiD) / 4))), 1e-5f);
}

// Lights are chosen in proportion to their power: pmf from the powers, sample() frequencies
// over stratified u matching it, a zero-power light never chosen, no lights no choice.
TEST(LightSampler, ChoosesInProportionToPower) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  std::vector<LightSource> lights;
  for (float i : {1.0f, 3.0f, 0.0f, 4.0f})
    lights.emplace_back(punctual(LightType::point, i), colour);
  const LightSampler sampler(lights, 1.0f);
  EXPECT_NEAR(sampler.pmf(0), 1.0f / 8.0f, 1e-6f);
  EXPECT_NEAR(sampler.pmf(1), 3.0f / 8.0f, 1e-6f);
  EXPECT_EQ(sampler.pmf(2), 0.0f);
  EXPECT_NEAR(sampler.pmf(3), 4.0f / 8.0f, 1e-6f);
  EXPECT_EQ(sampler.pmf(4), 0.0f);
  std::vector<int> counts(4, 0);
  constexpr int kN = 80000;
  for (int k = 0; k < kN; ++k) {
    SampledLight chosen;
    ASSERT_TRUE(sampler.sample((k + 0.5f) / kN, &chosen));
    ++counts[chosen.index];
    EXPECT_EQ(chosen.pmf, sampler.pmf(chosen.index));
  }
  EXPECT_EQ(counts[2], 0);
  EXPECT_NEAR(counts[0], kN / 8, 2);
  EXPECT_NEAR(counts[1], 3 * kN / 8, 2);
  EXPECT_NEAR(counts[3], kN / 2, 2);
  const LightSampler none(std::vector<LightSource>{}, 1.0f);
  SampledLight chosen;
  EXPECT_FALSE(none.sample(0.5f, &chosen));
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace prism
