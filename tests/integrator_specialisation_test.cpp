// The integrators specialised on the scene's feature set (integrators/shading_flags.h): the
// rays they skip, counted exactly, and the image, which must be bit-identical to the general
// code's (testing::TestSettings::specialise = false). Each skipped kind of ray is also shown to be
// cast by the general code on the same scene, so the counts could fail.
#include <gtest/gtest.h>

#include <cstring>

#include "integrators/registry.h"
#include "scene_passes/scene_defaults.h"
#include "renderer/scene_features.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::quad_mesh;

using testing::directional_light;
using testing::point_light;

// A perspective camera at `eye` looking at `target`, +Y up.
CameraDescription camera_at(V3d eye, V3d target) {
  CameraDescription c;
  c.name = "view";
  c.yfov = 0.9;
  const V3d back = (eye - target).normalized();
  const V3d right = V3d(0, 1, 0).cross(back).normalized();
  const V3d up = back.cross(right);
  c.camera_to_world = M44d(right.x, right.y, right.z, 0, up.x, up.y, up.z, 0, back.x, back.y,
                           back.z, 0, eye.x, eye.y, eye.z, 1);
  return c;
}

MaterialDescription mirror_material() {
  MaterialDescription m;
  m.base_colour = C3f(0.9f, 0.9f, 0.9f);
  m.metallic = 1.0f;
  m.roughness = 0.0f;
  return m;
}

MaterialDescription glass_material() {
  MaterialDescription m;
  m.metallic = 0.0f;
  m.roughness = 0.0f;
  m.transmission = 1.0f;
  m.ior = 1.5f;
  return m;
}

// A diffuse floor (4 m quad at y = 0) with a diffuse ball above it that shadows it.
SceneDescription diffuse_with_occluder() {
  SceneDescription s;
  s.materials = {lambert_like(0.6f), lambert_like(0.3f)};
  s.meshes.push_back(quad_mesh(2.0f, 0.0f, 0));
  s.instances.push_back({0, M44d(), "floor"});
  s.spheres.push_back({V3d(0.2, 0.7, 0.0), 0.5, 1, "ball"});
  s.lights.push_back(point_light(V3d(-0.5, 3.0, 0.5), 20.0f));
  s.cameras.push_back(camera_at(V3d(0.0, 3.0, 4.0), V3d(0.0, 0.3, 0.0)));
  return s;
}

// One diffuse ball lit by a point light, seen from outside: nothing can block a shadow ray.
SceneDescription lone_ball() {
  SceneDescription s;
  s.materials = {lambert_like(0.7f)};
  s.spheres.push_back({V3d(0.0, 0.0, 0.0), 1.0, 0, "ball"});
  s.lights.push_back(point_light(V3d(2.0, 3.0, 2.0), 30.0f));
  s.cameras.push_back(camera_at(V3d(0.0, 1.0, 3.0), V3d(0.0, 0.0, 0.0)));
  return s;
}

// One flat floor lit by the sun: nothing can block a shadow ray either.
SceneDescription sunlit_floor() {
  SceneDescription s;
  s.materials = {lambert_like(0.5f)};
  s.meshes.push_back(quad_mesh(2.0f, 0.0f, 0));
  s.instances.push_back({0, M44d(), "floor"});
  s.lights.push_back(directional_light(V3d(0.4, -1.0, -0.3)));
  s.cameras.push_back(camera_at(V3d(0.0, 2.5, 3.0), V3d(0.0, 0.0, 0.0)));
  return s;
}

// A floor, a mirror ball and a glass ball.
SceneDescription mirror_and_glass() {
  SceneDescription s = diffuse_with_occluder();
  s.materials.push_back(mirror_material());
  s.materials.push_back(glass_material());
  s.spheres[0].material = 2;
  s.spheres.push_back({V3d(-0.9, 0.5, 0.6), 0.45, 3, "glass"});
  return s;
}

// The floor and the mirror ball alone: opaque, so no Fresnel and no refraction.
SceneDescription mirror_only() {
  SceneDescription s = diffuse_with_occluder();
  s.materials.push_back(mirror_material());
  s.spheres[0].material = 2;
  return s;
}

struct Renders {
  testing::Rendered specialised, general;
};

Renders render_both(const SceneDescription& scene, const char* kind) {
  testing::TestSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.ambient = 0.05f;
  settings.background = V3f(0.1f, 0.2f, 0.3f);
  Renders r;
  r.specialised = testing::render_scene(scene, kind, settings);
  settings.specialise = false;
  r.general = testing::render_scene(scene, kind, settings);
  return r;
}

