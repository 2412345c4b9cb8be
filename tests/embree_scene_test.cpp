// The Embree scene: baking versus instancing, mirrored transforms, and what a hit reports.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "renderer/geometry/embree_scene.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {
namespace {

// One counter-clockwise triangle in the XY plane: its front face looks down +Z.
Mesh triangle_mesh() {
  Mesh mesh;
  Primitive p;
  p.positions = {V3f(-1, -1, 0), V3f(1, -1, 0), V3f(0, 1, 0)};
  p.indices = {0, 1, 2};
  p.uv0 = {V2f(0, 0), V2f(1, 0), V2f(0.5f, 1)};
  p.material = 3;
  mesh.primitives.push_back(p);
  return mesh;
}

M44d translate_scale(V3d t, V3d s) {
  M44d m;
  m.setScale(s);
  m[3][0] = t.x;
  m[3][1] = t.y;
  m[3][2] = t.z;
  return m;
}

Ray ray_down_z(float x, float y) {
  Ray r;
  r.origin = V3f(x, y, 10.0f);
  r.direction = V3f(0, 0, -1);
  return r;
}

// A mesh placed once is baked into world space; placed twice it is instanced. Both must
// report the same hits, including for a mirroring node (negative determinant), whose front
// face must stay the authored one: the normal the inverse transpose gives, +Z here.
TEST(EmbreeScene, BakedAndInstancedMeshesReportTheSameHits) {
  const M44d mirrored = translate_scale(V3d(5, 0, 0), V3d(-2, 2, 2));  // det < 0
  const M44d plain = translate_scale(V3d(-5, 0, 0), V3d(2, 2, 2));
  SceneDescription once;  // two meshes, each used once: both baked
  once.meshes = {triangle_mesh(), triangle_mesh()};
  once.instances = {{0, plain, "a"}, {1, mirrored, "b"}};
  SceneDescription shared;  // one mesh used twice: instanced
  shared.meshes = {triangle_mesh()};
  shared.instances = {{0, plain, "a"}, {0, mirrored, "b"}};

  const EmbreeScene baked(once, {});
  const EmbreeScene instanced(shared, {});
  EXPECT_EQ(baked.statistics().meshes_baked, 2u);
  EXPECT_EQ(baked.statistics().mesh_instances, 0u);
  EXPECT_EQ(instanced.statistics().meshes_baked, 0u);
  EXPECT_EQ(instanced.statistics().mesh_instances, 2u);
  EXPECT_EQ(instanced.statistics().triangles, 2u);

  for (float x : {-5.0f, 5.0f, 5.5f}) {
    SCOPED_TRACE(x);
    SurfaceHit a, b;
    ASSERT_TRUE(baked.intersect(ray_down_z(x, 0.2f), &a));
    ASSERT_TRUE(instanced.intersect(ray_down_z(x, 0.2f), &b));
    EXPECT_NEAR(a.t, 10.0f, 1e-5f);
    EXPECT_NEAR(b.t, 10.0f, 1e-5f);
    EXPECT_NEAR((a.position - V3f(x, 0.2f, 0)).length(), 0.0f, 1e-5f);
    EXPECT_NEAR((b.position - V3f(x, 0.2f, 0)).length(), 0.0f, 1e-5f);
    // The authored front face (+Z) faces the ray in both, mirrored or not.
    EXPECT_NEAR(a.geometric_normal.z, 1.0f, 1e-6f);
    EXPECT_NEAR(b.geometric_normal.z, 1.0f, 1e-6f);
    EXPECT_FALSE(a.back_face);
    EXPECT_FALSE(b.back_face);
    EXPECT_EQ(a.material, 3);
    EXPECT_EQ(b.material, 3);
    EXPECT_NEAR(a.texcoord(0).x, b.texcoord(0).x, 1e-5f);
    EXPECT_NEAR(a.texcoord(0).y, b.texcoord(0).y, 1e-5f);
  }
  // The mirrored triangle is flipped in x: at local x = -0.25 (world 5.5) the texture
  // coordinate u is that of local x = -0.25, i.e. below the centre line's 0.5.
  SurfaceHit m;
  ASSERT_TRUE(instanced.intersect(ray_down_z(5.5f, 0.2f), &m));
  EXPECT_LT(m.texcoord(0).x, 0.5f);
  EXPECT_FLOAT_EQ(baked.bounds().min.x, -7.0f);
  EXPECT_FLOAT_EQ(baked.bounds().max.x, 7.0f);
}

TEST(EmbreeScene, SmoothNormalsTurnWithTheNodeAndStayOnTheGeometricSide) {
  Mesh mesh = triangle_mesh();
  // Authored normals pointing against the winding: they must be flipped onto its side.
  mesh.primitives[0].normals = {V3f(0, 0, -1), V3f(0, 0, -1), V3f(0, 0, -1)};
  SceneDescription scene;
  scene.meshes = {mesh};
  scene.instances = {{0, M44d(), "a"}};
  const EmbreeScene geometry(scene, {});
  SurfaceHit hit;
  ASSERT_TRUE(geometry.intersect(ray_down_z(0.0f, 0.0f), &hit));
  EXPECT_NEAR(hit.shading_normal.z, 1.0f, 1e-6f);
}

// A flat-shaded mesh with stored normals, baked at an angle: the hit's shading normal is the
// face normal itself, which the normals' interpolation gives to rounding, and no terminator
// offset lifts the point (the patch the normals describe is the triangle's plane).
TEST(EmbreeScene, AFlatShadedMeshsHitsTakeTheFaceNormal) {
  Mesh mesh = triangle_mesh();
  mesh.primitives[0].normals = {V3f(0, 0, 1), V3f(0, 0, 1), V3f(0, 0, 1)};
  M44d turn;
  turn.setAxisAngle(V3d(1, 0, 0), 0.2);
  SceneDescription scene;
  scene.meshes = {mesh};
  scene.instances = {{0, turn, "a"}};
  const EmbreeScene geometry(scene, {});
  SurfaceHit hit;
  ASSERT_TRUE(geometry.intersect(ray_down_z(0.1f, 0.2f), &hit));
  EXPECT_EQ(hit.shading_normal, hit.geometric_normal);
  EXPECT_EQ(hit.terminator_offset, V3f(0.0f));
  V3d turned;
  turn.multDirMatrix(V3d(0, 0, 1), turned);
  EXPECT_NEAR(hit.shading_normal.dot(V3f(turned)), 1.0f, 1e-6f);
  EXPECT_LT(hit.shading_normal.z, 0.99f);  // really turned
}

// Every sphere mode: a ray from the centre leaves through the far side (t = r), flagged as
// arriving at the back face, with the outward normal; a ray from outside arrives at the front.
TEST(EmbreeScene, SphereHitsReportBackFacesFromInside) {
  SceneDescription scene;
  scene.spheres.push_back(Sphere{V3d(1, 2, 3), 0.5, 7, "s"});
  for (const char* mode : {"analytic", "embree-points", "mesh:6"}) {
    SCOPED_TRACE(mode);
    GeometryOptions options;
    ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
    const EmbreeScene geometry(scene, options);
    const double tolerance = tessellation_max_error(0.5, 6) + 1e-6;
    Ray inside;
    inside.origin = V3f(1, 2, 3);
    inside.direction = V3f(0, 0, 1);
    SurfaceHit hit;
    ASSERT_TRUE(geometry.intersect(inside, &hit));
    EXPECT_NEAR(hit.t, 0.5f, tolerance);
    EXPECT_TRUE(hit.back_face);
    EXPECT_NEAR(hit.geometric_normal.z, 1.0f, 1e-3f);
    EXPECT_EQ(hit.material, 7);
    Ray outside;
    outside.origin = V3f(1, 2, -10);
    outside.direction = V3f(0, 0, 1);
    ASSERT_TRUE(geometry.intersect(outside, &hit));
    EXPECT_NEAR(hit.t, 12.5f, tolerance + 1e-5);
    EXPECT_FALSE(hit.back_face);
    EXPECT_NEAR(hit.geometric_normal.z, -1.0f, 1e-3f);
    EXPECT_NEAR((hit.position - V3f(1, 2, 2.5f)).length(), 0.0f, tolerance + 1e-6);
    // The shadow query sees the sphere between the two points and nothing beyond.
    Ray segment = outside;
    segment.tfar = 12.0f;
    EXPECT_FALSE(geometry.occluded(segment));
    segment.tfar = 13.0f;
    EXPECT_TRUE(geometry.occluded(segment));
  }
}

// Scenes built on one device trace as scenes on devices of their own, and keep the device
// alive after its maker lets it go.
TEST(EmbreeScene, ScenesShareOneDeviceAndKeepItAlive) {
  SceneDescription scene;
  scene.meshes = {triangle_mesh()};
  scene.instances = {{0, translate_scale(V3d(0, 0, 0), V3d(2, 2, 2)), "a"}};
  scene.spheres.push_back(Sphere{V3d(4, 0, 0), 1.0, 2, "s"});
  auto device = std::make_shared<EmbreeDevice>();
  auto first = std::make_unique<EmbreeScene>(device, scene, GeometryOptions{});
  const EmbreeScene second(device, scene, GeometryOptions{});
  EXPECT_EQ(first->device(), device);
  EXPECT_EQ(device.use_count(), 3);
  device.reset();
  EXPECT_EQ(second.device().use_count(), 2);
  first.reset();
  EXPECT_EQ(second.device().use_count(), 1);

  const EmbreeScene own(scene, GeometryOptions{});
  EXPECT_NE(own.device(), second.device());
  for (float x : {0.5f, 4.0f, 4.5f}) {
    SCOPED_TRACE(x);
    SurfaceHit a, b;
    ASSERT_TRUE(second.intersect(ray_down_z(x, 0.2f), &a));
    ASSERT_TRUE(own.intersect(ray_down_z(x, 0.2f), &b));
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.material, b.material);
  }
}

// Errors Embree reports on a device reach every watch open on it, and only those.
TEST(EmbreeDevice, ErrorWatchesSeeTheErrorsReportedWhileTheyAreOpen) {
  EmbreeDevice device;
  const auto bad_type = static_cast<RTCGeometryType>(1000);
  EXPECT_EQ(rtcNewGeometry(device.get(), bad_type), nullptr);  // no watch: dropped
  EmbreeDevice::ErrorWatch watch(device);
  EXPECT_EQ(watch.first_error(), "");
  EXPECT_NO_THROW(watch.throw_if_failed());
  {
    EmbreeDevice::ErrorWatch inner(device);
    EXPECT_EQ(rtcNewGeometry(device.get(), bad_type), nullptr);
    EXPECT_NE(inner.first_error(), "");
  }
  EXPECT_NE(watch.first_error(), "");
  EXPECT_THROW(watch.throw_if_failed(), std::runtime_error);
  const EmbreeDevice::ErrorWatch later(device);
  EXPECT_EQ(later.first_error(), "");
}

}  // namespace
}  // namespace prism
