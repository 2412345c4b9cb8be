// KHR_materials_clearcoat and KHR_materials_sheen in the BSDF (renderer/shading/bsdf.h,
// clearcoat_sheen.h), as pbrt-v4's bsdfs_test checks a BxDF: sample() draws directions with
// the density pdf() reports (a chi-square test on a grid refined about the mirror
// direction, so that a coat of roughness 0.1, alpha 0.01, spans many cells), pdf()
// integrates to at most 1, eval() is reciprocal, and the Monte Carlo albedo E[f cos / pdf]
// never exceeds 1 and, for a coat over a black base, is the GGX layer's tabulated albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "renderer/shading/bsdf.h"
#include "tests/chi_square.h"

namespace prism {
namespace {

constexpr double kPiD = std::numbers::pi;
const V3f kNormal(0.0f, 0.0f, 1.0f);

V3f view_at(float cos_v) {
  return testing::DirectionGrid::direction(cos_v, 0.3);
}

// A base of white Lambert (no specular layer) or black (nothing at all), under the layers.
BsdfLobes base(bool white) {
  BsdfLobes l;
  l.diffuse_albedo = V3f(white ? 1.0f : 0.0f);
  return l;
}
BsdfLobes coated(BsdfLobes l, float weight, float roughness) {
  l.layers.clearcoat = weight;
  l.layers.clearcoat_alpha = roughness * roughness;
  l.layers.clearcoat_normal = kNormal;
  return l;
}
BsdfLobes sheened(BsdfLobes l, const V3f& colour, float roughness) {
  l.layers.sheen_colour = colour;
  l.layers.sheen_alpha = std::max(roughness * roughness, kMinSheenAlpha);
  return l;
}
// glTF's rough white dielectric (ior 1.5) under the layers: the base's GGX lobe too.
BsdfLobes dielectric(float rho, float roughness) {
  BsdfLobes l;
  l.diffuse_albedo = V3f(rho);
  l.dielectric_f0 = V3f(0.04f);
  l.dielectric_f90 = 1.0f;
  l.specular_f0 = V3f(0.04f);
  l.specular_f90 = V3f(1.0f);
  l.alpha = roughness * roughness;
  return l;
}

// Cells about an axis: 1 - cos(theta') from 0 to 2 in kRings rings whose edges go as
// 2 (k / kRings)^6, so the innermost are a few thousandths of a radian wide, by kSectors in
// phi'. A cell's expected count is pdf() integrated over it by the midpoint rule on a
// kSub x kSub grid in (1 - cos, phi), which is exact for solid angle.
struct AxisGrid {
  static constexpr int kRings = 40, kSectors = 32, kSub = 12;
  V3f axis;

