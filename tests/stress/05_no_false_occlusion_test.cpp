// Stress case 5: no false occlusion. Shadow rays between points on two surfaces that see
// each other must all come back unoccluded: two facing quads, and a floor quad under a
// sphere (all three sphere modes), each moved by an offset and scaled, at
// (offset, scale) = (0, 1), (1e3, 1), (0, 1e-3), (1e4, 1e3). The points are real hits,
// rebuilt by EmbreeScene as the integrators get them; the ray leaves one point offset to
// its side and ends at the other point offset to its side, as a shadow ray to a light on a
// surface would.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/geometry/embree_scene.h"
#include "renderer/math.h"

namespace prism {
namespace {

struct Placement {
  double offset;
  double scale;
};

const Placement kPlacements[] = {{0.0, 1.0}, {1e3, 1.0}, {0.0, 1e-3}, {1e4, 1e3}};
const V3d kOffsetAxis(1.0, -0.75, 0.5);  // no component zero, so every coordinate is moved

M44d placement(const Placement& p) {
  M44d m;
  m.setScale(p.scale);
  const V3d t = p.offset * kOffsetAxis;
  m[3][0] = t.x;
  m[3][1] = t.y;
  m[3][2] = t.z;
  return m;
}

V3d place(const Placement& p, const V3d& local) {
  return p.scale * local + p.offset * kOffsetAxis;
}

// A 2 x 2 quad in the plane z = height, its front face toward +z or -z.
Mesh quad(double height, bool faces_up) {
  Mesh mesh;
  Primitive p;
  const float h = float(height);
  p.positions = {V3f(-1, -1, h), V3f(1, -1, h), V3f(1, 1, h), V3f(-1, 1, h)};
  p.indices =
      faces_up ? std::vector<uint32_t>{0, 1, 2, 0, 2, 3} : std::vector<uint32_t>{0, 2, 1, 0, 3, 2};
  mesh.primitives.push_back(p);
  return mesh;
}

// A hit on the surface under local point `local`, found by a ray from `from_local`.
bool surface_point(const EmbreeScene& g, const Placement& pl, const V3d& from_local,
                   const V3d& local, SurfaceHit* hit) {
  Ray ray;
  ray.origin = V3f(place(pl, from_local));
  ray.direction = V3f((place(pl, local) - V3d(ray.origin)).normalized());
  return g.intersect(ray, hit);
}

struct Count {
  int pairs = 0;
  int occluded = 0;
};

// The shadow ray from a to b, both offset toward each other.
bool blocked(const EmbreeScene& g, const SurfaceHit& a, const SurfaceHit& b) {
  const V3f ab = b.position - a.position;
  const V3f from =
      offset_ray_origin(a.position, face_forward(a.geometric_normal, ab), a.surface_error);
  const V3f to =
      offset_ray_origin(b.position, face_forward(b.geometric_normal, -ab), b.surface_error);
  Ray ray;
  ray.origin = from;
  ray.direction = normalize(to - from);
  ray.tfar = (to - from).length();
  return g.occluded(ray);
}

TEST(StressNoFalseOcclusion, FacingQuads) {
  std::mt19937_64 rng(0x0cc1);
  std::uniform_real_distribution<double> u(-0.95, 0.95);
  std::printf("%8s %8s %7s %9s\n", "offset", "scale", "pairs", "occluded");
  for (const Placement& pl : kPlacements) {
    SCOPED_TRACE(testing::Message() << "offset " << pl.offset << " scale " << pl.scale);
    SceneDescription scene;
    scene.meshes = {quad(0.0, true), quad(1.0, false)};
    scene.instances = {{0, placement(pl), "floor"}, {1, placement(pl), "ceiling"}};
    const EmbreeScene g(scene, {});
    Count c;
    for (int i = 0; i < 3000; ++i) {
      SurfaceHit a, b;
      ASSERT_TRUE(surface_point(g, pl, V3d(0, 0, 0.5), V3d(u(rng), u(rng), 0.0), &a));
      ASSERT_TRUE(surface_point(g, pl, V3d(0, 0, 0.5), V3d(u(rng), u(rng), 1.0), &b));
      ++c.pairs;
      c.occluded += blocked(g, a, b);
      c.occluded += blocked(g, b, a);
    }
    std::printf("%8.0e %8.0e %7d %9d\n", pl.offset, pl.scale, c.pairs, c.occluded);
    EXPECT_EQ(c.occluded, 0);
  }
}

TEST(StressNoFalseOcclusion, QuadAndSphere) {
  std::printf("%-14s %8s %8s %7s %9s\n", "mode", "offset", "scale", "pairs", "occluded");
  for (const SphereOptions& mode :
       {SphereOptions{SphereMode::analytic, 0}, SphereOptions{SphereMode::embree_points, 0},
        SphereOptions{SphereMode::mesh, 5}}) {
    std::mt19937_64 rng(0x0cc2);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const Placement& pl : kPlacements) {
      SCOPED_TRACE(testing::Message()
                   << to_string(mode) << " offset " << pl.offset << " scale " << pl.scale);
      // Floor at z = 0 (2 x 2), a sphere of radius 0.5 centred 1 above it.
      SceneDescription scene;
      scene.meshes = {quad(0.0, true)};
      scene.instances = {{0, placement(pl), "floor"}};
      scene.spheres.push_back(Sphere{place(pl, V3d(0, 0, 1)), 0.5 * pl.scale, -1, "ball"});
      GeometryOptions options;
      options.spheres = mode;
      const EmbreeScene g(scene, options);
      Count c;
      while (c.pairs < 3000) {
        const V3d floor_point(0.95 * u(rng), 0.95 * u(rng), 0.0);
        V3d w(u(rng), u(rng), u(rng));
        if (w.length2() > 1.0 || w.length2() < 1e-3) continue;
        w.normalize();
        // A point on the lower half of the sphere that the floor point sees above its
        // tangent plane, and that sees the floor point (z > 0 from the floor).
        const V3d ball_point = V3d(0, 0, 1) + 0.5 * w;
        if ((floor_point - ball_point).dot(w) < 0.05 * (floor_point - ball_point).length())
          continue;
        SurfaceHit a, b;
        ASSERT_TRUE(surface_point(g, pl, V3d(floor_point.x, floor_point.y, 0.2), floor_point, &a));
        if (!surface_point(g, pl, ball_point + 0.2 * w, ball_point, &b)) continue;
        ++c.pairs;
        c.occluded += blocked(g, a, b);
        c.occluded += blocked(g, b, a);
      }
      std::printf("%-14s %8.0e %8.0e %7d %9d\n", to_string(mode).c_str(), pl.offset, pl.scale,
                  c.pairs, c.occluded);
      EXPECT_EQ(c.occluded, 0);
    }
  }
}

}  // namespace
}  // namespace prism
