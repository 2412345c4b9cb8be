// The path integrator against analytic answers (pbrt-v4's integrators_test cases, furnaces,
// irradiance under area lights), its three light strategies against each other, Russian
// roulette against none, and its determinism. Each test prints what it measured, with the
// noise its bound is made of: docs/accuracy.md lists the figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "integrators/registry.h"
#include "tests/analytic_scenes.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::difference;
using testing::emissive;
using testing::estimate;
using testing::Estimate;
using testing::expect_close;
using testing::film;
using testing::floor_under_sphere;
using testing::floor_under_sphere_exact;
using testing::floor_under_square;
using testing::floor_under_square_exact;
using testing::kPiD;
using testing::lambert_like;
using testing::ortho_camera_looking_down_y;
using testing::ortho_camera_looking_down_z;
using testing::quad_mesh;

struct PathSettings {
  int max_depth = 64;
  int roulette_depth = 3;
  int strategy = 0;
};

testing::Rendered render_path(const SceneDescription& scene, testing::TestSettings settings,
                              const PathSettings& path = {}) {
  const IntegratorInfo* info = find_integrator("path");
  EXPECT_NE(info, nullptr);
  const ConfiguredIntegrator c =
      configure_integrator(*info, {{"max-depth", path.max_depth},
                                   {"roulette-depth", path.roulette_depth},
                                   {"strategy", path.strategy}});
  return testing::render_scene(scene, *c.integrator, settings);
}

// pbrt-v4's RadianceMatches: inside a closed diffuse sphere of albedo 0.5 that emits 0.5,
// the radiance everywhere is L = Le / (1 - rho) = 1; with a point light of pi candela at its
// centre instead (E = pi on the wall, L_direct = rho E / pi = 0.5), L = 0.5 / (1 - rho) = 1.
TEST(PathIntegrator, InsideAnEmissiveDiffuseSphereRadianceIsOne) {
  SceneDescription scene;
  scene.materials.push_back(emissive(0.5f, 0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "sphere"});
  scene.cameras.push_back(ortho_camera_looking_down_z(0.0, 0.5));
  const char* names[] = {"emissive sphere, albedo 0.5, Le 0.5, MIS",
                         "emissive sphere, albedo 0.5, Le 0.5, light samples only",
                         "emissive sphere, albedo 0.5, Le 0.5, BSDF samples only"};
  for (int strategy = 0; strategy < 3; ++strategy)
    expect_close(names[strategy],
                 estimate(render_path(scene, film(32, 64), {64, 3, strategy}).image), 1.0);
}

TEST(PathIntegrator, InsideADiffuseSphereAroundAPointLightRadianceIsOne) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "sphere"});
  scene.lights.push_back(testing::point_light(V3d(0.0), float(kPiD)));
  scene.cameras.push_back(ortho_camera_looking_down_z(0.0, 0.5));
  expect_close("point light pi cd in a sphere of albedo 0.5",
               estimate(render_path(scene, film(32, 64)).image), 1.0);
}

// The white furnace: lossless white materials (Lambert, a perfect mirror, clear glass) under
// a uniform environment of radiance 1 send 1 back everywhere, the misses too.
TEST(PathIntegrator, WhiteFurnaceIsOneEverywhere) {
  MaterialDescription mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  MaterialDescription glass = lambert_like(1.0f);
  glass.roughness = 0.0f;
  glass.specular = 1.0f;
  glass.transmission = 1.0f;
  const std::pair<const char*, MaterialDescription> materials[] = {
      {"furnace: white Lambert sphere", lambert_like(1.0f)},
      {"furnace: white perfect mirror sphere", mirror},
      {"furnace: clear glass sphere", glass}};
  for (const auto& [name, material] : materials) {
    SceneDescription scene;
    scene.materials.push_back(material);
    scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "sphere"});
    scene.cameras.push_back(ortho_camera_looking_down_z(3.0, 0.9));
    testing::TestSettings s = film(32, 32);
    s.background = V3f(1.0f);
    const testing::Rendered r = render_path(scene, s);
    const Estimate e = estimate(r.image);
    expect_close(name, e, 1.0);
    // Every pixel, not only the mean: none strays beyond the noise of its 32 samples.
    double worst = 0.0;
    for (int y = 0; y < r.image.height; ++y)
      for (int x = 0; x < r.image.width; ++x)
        worst = std::max(worst, std::fabs(double(r.image.pixel(x, y)[0]) - 1.0));
    std::printf("  worst pixel |L - 1| = %.4f\n", worst);
    EXPECT_LT(worst, 0.25) << name;
  }
}