  static double edge(int k) { return 2.0 * std::pow(double(k) / kRings, 6.0); }
  size_t cells() const { return size_t(kRings) * kSectors; }
  size_t cell_of(const V3f& w) const {
    const V3f local = to_local(w, axis);
    // 1 - cos = |w - axis|^2 / 2, exact near the axis where 1 - z has no digits left.
    const V3f d = w - axis;
    const double u =
        std::clamp(0.5 * (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z), 0.0, 2.0);
    int ring = int(std::pow(u / 2.0, 1.0 / 6.0) * kRings);
    ring = std::clamp(ring, 0, kRings - 1);
    while (ring > 0 && u < edge(ring)) --ring;
    while (ring + 1 < kRings && u >= edge(ring + 1)) ++ring;
    double phi = std::atan2(double(local.y), double(local.x));
    if (phi < 0) phi += 2 * kPiD;
    const int sector = std::min(kSectors - 1, int(phi / (2 * kPiD) * kSectors));
    return size_t(ring) * kSectors + size_t(sector);
  }
  // The integral of `f` over each cell.
  template <typename F>
  std::vector<double> integrate(F f) const {
    std::vector<double> out(cells(), 0.0);
    for (int k = 0; k < kRings; ++k) {
      const double u0 = edge(k), du = (edge(k + 1) - u0) / kSub;
      for (int s = 0; s < kSectors; ++s) {
        double total = 0.0;
        for (int a = 0; a < kSub; ++a)
          for (int b = 0; b < kSub; ++b) {
            const double cos_t = 1.0 - (u0 + (a + 0.5) * du);
            const double phi = (s + (b + 0.5) / kSub) * 2 * kPiD / kSectors;
            total += f(from_local(testing::DirectionGrid::direction(cos_t, phi), axis));
          }
        out[size_t(k) * kSectors + size_t(s)] = total * du * (2 * kPiD / kSectors / kSub);
      }
    }
    return out;
  }
};

AxisGrid grid_for(const V3f& wo) {
  return AxisGrid{normalize(reflect(-wo, kNormal))};
}

// The p-value of sample()'s directions against `density`'s pdf() over the grid.
double chi_square_p(const Bsdf& bsdf, const V3f& wo, int samples, const Bsdf& density) {
  const AxisGrid grid = grid_for(wo);
  std::vector<double> observed(grid.cells(), 0.0);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < samples; ++i) {
    BsdfSample s;
    const float u_lobe = u01(rng);
    const Imath::V2f u(u01(rng), u01(rng));
    if (!bsdf.sample(wo, u_lobe, u, false, &s) || s.specular()) continue;
    observed[grid.cell_of(s.wi)] += 1.0;
  }
  std::vector<double> expected = grid.integrate([&](const V3f& wi) { return density.pdf(wo, wi); });
  for (double& e : expected) e *= samples;
  return testing::chi_square_test(observed, expected);
}

struct Case {
  const char* name;
  BsdfLobes lobes;
};

std::vector<Case> layered_cases() {
  std::vector<Case> cases;
  for (float r : {0.1f, 0.3f, 0.6f}) {
    cases.push_back({"coat over black", coated(base(false), 1.0f, r)});
    cases.push_back({"coat over lambert", coated(base(true), 1.0f, r)});
    cases.push_back({"half coat over rough dielectric", coated(dielectric(0.5f, 0.7f), 0.5f, r)});
  }
  for (float r : {0.1f, 0.5f, 1.0f}) {
    cases.push_back({"sheen over black", sheened(base(false), V3f(1.0f), r)});
    cases.push_back(
        {"sheen over dielectric", sheened(dielectric(0.8f, 0.5f), V3f(0.9f, 0.5f, 0.2f), r)});
  }
  cases.push_back({"coat over sheen over dielectric",
                   coated(sheened(dielectric(0.6f, 0.4f), V3f(0.7f), 0.4f), 0.8f, 0.1f)});
  return cases;
}

const float kViews[] = {1.0f, 0.7f, 0.3f, 0.1f};

TEST(ClearcoatSheen, SamplingMatchesPdfChiSquare) {
  // 1e-3 per test as tests/bsdf_test.cpp's (44 tests; with the fixed seed never a false alarm).
  for (const Case& c : layered_cases())
    for (float cos_v : kViews) {
      const Bsdf bsdf = Bsdf(kNormal, c.lobes).path_traced();
      const double p = chi_square_p(bsdf, view_at(cos_v), 1000000, bsdf);
      SCOPED_TRACE(::testing::Message()
                   << c.name << " coat alpha " << c.lobes.layers.clearcoat_alpha << " sheen alpha "
                   << c.lobes.layers.sheen_alpha << " cos " << cos_v);
      EXPECT_GT(p, 1e-3);
    }
}

// The grid has teeth at the sharpest coat: a sampler drawing from roughness 0.1 while its
// pdf claims 0.11 (alpha 0.0100 against 0.0121) is rejected.
TEST(ClearcoatSheen, ChiSquareRejectsAMismatchedCoatRoughness) {
  const Bsdf sampled = Bsdf(kNormal, coated(base(false), 1.0f, 0.1f)).path_traced();
  const Bsdf claimed = Bsdf(kNormal, coated(base(false), 1.0f, 0.11f)).path_traced();
  for (float cos_v : {1.0f, 0.5f}) {
    EXPECT_LT(chi_square_p(sampled, view_at(cos_v), 1000000, claimed), 1e-6) << cos_v;
  }
}

TEST(ClearcoatSheen, PdfIntegratesToAtMostOne) {
  for (const Case& c : layered_cases())
    for (float cos_v : kViews) {
      const Bsdf bsdf = Bsdf(kNormal, c.lobes).path_traced();
      const V3f wo = view_at(cos_v);
      double total = 0.0;
      for (double cell : grid_for(wo).integrate([&](const V3f& wi) { return bsdf.pdf(wo, wi); }))
        total += cell;
      SCOPED_TRACE(::testing::Message() << c.name << " cos " << cos_v);
      // Visible normals that reflect below the horizon lose their share: at most 1. The
      // cosine lobes (Lambert, sheen) lose nothing, so a sheen over black integrates to 1.
      EXPECT_LE(total, 1.0 + 2e-3);
      EXPECT_GT(total, 0.5);
      if (c.lobes.layers.clearcoat == 0.0f && c.lobes.specular_f90 == V3f(0.0f)) {
        EXPECT_NEAR(total, 1.0, 2e-3);
      }
    }
}

TEST(ClearcoatSheen, EvalIsReciprocal) {
  // The layers' own terms are symmetric to the bit (sums ordered alike, V.H and L.H
  // averaged); a base with a GGX lobe brings its own float asymmetry, Schlick's weight at
  // V.H (tests/bsdf_test.cpp, GgxIsReciprocal), measured here on the base alone too.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  double worst_layers = 0.0, worst_with_ggx = 0.0, worst_base = 0.0;
  for (const Case& c : layered_cases()) {
    const Bsdf bsdf = Bsdf(kNormal, c.lobes).path_traced();
    BsdfLobes base_lobes = c.lobes;
    base_lobes.layers = SurfaceLayers{};
    const Bsdf base_alone(kNormal, base_lobes);
    const bool ggx_base = c.lobes.specular_f90 != V3f(0.0f);
    for (int i = 0; i < 2000; ++i) {
      const V3f wo = testing::DirectionGrid::direction(u01(rng), 2 * kPiD * u01(rng));
      // Half the pairs near the mirror direction, where the sharp coat has its peak.
      V3f wi = testing::DirectionGrid::direction(u01(rng), 2 * kPiD * u01(rng));
      if (i % 2 == 0) {
        wi = normalize(reflect(-wo, kNormal) + V3f(u01(rng) - 0.5f, u01(rng) - 0.5f, 0.0f) * 0.04f);
        if (wi.z <= 0.0f) continue;
      }
      const V3f a = bsdf.eval(wo, wi), b = bsdf.eval(wi, wo);
      const V3f base_a = base_alone.eval(wo, wi), base_b = base_alone.eval(wi, wo);
      for (int k = 0; k < 3; ++k) {
        const double rel = std::fabs(a[k] - b[k]) / std::max(1.0f, std::fabs(a[k]));
        const double base_rel =
            std::fabs(base_a[k] - base_b[k]) / std::max(1.0f, std::fabs(base_a[k]));
        worst_base = std::max(worst_base, base_rel);
        (ggx_base ? worst_with_ggx : worst_layers) =
            std::max(ggx_base ? worst_with_ggx : worst_layers, rel);
        EXPECT_LE(rel, ggx_base ? 1e-4 : 1e-6) << c.name << " " << a[k] << " " << b[k];
      }
    }
  }
  std::printf(
      "clearcoat/sheen reciprocity: worst relative difference %.3g over a Lambert or "
      "black base, %.3g over a GGX base (the base alone: %.3g)\n",
      worst_layers, worst_with_ggx, worst_base);
}

struct Estimate {
  double mean = 0.0, error = 0.0;
};
// E[f cos / pdf] over sample()'s directions: the BSDF's albedo towards wo, red channel.
Estimate monte_carlo_albedo(const Bsdf& bsdf, const V3f& wo, int samples, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    BsdfSample b;
    const float u_lobe = u01(rng);
    const Imath::V2f u(u01(rng), u01(rng));
    double w = 0.0;
    if (bsdf.sample(wo, u_lobe, u, false, &b)) w = b.f.x * std::fabs(b.wi.z) / b.pdf;
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / samples;
  return {mean, std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples)};
}

