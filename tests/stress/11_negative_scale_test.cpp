// Stress case 11: non-uniform and negative node scales. A scene and its mirror image
// (every node scaled by (-1, 1, 1), spheres and lights mirrored, the camera on the mirror
// plane) render as each other's horizontal flip; and the smooth normals of non-uniformly
// scaled, mirrored meshes, baked or instanced, are the ellipsoid's true outward normals on
// the geometric normal's side.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "integrators/registry.h"
#include "renderer/math.h"
#include "renderer/geometry/sphere_mesh.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::quad_mesh;
using testing::render_scene;

// Rotation about Y, then non-uniform scale... in Imath's row-vector order: p * S * R * T.
M44d node(const V3d& scale, double yaw, const V3d& translation) {
  M44d s, r;
  s.setScale(scale);
  r.setEulerAngles(V3d(0.0, yaw, 0.0));
  M44d m = s * r;
  m[3][0] = translation.x;
  m[3][1] = translation.y;
  m[3][2] = translation.z;
  return m;
}

// Deliberately lopsided: ellipsoids (one baked, one mesh placed twice so instanced) at
// different yaws, a glossy analytic sphere, a mirror sphere and two lights, all off the
// mirror plane x = 0.
SceneDescription lopsided_scene() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.7f));
  MaterialDescription glossy = lambert_like(0.9f);
  glossy.roughness = 0.45f;
  scene.materials.push_back(glossy);
  MaterialDescription mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  scene.materials.push_back(mirror);
  scene.meshes.push_back(quad_mesh(5.0f, 0.0f, 0));
  Mesh ball;
  ball.primitives.push_back(tessellate_sphere(Sphere{V3d(0.0), 1.0, 1, ""}, 3));
  scene.meshes.push_back(ball);
  scene.meshes.push_back(ball);
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.instances.push_back(
      MeshInstance{1, node(V3d(0.9, 0.4, 0.5), 0.5, V3d(-1.4, 0.4, 0.2)), "baked"});
  scene.instances.push_back(
      MeshInstance{2, node(V3d(0.3, 0.8, 0.5), -0.3, V3d(1.2, 0.8, -0.6)), "instanced a"});
  scene.instances.push_back(
      MeshInstance{2, node(V3d(0.6, 0.3, 0.3), 1.1, V3d(0.5, 0.3, 1.5)), "instanced b"});
  scene.spheres.push_back(Sphere{V3d(-0.3, 0.5, -1.2), 0.5, 1, "glossy"});
  scene.spheres.push_back(Sphere{V3d(1.9, 0.45, 0.9), 0.45, 2, "mirror"});
  Light bulb;
  bulb.intensity = 25.0f;
  bulb.position = V3d(-2.0, 3.5, 2.0);
  scene.lights.push_back(bulb);
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 1.0f;
  sun.direction = V3d(0.5, -1.0, -0.3).normalized();
  scene.lights.push_back(sun);
  CameraDescription camera;  // on the mirror plane, so mirroring the scene flips the image
  camera.yfov = 0.9;
  camera.camera_to_world.setEulerAngles(V3d(-0.5, 0.0, 0.0));
  camera.camera_to_world[3][1] = 3.5;
  camera.camera_to_world[3][2] = 6.0;
  scene.cameras.push_back(camera);
  return scene;
}

SceneDescription mirrored(SceneDescription scene) {
  M44d flip;
  flip.setScale(V3d(-1.0, 1.0, 1.0));
  for (MeshInstance& inst : scene.instances) inst.object_to_world = inst.object_to_world * flip;
  for (Sphere& s : scene.spheres) s.centre.x = -s.centre.x;
  for (Light& l : scene.lights) {
    l.position.x = -l.position.x;
    l.direction.x = -l.direction.x;
  }
  return scene;
}