TEST(PathIntegrator, FloorUnderAnEmissiveSphereMatchesTheClosedForm) {
  const double exact = floor_under_sphere_exact();
  const char* names[] = {"sphere lamp, MIS", "sphere lamp, light samples only",
                         "sphere lamp, BSDF samples only"};
  for (int strategy = 0; strategy < 3; ++strategy)
    expect_close(names[strategy],
                 estimate(render_path(floor_under_sphere(), film(32, 64), {1, 3, strategy}).image),
                 exact);
}

TEST(PathIntegrator, FloorUnderAnEmissiveSquareMatchesTheClosedForm) {
  const double exact = floor_under_square_exact();
  const char* names[] = {"square lamp, MIS", "square lamp, light samples only",
                         "square lamp, BSDF samples only"};
  for (int strategy = 0; strategy < 3; ++strategy)
    expect_close(names[strategy],
                 estimate(render_path(floor_under_square(), film(32, 64), {1, 3, strategy}).image),
                 exact);
}

// A scene with a small and a large area light, a point light and an environment, glossy and
// diffuse surfaces, several bounces: MIS, light sampling alone and BSDF sampling alone agree
// within their combined noise, and MIS is the least noisy.
SceneDescription mixed_lights_scene() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.6f));
  MaterialDescription glossy;
  glossy.base_colour = C3f(0.9f, 0.8f, 0.6f);
  glossy.metallic = 1.0f;
  glossy.roughness = 0.35f;
  scene.materials.push_back(glossy);
  scene.materials.push_back(emissive(40.0f));
  scene.materials.push_back(emissive(0.8f));
  scene.meshes.push_back(quad_mesh(4.0f, 0.0f, 0));
  scene.meshes.push_back(quad_mesh(1.5f, 3.0f, 3));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.instances.push_back(MeshInstance{1, M44d(), "big panel"});
  scene.spheres.push_back(Sphere{V3d(0.0, 0.8, 0.0), 0.8, 1, "glossy ball"});
  scene.spheres.push_back(Sphere{V3d(1.5, 1.5, 1.0), 0.08, 2, "small lamp"});
  scene.lights.push_back(testing::point_light(V3d(-2.0, 2.5, 1.0), 3.0f));
  CameraDescription camera;  // perspective, looking down at the ball from the front
  camera.camera_to_world.setAxisAngle(V3d(1.0, 0.0, 0.0), -0.35);
  camera.camera_to_world[3][0] = 0.0;
  camera.camera_to_world[3][1] = 2.5;
  camera.camera_to_world[3][2] = 5.5;
  scene.cameras.push_back(camera);
  return scene;
}

// Renders mixed_lights_scene() with MIS and with each strategy alone (names in that order)
// and expects the image means to agree within their combined noise.
void expect_strategies_agree(const testing::TestSettings& s, const char* const (&names)[3]) {
  Image images[3];
  for (int strategy = 0; strategy < 3; ++strategy) {
    images[strategy] = render_path(mixed_lights_scene(), s, {8, 3, strategy}).image;
    std::printf("%s: image mean %.5f\n", names[strategy], estimate(images[strategy]).mean);
  }
  for (int k = 1; k < 3; ++k) {
    const Estimate d = difference(images[0], images[k]);
    std::printf("  %s - MIS = %+.5f +- %.5f (%.2f sigma)\n", names[k], d.mean, d.error,
                d.mean / d.error);
    EXPECT_NEAR(d.mean, 0.0, 4.0 * d.error) << names[k];
  }
}

TEST(PathIntegrator, MisLightOnlyAndBsdfOnlyAgree) {
  testing::TestSettings s = film(48, 64);
  s.background = V3f(0.2f);
  expect_strategies_agree(s, {"mixed lights, MIS", "mixed lights, light samples only",
                              "mixed lights, BSDF samples only"});
}