// White furnace: a white Lambert base under a full coat, a white sheen, or both, never
// reflects more than 1 at any incident angle (the layers take from the base what they
// reflect, by the symmetric weights of docs/materials.md). Below sheen roughness 0.3 the
// Charlie lobe alone reflects more than 1 at grazing views (E up to 2.1, see
// SheenAlbedoTableMatchesItsIntegral) and is divided by its tabulated albedo there; the
// table's interpolation error where E > 1 then leaves up to 2 % over 1.
TEST(ClearcoatSheen, WhiteFurnaceNeverExceedsOne) {
  std::vector<Case> cases;
  for (float r : {0.1f, 0.3f, 0.5f, 1.0f}) {
    cases.push_back({"coat", coated(base(true), 1.0f, r)});
    cases.push_back({"sheen", sheened(base(true), V3f(1.0f), r)});
    cases.push_back({"coat and sheen", coated(sheened(base(true), V3f(1.0f), r), 1.0f, r)});
  }
  double highest = 0.0, highest_smooth_sheen = 0.0;
  for (const Case& c : cases)
    for (float cos_v : {0.02f, 0.1f, 0.3f, 0.5f, 0.7f, 0.9f, 1.0f}) {
      const Bsdf bsdf = Bsdf(kNormal, c.lobes).path_traced();
      const Estimate e = monte_carlo_albedo(bsdf, view_at(cos_v), 200000, 17);
      std::printf("furnace %-15s coat a %.2f sheen a %.2f cos %.2f: %.5f +- %.5f\n", c.name,
                  c.lobes.layers.clearcoat_alpha, c.lobes.layers.sheen_alpha, cos_v, e.mean,
                  e.error);
      const bool smooth_sheen =
          c.lobes.layers.sheen_max() > 0.0f && c.lobes.layers.sheen_alpha < 0.09f - 1e-6f;
      (smooth_sheen ? highest_smooth_sheen : highest) =
          std::max(smooth_sheen ? highest_smooth_sheen : highest, e.mean);
      EXPECT_LE(e.mean, (smooth_sheen ? 1.02 : 1.0) + 4.0 * e.error) << c.name << " cos " << cos_v;
      // At least the coat's own albedo, at most the tabulated albedo of the stack (which
      // weighs the base by the view's transmittance alone, an upper bound of the symmetric one).
      const V3f wo = view_at(cos_v);
      const double coat_alone = c.lobes.layers.coat_albedo(wo, kNormal);
      const double table = bsdf.albedo(wo, kNormal, false, AlbedoScope::all_lobes).x;
      EXPECT_GE(e.mean, coat_alone - 4.0 * e.error) << c.name << " cos " << cos_v;
      EXPECT_LE(e.mean, table + 4.0 * e.error + 5e-3) << c.name << " cos " << cos_v;
    }
  std::printf("furnace: highest albedo %.5f; with sheen roughness 0.1 %.5f\n", highest,
              highest_smooth_sheen);
}