TEST(StressNegativeScale, MirroredSceneRendersAsTheHorizontalFlip) {
  testing::TestSettings settings;
  // A power-of-two width makes pixel x and width - 1 - x generate exactly mirrored rays
  // (2 (x + 0.5) / 128 - 1 is exact), so only the geometry's rounding can differ.
  settings.width = 128;
  settings.height = 96;
  const SceneDescription scene = lopsided_scene();
  const SceneDescription mirror = mirrored(scene);
  for (bool robust : {false, true}) {
    SCOPED_TRACE(robust ? "robust" : "default");
    GeometryOptions options;
    options.robust = robust;
    const auto whitted = make_integrator("whitted");
    const auto a = render_scene(scene, *whitted, settings, options);
    const auto b = render_scene(mirror, *whitted, settings, options);
    double max_diff = 0.0, max_value = 0.0;
    int differing = 0, off_by_more = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        const float* p = a.image.pixel(x, y);
        const float* q = b.image.pixel(settings.width - 1 - x, y);
        for (int c = 0; c < 4; ++c) {
          ASSERT_TRUE(std::isfinite(p[c]) && std::isfinite(q[c]));
          const double d = std::fabs(static_cast<double>(p[c]) - q[c]);
          max_diff = std::max(max_diff, d);
          max_value = std::max(max_value, static_cast<double>(p[c]));
          differing += p[c] != q[c] ? 1 : 0;
          off_by_more += d > 1e-4 * std::max(1.0f, p[c]) ? 1 : 0;
        }
      }
    }
    std::printf(
        "mirror (%s): max |difference| %.3g of max %.3g; %d channel values differ, %d "
        "by more than 1e-4\n",
        robust ? "robust" : "default", max_diff, max_value, differing, off_by_more);
    ASSERT_GT(max_value, 0.1);
    // Mirrored triangles have their winding reversed (to keep the front face) and so are
    // intersected with their vertices in another order: hits agree to rounding, 1e-4
    // relative, not bit for bit. Every pixel must agree to that.
    EXPECT_EQ(off_by_more, 0);
  }
}

// The ellipsoid p = (x/a, y/b, z/c) scaled from the unit sphere has outward normal
// (x/a^2, y/b^2, z/c^2) at p: the smooth normals, turned by the inverse transpose, must be
// that (to the tessellation's angle) and on the outside, for any signs of a, b, c.
TEST(StressNegativeScale, SmoothNormalsOfScaledAndMirroredMeshesFaceOutwards) {
  constexpr int kLevel = 5;
  const V3d scales[] = {V3d(2.0, 0.5, 1.0), V3d(-2.0, 0.5, 1.0), V3d(-1.0, -1.5, 0.7)};
  for (const V3d& scale : scales) {
    for (int placements : {1, 2}) {  // baked, instanced
      SCOPED_TRACE(::testing::Message() << "scale " << scale.x << " " << scale.y << " " << scale.z
                                        << ", placements " << placements);
      SceneDescription scene;
      Mesh ball;
      ball.primitives.push_back(tessellate_sphere(Sphere{V3d(0.0), 1.0, -1, ""}, kLevel));
      scene.meshes.push_back(ball);
      M44d m;
      m.setScale(scale);
      scene.instances.push_back(MeshInstance{0, m, "a"});
      if (placements == 2) {
        M44d far = m;
        far[3][0] = 100.0;
        scene.instances.push_back(MeshInstance{0, far, "b"});
      }
      const EmbreeScene geometry(scene, {});
      const V3d axes(std::fabs(scale.x), std::fabs(scale.y), std::fabs(scale.z));
      double worst = 1.0;
      int hits = 0;
      for (int i = -20; i <= 20; ++i) {
        for (int j = -20; j <= 20; ++j) {
          for (float side : {1.0f, -1.0f}) {
            Ray ray;
            ray.origin = V3f(0.048f * i * static_cast<float>(axes.x),
                             0.048f * j * static_cast<float>(axes.y), side * 10.0f);
            ray.direction = V3f(0.0f, 0.0f, -side);
            SurfaceHit hit;
            if (!geometry.intersect(ray, &hit)) continue;
            ++hits;
            EXPECT_FALSE(hit.back_face) << i << " " << j << " " << side << " t " << hit.t << " ng "
                                        << hit.geometric_normal << " p " << hit.position;
            const V3d p(hit.position);
            const V3d outward =
                V3d(p.x / (axes.x * axes.x), p.y / (axes.y * axes.y), p.z / (axes.z * axes.z))
                    .normalized();
            EXPECT_GT(dot(hit.geometric_normal, V3f(outward)), 0.0f);
            worst = std::min(worst, static_cast<double>(dot(hit.shading_normal, V3f(outward))));
          }
        }
      }
      std::printf("scale (%g %g %g) x%d: %d hits, worst shading . true normal %.6f (%.3f deg)\n",
                  scale.x, scale.y, scale.z, placements, hits, worst,
                  std::acos(std::min(1.0, worst)) * 180.0 / 3.14159265358979);
      EXPECT_GT(hits, 2000);
      // Level 5's vertices are 2.3 degrees apart on the sphere and carry the exact normal;
      // interpolating between them errs by a fraction of that spacing, even stretched 4:1:
      // within 1 degree (measured 0.07). Transforming normals by the matrix itself instead
      // of its inverse transpose is off by up to 37 degrees here, a flipped one by 180.
      EXPECT_GT(worst, std::cos(1.0 * 3.14159265358979 / 180.0));
    }
  }
}

}  // namespace
}  // namespace prism
