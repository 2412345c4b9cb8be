// Stress case 2: re-intersection, after pbrt-v4's Reintersect tests. Spheres and triangles of
// every size, scaled and moved far from the origin, are hit by one ray each; from that hit,
// 1000 rays leave into the hemisphere of the normal on the chosen side, from
// offset_ray_origin(hit.position, normal). None may hit the same surface again. Each scene
// holds that one surface, so any hit at all is a re-hit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/geometry/embree_scene.h"
#include "renderer/math.h"

namespace prism {
namespace {

constexpr int kRaysPerHit = 1000;

class Sampler {
 public:
  explicit Sampler(uint64_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  double pow10(double lo, double hi) { return std::pow(10.0, uniform(lo, hi)); }
  double sign() { return uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0; }
  // Uniform on the unit sphere (Archimedes: z uniform, azimuth uniform).
  V3d direction() {
    const double z = uniform(-1.0, 1.0);
    const double phi = uniform(0.0, 2.0 * M_PI);
    const double s = std::sqrt(std::fmax(0.0, 1.0 - z * z));
    return V3d(s * std::cos(phi), s * std::sin(phi), z);
  }
  // Uniform in the unit ball.
  V3d in_ball() { return std::cbrt(uniform(0.0, 1.0)) * direction(); }

 private:
  std::mt19937_64 rng_;
};

V3f to_f(const V3d& v) {
  return V3f(float(v.x), float(v.y), float(v.z));
}

struct Tally {
  int surfaces = 0;  // surfaces drawn
  int hit = 0;       // surfaces the first ray found (the others are below float resolution)
  long rays = 0;
  long rehits = 0;
  std::string first_failure;
};

// Spawns kRaysPerHit rays from hit into the hemisphere of `side` and counts any hit.
void spawn_and_count(const EmbreeScene& geometry, const SurfaceHit& hit, const V3f& side,
                     Sampler* sampler, Tally* tally, const std::string& what) {
  const V3f origin = offset_ray_origin(hit.position, side, hit.surface_error);
  for (int k = 0; k < kRaysPerHit; ++k) {
    V3f w = to_f(sampler->direction());
    if (dot(w, side) < 0.0f) w = -w;
    if (dot(w, side) == 0.0f) continue;  // exactly in the tangent plane: no side to leave on
    Ray out;
    out.origin = origin;
    out.direction = w;
    ++tally->rays;
    SurfaceHit again;
    if (geometry.intersect(out, &again)) {
      if (tally->rehits == 0) {
        char buffer[512];
        std::snprintf(buffer, sizeof buffer,
                      "%s: p (%.9g %.9g %.9g) n (%.7g %.7g %.7g) w (%.7g %.7g %.7g) t %.9g",
                      what.c_str(), hit.position.x, hit.position.y, hit.position.z, side.x, side.y,
                      side.z, w.x, w.y, w.z, again.t);
        tally->first_failure = buffer;
      }
      ++tally->rehits;
    }
  }
}

void print(const char* name, const Tally& t) {
  std::printf("%-24s surfaces %5d  hit %5d  rays %8ld  re-hits %ld\n", name, t.surfaces, t.hit,
              t.rays, t.rehits);
  if (t.rehits) std::printf("  first: %s\n", t.first_failure.c_str());
}

// A sphere of radius 10^U(-4,4), scaled by 10^U(-4,4) and moved by up to 1e8 per axis (a
// log-uniform magnitude, so every scale from 1e-4 to 1e8 is drawn as often), hit from a
// random point 1.1 to 1000 radii away. The spawned rays leave into the outward hemisphere:
// a convex surface can never be met again from there.
Tally sphere_reintersect(const SphereOptions& spheres, int count, uint64_t seed) {
  Sampler s(seed);
  Tally tally;
  for (int i = 0; i < count; ++i) {
    const double radius = s.pow10(-4, 4) * s.pow10(-4, 4);
    const V3d centre(s.sign() * s.pow10(-4, 8), s.sign() * s.pow10(-4, 8),
                     s.sign() * s.pow10(-4, 8));
    SceneDescription scene;
    scene.spheres.push_back(Sphere{centre, radius, -1, "s"});
    GeometryOptions options;
    options.spheres = spheres;
    const EmbreeScene geometry(scene, options);
    ++tally.surfaces;
    const V3d from = centre + radius * s.pow10(std::log10(1.1), 3) * s.direction();
    const V3d to = centre + 0.99 * radius * s.in_ball();
    Ray ray;
    ray.origin = to_f(from);
    ray.direction = to_f((to - V3d(ray.origin.x, ray.origin.y, ray.origin.z)).normalized());
    SurfaceHit hit;
    if (!geometry.intersect(ray, &hit)) continue;
    ++tally.hit;
    char what[160];
    std::snprintf(what, sizeof what, "sphere c (%.9g %.9g %.9g) r %.9g", centre.x, centre.y,
                  centre.z, radius);
    spawn_and_count(geometry, hit, hit.geometric_normal, &s, &tally, what);
  }
  return tally;
}

// pbrt's triangle: vertex coordinates 10^U(-8,8) with random signs, then a random per-axis
// scale 10^U(-4,4) and translation as for the spheres, baked into world space. The first
// ray aims at a random barycentric point from up to 1e8 away; the spawned rays leave on the
// side the first ray came from (a triangle has nothing behind either side).
enum class TriangleNormal { renderer, exact };

Tally triangle_reintersect(int count, uint64_t seed, bool robust, TriangleNormal normal) {
  Sampler s(seed);
  Tally tally;
  for (int i = 0; i < count; ++i) {
    Mesh mesh;
    Primitive p;
    for (int v = 0; v < 3; ++v) {
      p.positions.push_back(to_f(
          V3d(s.sign() * s.pow10(-8, 8), s.sign() * s.pow10(-8, 8), s.sign() * s.pow10(-8, 8))));
    }
    p.indices = {0, 1, 2};
    mesh.primitives.push_back(p);
    M44d transform;
    transform.setScale(V3d(s.pow10(-4, 4), s.pow10(-4, 4), s.pow10(-4, 4)));
    transform[3][0] = s.sign() * s.pow10(-4, 8);
    transform[3][1] = s.sign() * s.pow10(-4, 8);
    transform[3][2] = s.sign() * s.pow10(-4, 8);
    SceneDescription scene;
    scene.meshes.push_back(mesh);
    scene.instances.push_back({0, transform, "t"});
    GeometryOptions options;
    options.robust = robust;
    const EmbreeScene geometry(scene, options);
    ++tally.surfaces;
    // The world-space vertices as Embree holds them, for aiming.
    V3d world[3];
    for (int v = 0; v < 3; ++v) {
      V3d w;
      transform.multVecMatrix(V3d(p.positions[v]), w);
      world[v] = V3d(to_f(w));
    }
    double b1 = s.uniform(0, 1), b2 = s.uniform(0, 1);
    if (b1 + b2 > 1.0) {
      b1 = 1.0 - b1;
      b2 = 1.0 - b2;
    }
    const V3d to = (1.0 - b1 - b2) * world[0] + b1 * world[1] + b2 * world[2];
    const V3d from = to + s.pow10(-4, 8) * s.direction();
    Ray ray;
    ray.origin = to_f(from);
    ray.direction = to_f((to - V3d(ray.origin.x, ray.origin.y, ray.origin.z)).normalized());
    SurfaceHit hit;
    if (!geometry.intersect(ray, &hit)) continue;
    ++tally.hit;
    char what[256];
    std::snprintf(what, sizeof what, "triangle (%.9g %.9g %.9g) (%.9g %.9g %.9g) (%.9g %.9g %.9g)",
                  world[0].x, world[0].y, world[0].z, world[1].x, world[1].y, world[1].z,
                  world[2].x, world[2].y, world[2].z);
    // The normal the spawned rays leave around: the renderer's, or the exact normal of the
    // float triangle, worked out in double.
    const V3f n = normal == TriangleNormal::renderer
                      ? hit.geometric_normal
                      : to_f((world[1] - world[0]).cross(world[2] - world[0]).normalized());
    spawn_and_count(geometry, hit, face_forward(n, -ray.direction), &s, &tally, what);
  }
  return tally;
}

TEST(StressReintersect, SpheresAnalytic) {
  const Tally t = sphere_reintersect({SphereMode::analytic, 0}, 1000, 0x5eed0001);
  print("spheres analytic", t);
  EXPECT_GT(t.hit, t.surfaces / 2);
  EXPECT_EQ(t.rehits, 0) << t.first_failure;
}

TEST(StressReintersect, SpheresEmbreePoints) {
  const Tally t = sphere_reintersect({SphereMode::embree_points, 0}, 1000, 0x5eed0002);
  print("spheres embree-points", t);
  EXPECT_GT(t.hit, t.surfaces / 2);
  EXPECT_EQ(t.rehits, 0) << t.first_failure;
}

TEST(StressReintersect, SpheresMesh) {
  const Tally t = sphere_reintersect({SphereMode::mesh, 3}, 300, 0x5eed0003);
  print("spheres mesh:3", t);
  EXPECT_GT(t.hit, t.surfaces / 2);
  EXPECT_EQ(t.rehits, 0) << t.first_failure;
}

// pbrt's triangles include slivers a few ulps wide and 1e7 long. Only Embree's watertight
// test (GeometryOptions::robust) puts such a triangle's plane where its float vertices say;
// the default Moller-Trumbore test reports hits up to ~100 units off it, which no offset
// proportional to the hit point's own precision can clear. The default mode's count is
// printed for docs/stress-geometry.md, not asserted.
TEST(StressReintersect, TrianglesRobustWithTheRenderersNormal) {
  const Tally fast = triangle_reintersect(1000, 0x5eed0004, false, TriangleNormal::renderer);
  print("triangles default flag", fast);
  const Tally t = triangle_reintersect(1000, 0x5eed0004, true, TriangleNormal::renderer);
  print("triangles robust", t);
  EXPECT_GT(t.hit, t.surfaces / 2);
  // SurfaceHit::geometric_normal is Embree's float Ng, the cross product of two float edges:
  // for a sliver it cancels to a wrong direction or to zero. Needs the exact normal below
  // computed in renderer/geometry/mesh_preparation.cpp (docs/stress-geometry.md, case 2).
  EXPECT_EQ(t.rehits, 0) << t.first_failure;
}

// The same triangles with the normal the hit should report: the float triangle's own,
// computed in double.
TEST(StressReintersect, TrianglesRobustWithTheExactNormal) {
  const Tally t = triangle_reintersect(1000, 0x5eed0004, true, TriangleNormal::exact);
  print("triangles robust, exact n", t);
  EXPECT_GT(t.hit, t.surfaces / 2);
  EXPECT_EQ(t.rehits, 0) << t.first_failure;
}

}  // namespace
}  // namespace prism