// A coat over a black base is the GGX layer alone with F0 = 0.04: its albedo is
// c (F0 E + (1 - F0) E_S), from the quadrature of renderer/shading/ggx_albedo.h, and the
// tabulated value Bsdf::albedo() gives is that within the table's 5e-3.
TEST(ClearcoatSheen, CoatOverBlackHasTheGgxLayersAlbedo) {
  double worst = 0.0;
  for (float weight : {1.0f, 0.4f})
    for (float r : {0.1f, 0.3f, 0.6f, 1.0f})
      for (float cos_v : {0.1f, 0.4f, 0.8f, 1.0f}) {
        const Bsdf bsdf = Bsdf(kNormal, coated(base(false), weight, r)).path_traced();
        const V3f wo = view_at(cos_v);
        const Estimate e = monte_carlo_albedo(bsdf, wo, 200000, 31);
        const GgxAlbedo g = integrate_ggx_albedo(cos_v, std::max(r * r, kMinGgxAlpha), 256);
        const double expected = weight * (0.04 * g.e + 0.96 * g.e_schlick);
        const double table = bsdf.albedo(wo, kNormal, false, AlbedoScope::all_lobes).x;
        std::printf(
            "coat over black c %.1f r %.1f cos %.1f: %.5f +- %.5f (GGX layer %.5f, "
            "table %.5f)\n",
            weight, r, cos_v, e.mean, e.error, expected, table);
        worst = std::max(worst, std::fabs(e.mean - expected) / std::max(e.error, 1e-9));
        EXPECT_NEAR(e.mean, expected, 4.0 * e.error + 1e-4) << r << " " << cos_v;
        EXPECT_NEAR(table, expected, 5e-3) << r << " " << cos_v;
      }
  std::printf("coat over black: worst |MC - GGX layer| = %.2f standard errors\n", worst);
}

