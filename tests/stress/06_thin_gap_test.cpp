// Stress case 6: two parallel quads a gap g apart, at height z. A gap counts as resolved
// when both hold:
//   - every ray from above (straight down and up to 60 degrees off) reports the top quad;
//   - every ray leaving a hit on the lower quad upward (same angles), from
//     offset_ray_origin(hit.position, +z), reports the top quad: neither the lower quad
//     again nor nothing.
// The quads carry different materials, so a hit says which one it found even when float
// rounding puts both in one plane. The smallest resolved power of two and power of ten are
// measured at z = +-1, +-1e3, +-1e6 and asserted: they follow from the offset (257 ulps of
// z, see renderer/math.h) and must not creep up.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "renderer/geometry/embree_scene.h"
#include "renderer/math.h"

namespace prism {
namespace {

constexpr int kLower = 0, kUpper = 1;

Mesh quad(double z, double half, int material) {
  Mesh mesh;
  Primitive p;
  const float zf = float(z), h = float(half);
  p.positions = {V3f(-h, -h, zf), V3f(h, -h, zf), V3f(h, h, zf), V3f(-h, h, zf)};
  p.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise from +z: front face up
  p.material = material;
  mesh.primitives.push_back(p);
  return mesh;
}

// Directions within 60 degrees of +z (up = true) or -z.
V3f direction(std::mt19937_64& rng, bool up) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double cos_t = 1.0 - u(rng) * 0.5;  // uniform in solid angle down to cos = 0.5
  const double phi = 2.0 * M_PI * u(rng);
  const double sin_t = std::sqrt(1.0 - cos_t * cos_t);
  return V3f(float(sin_t * std::cos(phi)), float(sin_t * std::sin(phi)),
             float(up ? cos_t : -cos_t));
}

bool resolved(double z, double gap) {
  // The quads reach well beyond where any ray can cross them: 60 degrees over a gap g
  // travels 1.8 g sideways, and rays start within half the half-size of the centre.
  const double half = std::max(1.0, 8.0 * gap);
  SceneDescription scene;
  scene.meshes = {quad(z, half, kLower), quad(z + gap, half, kUpper)};
  scene.instances = {{0, M44d(), "lower"}, {1, M44d(), "upper"}};
  const EmbreeScene geometry(scene, {});
  std::mt19937_64 rng(0x6a9);
  std::uniform_real_distribution<double> xy(-0.5 * half, 0.5 * half);
  for (int i = 0; i < 500; ++i) {
    const V3f d = direction(rng, false);
    const float x = float(xy(rng)), y = float(xy(rng));
    Ray down;
    down.direction = d;
    // Start one gap above the top, back along the direction.
    const double above = gap;
    down.origin = V3f(x, y, float(z + gap + above)) - float(above / -d.z) * d;
    SurfaceHit hit;
    if (!geometry.intersect(down, &hit) || hit.material != kUpper) return false;

    // A hit on the lower quad: from below, going up.
    Ray from_below;
    from_below.origin = V3f(x, y, float(z - above));
    from_below.direction = V3f(0, 0, 1);
    if (!geometry.intersect(from_below, &hit) || hit.material != kLower) return false;
    Ray leave;
    leave.origin = offset_ray_origin(hit.position, V3f(0, 0, 1));
    leave.direction = direction(rng, true);
    SurfaceHit next;
    if (!geometry.intersect(leave, &next) || next.material != kUpper) return false;
  }
  return true;
}

// The smallest gap base^k (k from lowest up) such that it and every larger one up to 2^40
// is resolved.
double smallest_resolved(double z, double base, int lowest) {
  double best = 0.0;
  for (int k = int(std::log(1e12) / std::log(base)); k >= lowest; --k) {
    const double g = std::pow(base, k);
    if (!resolved(z, g)) break;
    best = g;
  }
  return best;
}

TEST(StressThinGap, SmallestResolvedGapFollowsTheOffset) {
  struct Expected {
    double z;
    double pow2;
    double pow10;
  };
  // ulp(z) * 257 is the offset; the top quad must lie strictly above the moved origin
  // (Embree's tnear is open for triangles at t = 0 only by luck of rounding), so the first
  // power of two above 257 ulps, and the first power of ten above it.
  const Expected expected[] = {{1.0, 0x1p-14, 1e-4}, {-1.0, 0x1p-14, 1e-4}, {1e3, 0x1p-5, 0.1},
                               {-1e3, 0x1p-5, 0.1},  {1e6, 32.0, 100.0},    {-1e6, 32.0, 100.0}};
  std::printf("%8s %14s %14s %14s\n", "z", "257 ulp(z)", "smallest 2^k", "smallest 10^k");
  for (const Expected& e : expected) {
    SCOPED_TRACE(testing::Message() << "z " << e.z);
    const double p2 = smallest_resolved(e.z, 2.0, -40);
    const double p10 = smallest_resolved(e.z, 10.0, -12);
    std::printf("%8.0e %14.6g %14.6g %14.6g\n", e.z, 257.0 * ulp_of(float(e.z)), p2, p10);
    EXPECT_EQ(p2, e.pow2);
    EXPECT_EQ(p10, e.pow10);
  }
}

}  // namespace
}  // namespace prism