// Bit for bit, so that even a +0 turned into -0 would show.
void expect_same_bits(const Image& a, const Image& b) {
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  ASSERT_EQ(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)), 0);
}

void expect_same_rays(const RayCounters& a, const RayCounters& b) {
  EXPECT_EQ(a[RayKind::camera], b[RayKind::camera]);
  EXPECT_EQ(a[RayKind::shadow], b[RayKind::shadow]);
  EXPECT_EQ(a[RayKind::reflection], b[RayKind::reflection]);
  EXPECT_EQ(a[RayKind::refraction], b[RayKind::refraction]);
}

SceneFeatures features(const SceneDescription& scene) {
  return derive_scene_features(scene, SphereOptions());
}

constexpr uint64_t kPixels = 64 * 48;

TEST(IntegratorSpecialisation, DiffuseSceneWhittedRunsTheShadowPath) {
  const SceneDescription scene = diffuse_with_occluder();
  const SceneFeatures f = features(scene);
  ASSERT_TRUE(f.shadows);
  ASSERT_FALSE(f.mirror || f.transmission || f.emission);

  const Renders shadow = render_both(scene, "shadow");
  const Renders whitted = render_both(scene, "whitted");
  // The occluder is there: shadow rays are cast, the same ones either way.
  EXPECT_GT(shadow.specialised.result.rays[RayKind::shadow], kPixels / 4);
  expect_same_rays(shadow.specialised.result.rays, shadow.general.result.rays);
  expect_same_bits(shadow.specialised.image, shadow.general.image);

  // whitted casts exactly the shadow integrator's rays and makes its image.
  const RayCounters& w = whitted.specialised.result.rays;
  EXPECT_EQ(w[RayKind::camera], kPixels);
  EXPECT_EQ(w[RayKind::shadow], shadow.specialised.result.rays[RayKind::shadow]);
  EXPECT_EQ(w[RayKind::reflection], 0u);
  EXPECT_EQ(w[RayKind::refraction], 0u);
  expect_same_rays(w, whitted.general.result.rays);
  expect_same_bits(whitted.specialised.image, shadow.specialised.image);
  expect_same_bits(whitted.specialised.image, whitted.general.image);
}

TEST(IntegratorSpecialisation, NoOccluderMeansNoShadowRays) {
  for (const SceneDescription& scene : {lone_ball(), sunlit_floor()}) {
    ASSERT_FALSE(features(scene).shadows);
    const Renders phong = render_both(scene, "phong");
    const Renders shadow = render_both(scene, "shadow");
    const Renders whitted = render_both(scene, "whitted");
    // The general code casts them, and they change nothing.
    EXPECT_GT(shadow.general.result.rays[RayKind::shadow], kPixels / 16);
    EXPECT_GT(whitted.general.result.rays[RayKind::shadow], kPixels / 16);
    EXPECT_EQ(shadow.specialised.result.rays[RayKind::shadow], 0u);
    EXPECT_EQ(whitted.specialised.result.rays[RayKind::shadow], 0u);
    EXPECT_EQ(whitted.specialised.result.rays[RayKind::reflection], 0u);
    EXPECT_EQ(whitted.specialised.result.rays[RayKind::refraction], 0u);
    EXPECT_EQ(shadow.specialised.result.rays[RayKind::camera], kPixels);
    expect_same_bits(shadow.specialised.image, shadow.general.image);
    expect_same_bits(whitted.specialised.image, whitted.general.image);
    expect_same_bits(shadow.specialised.image, phong.general.image);
    expect_same_bits(phong.specialised.image, phong.general.image);
    expect_same_rays(phong.specialised.result.rays, phong.general.result.rays);
  }
}

TEST(IntegratorSpecialisation, MirrorAndGlassKeepEveryRay) {
  const SceneDescription scene = mirror_and_glass();
  const SceneFeatures f = features(scene);
  ASSERT_TRUE(f.shadows && f.mirror && f.transmission);
  const Renders whitted = render_both(scene, "whitted");
  EXPECT_GT(whitted.general.result.rays[RayKind::reflection], 0u);
  EXPECT_GT(whitted.general.result.rays[RayKind::refraction], 0u);
  expect_same_rays(whitted.specialised.result.rays, whitted.general.result.rays);
  expect_same_bits(whitted.specialised.image, whitted.general.image);
}