// The same under a map with a sun, where MIS's light samples leave out the light below the
// map's mean (EnvironmentDensity::beside_bsdf) and the BSDF samples must find it alone: a
// bias there would show against the light samples alone, which take the complete density.
TEST(PathIntegrator, MisLightOnlyAndBsdfOnlyAgreeUnderASunMap) {
  Image map(32, 16);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      float* p = map.pixel(x, y);
      const float g = 0.1f + 0.6f * float(map.height - y) / float(map.height);
      p[0] = g * 0.8f;
      p[1] = g * 0.9f;
      p[2] = g;
      p[3] = 1.0f;
    }
  std::fill_n(map.pixel(20, 4), 3, 300.0f);
  testing::TestSettings s = film(48, 64);
  s.environment = Environment(map, 0.4f, 1.0f);
  expect_strategies_agree(
      s, {"sun map, MIS", "sun map, light samples only", "sun map, BSDF samples only"});
}

// Russian roulette changes the noise, not the mean: a closed grey box lit by a panel, with
// roulette after 1 and after 3 bounces and without (all stopped at 32), and it does end paths:
// fewer bounce rays than without.
TEST(PathIntegrator, RussianRouletteIsUnbiased) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.7f));
  scene.materials.push_back(emissive(5.0f));
  scene.spheres.push_back(Sphere{V3d(0.0), 2.0, 0, "room"});
  scene.spheres.push_back(Sphere{V3d(0.0, 1.2, 1.0), 0.2, 1, "lamp"});  // behind the camera
  scene.cameras.push_back(ortho_camera_looking_down_z(0.0, 1.0));
  const testing::Rendered without = render_path(scene, film(32, 64), {32, 1024, 0});
  for (int depth : {1, 3}) {
    const testing::Rendered with = render_path(scene, film(32, 64), {32, depth, 0});
    const Estimate d = difference(without.image, with.image);
    std::printf(
        "roulette after %d: %.5f; none: %.5f; difference %+.5f +- %.5f (%.2f sigma); "
        "bounce rays %llu against %llu\n",
        depth, estimate(with.image).mean, estimate(without.image).mean, d.mean, d.error,
        d.mean / d.error, static_cast<unsigned long long>(with.result.rays[RayKind::bounce]),
        static_cast<unsigned long long>(without.result.rays[RayKind::bounce]));
    EXPECT_NEAR(d.mean, 0.0, 4.0 * d.error) << depth;
    EXPECT_LT(with.result.rays[RayKind::bounce], without.result.rays[RayKind::bounce] * 3 / 4)
        << depth;
  }
}

// KHR_materials_unlit: every integrator shows the base colour, lit or not, and nothing
// reflects off it (the point light changes nothing).
TEST(Unlit, EveryIntegratorShowsTheBaseColour) {
  SceneDescription scene;
  MaterialDescription unlit = lambert_like(0.0f);
  unlit.base_colour = C3f(0.3f, 0.5f, 0.7f);
  unlit.unlit = true;
  scene.materials.push_back(unlit);
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "ball"});
  scene.lights.push_back(testing::point_light(V3d(0.0, 3.0, 3.0), 50.0f));
  scene.cameras.push_back(ortho_camera_looking_down_z(3.0, 0.5));
  for (const char* integrator : {"phong", "shadow", "whitted", "path"}) {
    const testing::Rendered r = testing::render_scene(scene, integrator, film(8, 4));
    for (int c = 0; c < 3; ++c)
      EXPECT_FLOAT_EQ(r.image.pixel(4, 4)[c], unlit.base_colour[c]) << integrator << " " << c;
  }
}

TEST(PathIntegrator, ImageIsBitIdenticalAcrossThreadsAndTiles) {
  testing::TestSettings s = film(40, 4);
  s.width = 45;
  s.background = V3f(0.2f);
  s.threads = 1;
  s.tile_size = 8;
  const testing::Rendered one = render_path(mixed_lights_scene(), s, {8, 3, 0});
  s.threads = 2;
  s.tile_size = 16;
  const testing::Rendered two = render_path(mixed_lights_scene(), s, {8, 3, 0});
  ASSERT_EQ(one.image.rgba.size(), two.image.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.image.rgba.data(), two.image.rgba.data(),
                           one.image.rgba.size() * sizeof(float)));
  EXPECT_EQ(one.result.rays.total(), two.result.rays.total());
  EXPECT_GT(one.result.rays[RayKind::bounce], 0u);
}

}  // namespace
}  // namespace prism