// The sheen's albedo table (built on first use) against the quadrature at 4x its points
// (its own error, 64 against 512 points, is below 1.3e-2 where E > 2 and 1e-3 elsewhere),
// and the sheen lobe alone against both where E < 1 at every angle (roughness >= 0.3): the
// sampler, eval and the integral agree.
TEST(ClearcoatSheen, SheenAlbedoTableMatchesItsIntegral) {
  double worst_table = 0.0, worst_over_one = 0.0, highest = 0.0;
  for (float r : {0.1f, 0.2f, 0.3f, 0.5f, 0.8f, 1.0f})
    for (float cos_v : {0.001f, 0.02f, 0.05f, 0.2f, 0.5f, 0.8f, 1.0f}) {
      const float alpha = std::max(r * r, kMinSheenAlpha);
      const double exact = integrate_sheen_albedo(cos_v, alpha, 256);
      const double table = sheen_albedo(cos_v, alpha);
      highest = std::max(highest, exact);
      // Where E > 1 it only divides the lobe; elsewhere it is the base's weight.
      if (exact > 1.0) {
        worst_over_one = std::max(worst_over_one, std::fabs(table - exact) / exact);
        EXPECT_NEAR(table / exact, 1.0, 2e-2) << r << " " << cos_v;
      } else {
        worst_table = std::max(worst_table, std::fabs(table - exact));
        EXPECT_NEAR(table, exact, r < 0.3f ? 1e-2 : 5e-3) << r << " " << cos_v;
      }
      if (r >= 0.3f) {
        EXPECT_LT(exact, 1.0);
        const Bsdf bsdf = Bsdf(kNormal, sheened(base(false), V3f(1.0f), r)).path_traced();
        const Estimate e = monte_carlo_albedo(bsdf, view_at(cos_v), 200000, 41);
        std::printf(
            "sheen over black r %.1f cos %.3f: %.5f +- %.5f (quadrature %.5f, table %.5f)\n", r,
            cos_v, e.mean, e.error, exact, table);
        EXPECT_NEAR(e.mean, exact, 4.0 * e.error + 1e-4) << r << " " << cos_v;
      }
    }
  std::printf("sheen albedo: highest E %.4f; table error %.2e (E <= 1), %.2e relative (E > 1)\n",
              highest, worst_table, worst_over_one);
}

// A scene without the extensions pays nothing and changes nothing: zero weights leave the
// layered paths untaken, and the BSDF's values are the base's exactly.
TEST(ClearcoatSheen, NoLayerLeavesTheBaseUnchanged) {
  const BsdfLobes plain = dielectric(0.5f, 0.4f);
  EXPECT_FALSE(plain.layers.present());
  BsdfLobes zero = plain;
  zero.layers.clearcoat_alpha = 0.3f;  // a roughness without a weight is no coat
  const Bsdf a(kNormal, plain), b(kNormal, zero);
  const V3f wo = view_at(0.6f), wi = normalize(V3f(-0.3f, 0.2f, 0.8f));
  EXPECT_EQ(a.eval(wo, wi), b.eval(wo, wi));
  EXPECT_EQ(a.pdf(wo, wi), b.pdf(wo, wi));
  EXPECT_EQ(a.flags(), b.flags());
}

}  // namespace
}  // namespace prism
