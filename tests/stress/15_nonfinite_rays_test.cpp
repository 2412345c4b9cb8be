// Stress case 15 (guard): rays with a non-finite origin, direction or range never reach
// Embree (renderer/geometry/embree_scene.cpp, ray_is_valid). intersect() reports no hit, so the
// sample sees the background; occluded() reports blocked, so a broken shadow ray can darken
// a point but never light it. (The tile loop's sample firewall is case 15's other half,
// 15_nan_firewall_test.cpp.)
#include <gtest/gtest.h>

#include <limits>

#include "renderer/geometry/embree_scene.h"

namespace prism {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A unit sphere at the origin and a large floor below it: any ray through the middle hits.
SceneDescription target() {
  SceneDescription scene;
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "ball"});
  Mesh floor;
  Primitive p;
  p.positions = {V3f(-50, -2, 50), V3f(50, -2, 50), V3f(50, -2, -50), V3f(-50, -2, -50)};
  p.indices = {0, 1, 2, 0, 2, 3};
  floor.primitives.push_back(p);
  scene.meshes.push_back(floor);
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  return scene;
}

Ray towards_ball() {
  Ray r;
  r.origin = V3f(0.0f, 0.0f, 5.0f);
  r.direction = V3f(0.0f, 0.0f, -1.0f);
  return r;
}

TEST(StressNonFiniteRays, NeverHitAndAlwaysOccludedInEverySphereMode) {
  for (const char* mode : {"analytic", "embree-points", "mesh:3"}) {
    SCOPED_TRACE(mode);
    GeometryOptions options;
    ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
    const EmbreeScene geometry(target(), options);

    // The valid ray first: the guard must not cost real hits.
    SurfaceHit hit;
    ASSERT_TRUE(geometry.intersect(towards_ball(), &hit));
    EXPECT_NEAR(hit.t, 4.0f, 0.01f);
    Ray free = towards_ball();
    free.direction = V3f(0.0f, 0.0f, 1.0f);
    EXPECT_FALSE(geometry.occluded(free));
    // An unbounded (tfar = +inf) ray is valid: infinity is the usual "no limit".
    EXPECT_TRUE(geometry.occluded(towards_ball()));

    std::vector<Ray> broken;
    for (float bad : {kNaN, kInf, -kInf}) {
      for (int axis = 0; axis < 3; ++axis) {
        Ray o = towards_ball();
        o.origin[axis] = bad;
        broken.push_back(o);
        Ray d = towards_ball();
        d.direction[axis] = bad;
        broken.push_back(d);
      }
      Ray near = towards_ball();
      near.tnear = bad;
      broken.push_back(near);
    }
    Ray nan_far = towards_ball();
    nan_far.tfar = kNaN;
    broken.push_back(nan_far);
    ASSERT_EQ(broken.size(), 3u * 7u + 1u);
    for (const Ray& r : broken) {
      SurfaceHit h;
      h.t = -7.0f;
      EXPECT_FALSE(geometry.intersect(r, &h));
      EXPECT_EQ(h.t, -7.0f);  // the hit record is left alone
      EXPECT_TRUE(geometry.occluded(r));
      // The same ray pointed away from everything: still blocked, as it cannot be traced.
      Ray away = r;
      if (std::isfinite(away.direction.z)) away.direction.z = -away.direction.z;
      EXPECT_TRUE(geometry.occluded(away));
    }
  }
}

}  // namespace
}  // namespace prism
