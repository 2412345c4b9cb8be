// Fresnel, refraction, the ray offset and the material mapping's energy bounds.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "renderer/math.h"
#include "renderer/shading/material.h"

namespace prism {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Fresnel, DielectricValuesAndTotalInternalReflection) {
  float cos_t = 0.0f;
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f, &cos_t), 0.04f, 1e-6f);
  EXPECT_FLOAT_EQ(cos_t, 1.0f);
  EXPECT_NEAR(fresnel_dielectric(std::cos(45.0 * kDeg), 1.5f, &cos_t), 0.0502, 5e-5);
  EXPECT_NEAR(std::acos(cos_t) / kDeg, 28.1255, 1e-3);
  EXPECT_EQ(fresnel_dielectric(std::cos(45.0 * kDeg), 1.0f / 1.5f, &cos_t), 1.0f);  // TIR
  EXPECT_EQ(cos_t, 0.0f);
  EXPECT_NEAR(fresnel_dielectric(std::cos(10.0 * kDeg), 1.0f / 1.5f, &cos_t), 0.0401, 5e-5);
  EXPECT_NEAR(std::acos(cos_t) / kDeg, 15.0981, 1e-3);
  // A negative cosine means the light arrives from the other side: eta is inverted.
  EXPECT_FLOAT_EQ(fresnel_dielectric(-std::cos(10.0f * kDeg), 1.5f),
                  fresnel_dielectric(std::cos(10.0f * kDeg), 1.0f / 1.5f));
}

// The inline neighbours the ray offset uses must be exactly std::nextafter's, across signs,
// zeros, subnormals, the largest finite float and the infinities.
TEST(NextFloat, MatchesNextafterEverywhere) {
  const float inf = std::numeric_limits<float>::infinity();
  const float values[] = {0.0f,
                          -0.0f,
                          std::numeric_limits<float>::denorm_min(),
                          -std::numeric_limits<float>::denorm_min(),
                          1e-40f,
                          -1e-40f,
                          std::numeric_limits<float>::min(),
                          1.0f,
                          -1.0f,
                          0.1f,
                          -3.5e7f,
                          std::numeric_limits<float>::max(),
                          -std::numeric_limits<float>::max(),
                          inf,
                          -inf};
  for (float x : values) {
    EXPECT_EQ(std::bit_cast<uint32_t>(next_float_up(x)),
              std::bit_cast<uint32_t>(std::nextafter(x, inf)))
        << x;
    EXPECT_EQ(std::bit_cast<uint32_t>(next_float_down(x)),
              std::bit_cast<uint32_t>(std::nextafter(x, -inf)))
        << x;
  }
}

TEST(InlineMinMax, GivesLibmsBitsForEveryKindOfInput) {
  // The shading code's fmax_inline/fmin_inline replace std::fmax/std::fmin without changing
  // an image: same bits as libm's, signed zeros and NaNs included. `volatile` keeps the
  // compiler from folding std::fmax with its own rules instead of calling libm.
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float denormal = std::numeric_limits<float>::denorm_min();
  const float values[] = {
      0.0f,     -0.0f,     1.0f, -1.0f, 0.5f, 1e-30f, -1e30f,
      denormal, -denormal, inf,  -inf,  nan,  -nan,   std::numeric_limits<float>::max()};
  int compared = 0;
  for (float a : values)
    for (float b : values) {
      volatile float va = a, vb = b;
      const float lib_max = std::fmax(va, vb), lib_min = std::fmin(va, vb);
      const float our_max = fmax_inline(a, b), our_min = fmin_inline(a, b);
      if (std::isnan(lib_max)) {
        EXPECT_TRUE(std::isnan(our_max)) << a << " " << b;
      } else {
        EXPECT_EQ(std::bit_cast<uint32_t>(our_max), std::bit_cast<uint32_t>(lib_max))
            << "fmax(" << a << ", " << b << ")";
      }
      if (std::isnan(lib_min)) {
        EXPECT_TRUE(std::isnan(our_min)) << a << " " << b;
      } else {
        EXPECT_EQ(std::bit_cast<uint32_t>(our_min), std::bit_cast<uint32_t>(lib_min))
            << "fmin(" << a << ", " << b << ")";
      }
      ++compared;
    }
  EXPECT_EQ(compared, 14 * 14);
  // The cases where the C standard leaves the answer open: libm's is the first argument.
  EXPECT_FALSE(std::signbit(fmax_inline(0.0f, -0.0f)));
  EXPECT_TRUE(std::signbit(fmax_inline(-0.0f, 0.0f)));
  EXPECT_TRUE(std::signbit(fmin_inline(-0.0f, 0.0f)));
  EXPECT_EQ(fmax_inline(nan, 2.0f), 2.0f);
  EXPECT_EQ(fmin_inline(2.0f, nan), 2.0f);
}