TEST(IntegratorSpecialisation, OpaqueMirrorSceneSkipsOnlyRefraction) {
  const SceneDescription scene = mirror_only();
  const SceneFeatures f = features(scene);
  ASSERT_TRUE(f.shadows && f.mirror);
  ASSERT_FALSE(f.transmission);
  const Renders whitted = render_both(scene, "whitted");
  EXPECT_GT(whitted.specialised.result.rays[RayKind::reflection], 0u);
  EXPECT_EQ(whitted.specialised.result.rays[RayKind::refraction], 0u);
  expect_same_rays(whitted.specialised.result.rays, whitted.general.result.rays);
  expect_same_bits(whitted.specialised.image, whitted.general.image);
}

TEST(IntegratorSpecialisation, LoneMirrorBallReflectsWithoutShadowRays) {
  SceneDescription scene = lone_ball();
  scene.materials[0] = mirror_material();
  ASSERT_FALSE(features(scene).shadows);
  ASSERT_TRUE(features(scene).mirror);
  const Renders whitted = render_both(scene, "whitted");
  EXPECT_GT(whitted.general.result.rays[RayKind::shadow], 0u);
  EXPECT_EQ(whitted.specialised.result.rays[RayKind::shadow], 0u);
  EXPECT_GT(whitted.specialised.result.rays[RayKind::reflection], 0u);
  EXPECT_EQ(whitted.specialised.result.rays[RayKind::reflection], whitted.general.result.rays[RayKind::reflection]);
  expect_same_bits(whitted.specialised.image, whitted.general.image);
}

TEST(IntegratorSpecialisation, EmissionIsAddedOnlyWhereSomethingEmits) {
  SceneDescription dark = lone_ball();
  dark.lights.clear();
  ASSERT_FALSE(features(dark).emission);
  SceneDescription glowing = dark;
  glowing.materials[0].emissive = C3f(0.5f, 0.25f, 1.0f);
  ASSERT_TRUE(features(glowing).emission);
  for (const char* kind :
       {"phong", "shadow", "whitted"}) {
    const Renders d = render_both(dark, kind);
    const Renders g = render_both(glowing, kind);
    expect_same_bits(d.specialised.image, d.general.image);
    expect_same_bits(g.specialised.image, g.general.image);
    // The centre pixel sees the ball: ambient alone, and ambient plus emission.
    const float* ambient = d.specialised.image.pixel(32, 24);
    const float* lit = g.specialised.image.pixel(32, 24);
    EXPECT_GT(lit[2] - ambient[2], 0.9f);
  }
}

// The shadow rule's cases that the specialisation made matter: in each, the general shadow
// integrator's image differs from phong's (a shadow ray is blocked somewhere), so the rule
// must say shadows=yes, and the specialised image is still the general one.
void expect_self_shadowing(const SceneDescription& scene, const char* kind) {
  ASSERT_TRUE(features(scene).shadows);
  const Renders r = render_both(scene, kind);
  const Renders unshadowed = render_both(scene, "phong");
  EXPECT_NE(std::memcmp(r.general.image.rgba.data(), unshadowed.general.image.rgba.data(),
                        r.general.image.rgba.size() * sizeof(float)),
            0);
  expect_same_rays(r.specialised.result.rays, r.general.result.rays);
  expect_same_bits(r.specialised.image, r.general.image);
}

TEST(IntegratorSpecialisation, CameraInsideABallLitFromOutsideSeesItsShadow) {
  SceneDescription scene = lone_ball();
  scene.lights = {directional_light(V3d(0.2, -1.0, 0.1))};
  scene.cameras = {camera_at(V3d(0.0, 0.2, 0.3), V3d(0.0, -1.0, 0.0))};
  expect_self_shadowing(scene, "shadow");
}

TEST(IntegratorSpecialisation, GlassBallShadowsItsOwnInside) {
  SceneDescription scene = lone_ball();
  scene.materials[0] = glass_material();
  expect_self_shadowing(scene, "whitted");
}

TEST(IntegratorSpecialisation, FlatFloorWithLeaningNormalsShadowsItself) {
  // Every vertex normal leans towards +X, so points face a light below the floor's plane
  // off to +X, and their shadow rays cross the floor.
  SceneDescription scene = sunlit_floor();
  for (V3f& n : scene.meshes[0].primitives[0].normals) n = V3f(1.0f, 1.0f, 0.0f).normalized();
  scene.lights = {point_light(V3d(6.0, -0.3, 0.0), 50.0f)};
  expect_self_shadowing(scene, "shadow");
}

}  // namespace
}  // namespace prism
