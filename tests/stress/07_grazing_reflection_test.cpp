// Stress case 7: grazing reflection. Rays arrive 89.9 degrees off the normal on a large quad
// (axis-aligned at the origin, and tilted and moved far away) and on big spheres (all three
// modes); the mirror ray leaves from offset_ray_origin(hit.position, n) only 0.1 degrees
// above the surface. Each scene holds the one convex surface, so any hit is surface acne.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "renderer/geometry/embree_scene.h"
#include "renderer/math.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {
namespace {

constexpr double kGrazing = 89.9 * M_PI / 180.0;
constexpr int kPoints = 20000;

V3f to_f(const V3d& v) {
  return V3f(float(v.x), float(v.y), float(v.z));
}

struct Acne {
  int reflected = 0;
  int rehits = 0;
};

// Shoots one grazing ray at each sampled surface point (point, unit normal) and counts
// reflected rays that hit anything.
template <typename SamplePoint>
Acne grazing(const EmbreeScene& g, SamplePoint&& sample, double approach, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Acne acne;
  for (int i = 0; i < kPoints; ++i) {
    V3d p, n;
    sample(rng, &p, &n);
    // A tangent direction at random azimuth.
    const V3d helper = std::fabs(n.x) < 0.9 ? V3d(1, 0, 0) : V3d(0, 1, 0);
    const V3d t1 = n.cross(helper).normalized(), t2 = n.cross(t1);
    const double phi = 2.0 * M_PI * u(rng);
    const V3d tangent = std::cos(phi) * t1 + std::sin(phi) * t2;
    const V3d d = std::sin(kGrazing) * tangent - std::cos(kGrazing) * n;
    Ray ray;
    ray.origin = to_f(p - approach * d);
    ray.direction = to_f(d);
    SurfaceHit hit;
    if (!g.intersect(ray, &hit)) continue;
    const V3f side = face_forward(hit.geometric_normal, -ray.direction);
    Ray out;
    out.origin = offset_ray_origin(hit.position, side, hit.surface_error);
    out.direction = normalize(reflect(ray.direction, side));
    ++acne.reflected;
    SurfaceHit again;
    const bool rehit = g.intersect(out, &again);
    acne.rehits += rehit;
  }
  return acne;
}

TEST(StressGrazingReflection, LargeQuads) {
  struct QuadCase {
    const char* name;
    M44d transform;
  };
  M44d tilted;
  tilted.setEulerAngles(V3d(0.7, -0.4, 1.1));
  tilted[3][0] = 1e3;
  tilted[3][1] = -2e3;
  tilted[3][2] = 500.0;
  const QuadCase cases[] = {{"axis-aligned at 0", M44d()}, {"tilted at 1e3", tilted}};
  std::printf("%-20s %10s %8s\n", "quad", "reflected", "re-hits");
  for (const QuadCase& c : cases) {
    SCOPED_TRACE(c.name);
    // A 2e4 x 2e4 quad in its own xy plane, front +z.
    Mesh mesh;
    Primitive prim;
    const float h = 1e4f;
    prim.positions = {V3f(-h, -h, 0), V3f(h, -h, 0), V3f(h, h, 0), V3f(-h, h, 0)};
    prim.indices = {0, 1, 2, 0, 2, 3};
    mesh.primitives.push_back(prim);
    SceneDescription scene;
    scene.meshes = {mesh};
    scene.instances = {{0, c.transform, "quad"}};
    const EmbreeScene g(scene, {});
    V3d normal;
    c.transform.multDirMatrix(V3d(0, 0, 1), normal);
    normal.normalize();
    const Acne acne = grazing(
        g,
        [&](std::mt19937_64& rng, V3d* p, V3d* n) {
          std::uniform_real_distribution<double> u(-0.9 * h, 0.9 * h);
          c.transform.multVecMatrix(V3d(u(rng), u(rng), 0.0), *p);
          *n = normal;
        },
        100.0, 0x7a1);
    std::printf("%-20s %10d %8d\n", c.name, acne.reflected, acne.rehits);
    EXPECT_GT(acne.reflected, kPoints * 9 / 10);
    EXPECT_EQ(acne.rehits, 0);
  }
}

TEST(StressGrazingReflection, BigSpheres) {
  std::printf("%-14s %8s %10s %10s %8s\n", "mode", "radius", "centre", "reflected", "re-hits");
  for (const SphereOptions& mode :
       {SphereOptions{SphereMode::analytic, 0}, SphereOptions{SphereMode::embree_points, 0},
        SphereOptions{SphereMode::mesh, 6}}) {
    for (const auto& [radius, centre] :
         {std::pair{1e3, V3d(0, 0, 0)}, std::pair{1e5, V3d(0, 0, -1e5)},
          std::pair{1e3, V3d(3e4, -2e4, 1e4)}}) {
      SCOPED_TRACE(testing::Message() << to_string(mode) << " r " << radius);
      SceneDescription scene;
      scene.spheres.push_back(Sphere{centre, radius, -1, "ball"});
      GeometryOptions options;
      options.spheres = mode;
      const EmbreeScene g(scene, options);
      // The mesh lies inside the sphere by more than a ray 0.1 degrees off its tangent
      // plane dips below it, so for the mesh the grazed points and normals are its facets'.
      const Primitive facets = tessellate_sphere(scene.spheres[0], mode.mesh_level);
      const bool is_mesh = mode.mode == SphereMode::mesh;
      const Acne acne = grazing(
          g,
          [&](std::mt19937_64& rng, V3d* p, V3d* n) {
            std::uniform_real_distribution<double> u(-1.0, 1.0);
            if (is_mesh) {
              const size_t tri =
                  std::uniform_int_distribution<size_t>(0, facets.indices.size() / 3 - 1)(rng);
              const V3d a(facets.positions[facets.indices[3 * tri]]);
              const V3d b(facets.positions[facets.indices[3 * tri + 1]]);
              const V3d c(facets.positions[facets.indices[3 * tri + 2]]);
              double s = 0.5 * (u(rng) + 1.0), t = 0.5 * (u(rng) + 1.0);
              if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
              *p = a + s * (b - a) + t * (c - a);
              *n = (b - a).cross(c - a).normalized();
              return;
            }
            V3d w;
            do w = V3d(u(rng), u(rng), u(rng));
            while (w.length2() > 1.0 || w.length2() < 1e-3);
            *n = w.normalized();
            *p = centre + radius * *n;
          },
          // Come from 1e-3 r away: the chord at 89.9 degrees is only 3.5e-3 r long, and
          // a level-6 facet is ~0.02 r across.
          1e-3 * radius, 0x7a2);
      std::printf("%-14s %8.0e %10.0e %10d %8d\n", to_string(mode).c_str(), radius, centre.length(),
                  acne.reflected, acne.rehits);
      EXPECT_GT(acne.reflected, kPoints / 2);
      EXPECT_EQ(acne.rehits, 0);
    }
  }
}

}  // namespace
}  // namespace prism