TEST(Refraction, FollowsSnellsLaw) {
  for (double angle : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0}) {
    for (float eta : {1.5f, 1.0f / 1.5f, 1.33f}) {
      const V3f d(static_cast<float>(std::sin(angle * kDeg)),
                  static_cast<float>(-std::cos(angle * kDeg)), 0.0f);
      V3f t;
      const double sin_t_expected = std::sin(angle * kDeg) / eta;
      const bool refracted = refract(d, V3f(0, 1, 0), eta, &t);
      EXPECT_EQ(refracted, sin_t_expected < 1.0) << angle << " " << eta;
      if (!refracted) continue;
      EXPECT_NEAR(t.length(), 1.0f, 1e-6f);
      EXPECT_NEAR(t.x, sin_t_expected, 1e-5) << angle << " " << eta;  // sin(theta_t)
      EXPECT_LT(t.y, 0.0f);  // continues through the surface
    }
  }
}

TEST(RayOffset, MovesOffTheSurfaceByAFewUlpsAtAnyScale) {
  for (float scale : {1e-3f, 1.0f, 1e3f, 1e6f}) {
    const V3f p(scale, -scale, 0.5f * scale);
    const V3f n(0.0f, 1.0f, 0.0f);
    const V3f q = offset_ray_origin(p, n);
    EXPECT_GT(q.y, p.y) << scale;  // moved to the normal's side
    EXPECT_EQ(q.x, p.x);           // and nowhere else
    // By a bounded number of ulps of the coordinate (256 here).
    EXPECT_LE(std::fabs(q.y - p.y), 300.0f * std::fabs(std::nextafter(p.y, 0.0f) - p.y) + 1e-4f);
  }
  // Near the origin the absolute offset of 2^-16 takes over from the vanishing ulps.
  const V3f q = offset_ray_origin(V3f(0.0f), V3f(0.0f, 0.0f, -1.0f));
  EXPECT_FLOAT_EQ(q.z, -1.0f / 65536.0f);
}

TEST(MaterialMapping, PhongExponentFromRoughness) {
  EXPECT_EQ(phong_exponent_from_roughness(1.0f), 0.0f);
  // Walter's n_H = 2 / alpha^2 - 2 for (N.H)^n, a quarter of it for (R.V)^n: 7.5 at alpha 1/4.
  EXPECT_NEAR(phong_exponent_from_roughness(0.5f), (2.0f / 0.0625f - 2.0f) / 4.0f, 1e-3f);
  EXPECT_EQ(phong_exponent_from_roughness(0.0f), kMaxPhongExponent);
}

// The normalised Phong lobe (n + 2) / (2 pi) cos^n(alpha), integrated against the cosine of
// the incident angle, reflects at most all of the light; at normal incidence exactly all.
TEST(MaterialMapping, NormalisedPhongLobeNeverCreatesEnergy) {
  for (float n : {0.0f, 1.0f, 10.0f, 100.0f}) {
    // At normal incidence R = N, so alpha = theta: integral of (n+2)/(2pi) cos^(n+1) dw = 1.
    double sum = 0.0;
    const int steps = 20000;
    for (int i = 0; i < steps; ++i) {
      const double theta = (i + 0.5) / steps * (std::numbers::pi / 2);
      sum += (n + 2.0) / (2.0 * std::numbers::pi) * std::pow(std::cos(theta), n + 1.0) *
             std::sin(theta) * 2.0 * std::numbers::pi * (std::numbers::pi / 2 / steps);
    }
    EXPECT_NEAR(sum, 1.0, 1e-4) << n;
  }
}

// A white material, whatever its metallic, transmission, ior and roughness, reflects at most
// what it receives from a uniform surround at every viewing angle (Bsdf::albedo, the
// ambient term's k_a), and a white dielectric exactly all of it.
TEST(MaterialMapping, WhiteSurfaceNeverReflectsMoreThanItReceives) {
  const V3f n(0.0f, 0.0f, 1.0f);
  for (float metallic : {0.0f, 0.3f, 1.0f})
    for (float transmission : {0.0f, 0.5f, 1.0f})
      for (float ior : {1.0f, 1.5f, 2.4f})
        for (float roughness : {0.0f, 0.3f, 1.0f})
          for (float cos_v : {1.0f, 0.5f, 0.05f}) {
            Material m;
            m.metallic = metallic;
            m.transmission = transmission;
            m.ior = ior;
            m.roughness = roughness;
            const SurfaceResponse r = evaluate(m, SurfaceHit{});
            const V3f wo(std::sqrt(1.0f - cos_v * cos_v), 0.0f, cos_v);
            const float total = r.bsdf.albedo(wo, n, false, AlbedoScope::all_lobes).x;
            EXPECT_LE(total, 1.0f + 1e-5f) << metallic << " " << transmission << " " << ior << " "
                                           << roughness << " " << cos_v;
            if (metallic == 0.0f) {
              EXPECT_NEAR(total, 1.0f, 1e-5f) << transmission << " " << ior << " " << roughness;
            }
            EXPECT_GE(r.bsdf.lobes().diffuse_albedo.x, 0.0f);
          }
  // Plain white dielectric: F0 0.04 from ior 1.5, the base white Lambert under it.
  Material white;
  white.metallic = 0.0f;
  const SurfaceResponse r = evaluate(white, SurfaceHit{});
  EXPECT_NEAR(r.bsdf.lobes().dielectric_f0.x, 0.04f, 1e-6f);
  EXPECT_NEAR(r.bsdf.lobes().diffuse_albedo.x, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace prism
