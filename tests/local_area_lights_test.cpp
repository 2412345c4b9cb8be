// Emissive surfaces as light for the local model (phong, shadow, whitted): one area-light
// sample per shading (integrators/local_shading.h) against closed forms, against the path
// tracer's direct light on the Cornell box, and bit-identical whatever the threads and tiles.
// The figures each test prints are in docs/accuracy.md.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>

#include "integrators/registry.h"
#include "scene_io/gltf_loader.h"
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

constexpr const char* kLocalIntegrators[] = {"phong", "shadow", "whitted"};

void expect_every_local_integrator_close(const char* scene_name, const SceneDescription& scene,
                                         double exact) {
  for (const char* integrator : kLocalIntegrators) {
    const testing::Rendered r = testing::render_scene(scene, integrator, film(32, 64));
    char what[128];
    std::snprintf(what, sizeof what, "%s, %s", scene_name, integrator);
    expect_close(what, estimate(r.image), exact);
    // At most one shadow ray per hit, for the single area-light term (none where the sample
    // arrives edge-on), and none from phong.
    const uint64_t shadow = r.result.rays[RayKind::shadow], camera = r.result.rays[RayKind::camera];
    if (std::strcmp(integrator, "phong") == 0) {
      EXPECT_EQ(shadow, 0u) << what;
    } else {
      EXPECT_LE(shadow, camera) << what;
      EXPECT_GT(shadow, camera * 9 / 10) << what;
    }
  }
}

// The path tracer's closed forms (tests/path_test.cpp) hold for direct light alone: the floor
// reflects the lamp once, and nothing else reaches it.
TEST(LocalAreaLights, FloorUnderAnEmissiveSphereMatchesTheClosedForm) {
  expect_every_local_integrator_close("sphere lamp", testing::floor_under_sphere(),
                                      testing::floor_under_sphere_exact());
}

TEST(LocalAreaLights, FloorUnderAnEmissiveSquareMatchesTheClosedForm) {
  expect_every_local_integrator_close("square lamp", testing::floor_under_square(),
                                      testing::floor_under_square_exact());
}

// Inside a closed diffuse sphere of albedo rho emitting Le, the wall receives E = pi Le from
// the rest of the wall, so direct light alone sees Le + rho Le = 0.75 for rho = Le = 0.5 (the
// path tracer's 1 is the whole series Le / (1 - rho)).
TEST(LocalAreaLights, InsideAnEmissiveSphereIsEmissionPlusOneReflection) {
  SceneDescription scene;
  scene.materials.push_back(emissive(0.5f, 0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "sphere"});
  scene.cameras.push_back(testing::ortho_camera_looking_down_z(0.0, 0.5));
  expect_every_local_integrator_close("inside an emissive sphere", scene, 0.75);
}

// The Cornell box, lit only by its ceiling panel and with two blocks that cast shadows: the
// shadow integrator's image is the path tracer's with one bounce (emission plus direct light),
// within the two renders' noise, and phong's, which casts no shadow rays, is brighter.
TEST(LocalAreaLights, CornellBoxIsThePathTracersDirectLight) {
  const SceneDescription scene = load_gltf(PRISM_SOURCE_DIR "/scenes/cornell.gltf");
  testing::TestSettings settings = film(48, 64);
  settings.max_depth = 1;
  const testing::Rendered path = testing::render_scene(scene, "path", settings);
  const Image& reference = path.image;
  for (const char* integrator : {"shadow", "whitted"}) {
    const testing::Rendered r = testing::render_scene(scene, integrator, settings);
    const Estimate d = difference(reference, r.image);
    std::printf(
        "cornell, %s: mean %.5f, path to depth 1 %.5f, difference %+.5f +- %.5f (%.2f "
        "sigma)\n",
        integrator, estimate(r.image).mean, estimate(reference).mean, d.mean, d.error,
        d.mean / d.error);
    EXPECT_NEAR(d.mean, 0.0, 4.0 * d.error) << integrator;
  }
  const Estimate unshadowed =
      difference(reference, testing::render_scene(scene, "phong", settings).image);
  std::printf("cornell, phong (no shadow rays) - path: %+.5f +- %.5f\n", unshadowed.mean,
              unshadowed.error);
  EXPECT_GT(unshadowed.mean, 10.0 * unshadowed.error);
}

// A smooth white metal floor (roughness 0.08, which whitted traces as a mirror) under the
// emissive square: whitted's mirror ray meets the panel and brings F Le = 1 (Schlick's F is
// 1 for F0 = 1), and the area-light sample leaves the floor's GGX lobe to that ray, so the
// panel is not counted twice (counted through the lobe as well, the image read 1.78 +- 0.28).
TEST(LocalAreaLights, WhittedCountsAMirroredEmitterOnce) {
  SceneDescription scene = testing::floor_under_square();
  scene.materials[0].metallic = 1.0f;
  scene.materials[0].base_colour = C3f(1.0f);
  scene.materials[0].roughness = 0.08f;
  const testing::Rendered r = testing::render_scene(scene, "whitted", film(16, 16));
  const Estimate e = estimate(r.image);
  std::printf("mirror floor under the square lamp, whitted: %.6f +- %.6f (exact 1)\n", e.mean,
              e.error);
  EXPECT_NEAR(e.mean, 1.0, 1e-5);
  EXPECT_GT(r.result.rays[RayKind::reflection], 0u);
}

TEST(LocalAreaLights, BitIdenticalAcrossThreadsAndTiles) {
  const SceneDescription scene = load_gltf(PRISM_SOURCE_DIR "/scenes/cornell.gltf");
  for (const char* integrator : kLocalIntegrators) {
    testing::TestSettings s = film(40, 4);
    s.width = 45;
    s.threads = 1;
    s.tile_size = 8;
    const testing::Rendered one = testing::render_scene(scene, integrator, s);
    s.threads = 2;
    s.tile_size = 16;
    const testing::Rendered two = testing::render_scene(scene, integrator, s);
    ASSERT_EQ(one.image.rgba.size(), two.image.rgba.size());
    EXPECT_EQ(0, std::memcmp(one.image.rgba.data(), two.image.rgba.data(),
                             one.image.rgba.size() * sizeof(float)))
        << integrator;
    EXPECT_EQ(one.result.rays.total(), two.result.rays.total()) << integrator;
  }
}

}  // namespace
}  // namespace prism
