// Stress case 15, the NaN firewall (integrators/tile_loop.h): a sample with non-finite
// radiance is discarded and counted, never averaged into its pixel. The loader rejects
// non-finite numbers, so these scenes are built in code.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "integrators/registry.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kBackground = 0.25f;

// A 2 x 2 floor under an orthographic camera that sees 4 x 4: the floor covers the middle
// quarter of the image, the rest is background. The sun shines straight down.
SceneDescription floor_scene(float sun_intensity) {
  SceneDescription scene;
  scene.materials.push_back(testing::lambert_like(0.5f));
  scene.meshes.push_back(testing::quad_mesh(1.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = sun_intensity;
  sun.direction = V3d(0.0, -1.0, 0.0);
  scene.lights.push_back(sun);
  scene.cameras.push_back(testing::ortho_camera_looking_down_y(5.0, 2.0));
  return scene;
}

testing::TestSettings small_settings() {
  testing::TestSettings s;
  // 0.16 world units a pixel: the floor's edges cut pixels 6 and 18, so some are partial.
  s.width = s.height = 25;
  s.spp = 4;
  s.background = V3f(kBackground);
  s.threads = 2;
  return s;
}

// Camera samples that hit the floor: alpha is hits / spp, exactly, with no discards.
uint64_t hit_samples(const Image& image, int spp) {
  double hits = 0.0;
  for (size_t i = 3; i < image.rgba.size(); i += 4) hits += image.rgba[i] * spp;
  return static_cast<uint64_t>(std::llround(hits));
}

bool all_finite(const Image& image) {
  for (float v : image.rgba)
    if (!std::isfinite(v)) return false;
  return true;
}

const char* const kAllIntegrators[] = {"phong", "shadow",
                                          "whitted"};

// An infinitely (or NaN-) bright sun makes every lit floor sample non-finite. Each of them
// is discarded, so the count is the number of samples that hit the floor in a finite render
// of the same scene; fully covered pixels become 0 with alpha 0, and partly covered ones
// keep only their background samples.
TEST(Stress15NanFirewall, NonFiniteLightSamplesAreDiscardedAndCounted) {
  const testing::TestSettings settings = small_settings();
  for (const char* kind : kAllIntegrators) {
    const auto integrator = make_integrator(kind);
    const testing::Rendered finite =
        testing::render_scene(floor_scene(1.0f), *integrator, settings);
    ASSERT_EQ(finite.result.rays.discarded_samples, 0u);
    const uint64_t hits = hit_samples(finite.image, settings.spp);
    ASSERT_GT(hits, 0u);
    ASSERT_LT(hits, static_cast<uint64_t>(settings.width * settings.height * settings.spp));
    for (float intensity : {kInf, kNaN}) {
      SCOPED_TRACE(std::string(kind) + (std::isnan(intensity) ? " NaN" : " inf"));
      const testing::Rendered r =
          testing::render_scene(floor_scene(intensity), *integrator, settings);
      EXPECT_TRUE(all_finite(r.image));
      EXPECT_EQ(r.result.rays.discarded_samples, hits);
      EXPECT_EQ(r.result.rays[RayKind::camera], finite.result.rays[RayKind::camera]);  // discarded, still cast
      int full = 0, partial = 0, clear = 0;
      for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
          const float* p = r.image.pixel(x, y);
          const float alpha = finite.image.pixel(x, y)[3];
          EXPECT_EQ(p[3], 0.0f) << x << ", " << y;  // no kept sample hit the floor
          if (alpha == 1.0f) {
            ++full;
            EXPECT_EQ(p[0], 0.0f) << x << ", " << y;
            EXPECT_EQ(p[1], 0.0f);
          } else {
            // Only background samples were kept: their mean is the background.
            ++(alpha == 0.0f ? clear : partial);
            EXPECT_EQ(p[0], kBackground) << x << ", " << y;
            EXPECT_EQ(p[2], kBackground);
          }
        }
      }
      EXPECT_GT(full, 0);
      EXPECT_GT(partial, 0);
      EXPECT_GT(clear, 0);
    }
  }
}

// NaN shading normals on every vertex. The hit code falls back to the geometric normal
// (renderer/geometry/embree_scene.cpp), so nothing reaches the firewall: no discards, and the image
// is the flat floor's. With an infinite sun as well, the discards are exactly the floor hits.
TEST(Stress15NanFirewall, NanShadingNormalsNeverReachThePixels) {
  const testing::TestSettings settings = small_settings();
  for (const char* kind : kAllIntegrators) {
    const auto integrator = make_integrator(kind);
    SCOPED_TRACE(kind);
    SceneDescription flat = floor_scene(1.0f);
    flat.meshes[0].primitives[0].normals.clear();
    const testing::Rendered reference = testing::render_scene(flat, *integrator, settings);
    const uint64_t hits = hit_samples(reference.image, settings.spp);

    SceneDescription poisoned = floor_scene(1.0f);
    for (V3f& n : poisoned.meshes[0].primitives[0].normals) n = V3f(kNaN, kNaN, kNaN);
    const testing::Rendered r = testing::render_scene(poisoned, *integrator, settings);
    EXPECT_TRUE(all_finite(r.image));
    EXPECT_EQ(r.result.rays.discarded_samples, 0u);
    EXPECT_EQ(r.image.rgba, reference.image.rgba);

    poisoned.lights[0].intensity = kInf;
    const testing::Rendered both = testing::render_scene(poisoned, *integrator, settings);
    EXPECT_TRUE(all_finite(both.image));
    EXPECT_EQ(both.result.rays.discarded_samples, hits);
  }
}

// A pixel whose every sample is discarded is transparent black, however many samples.
TEST(Stress15NanFirewall, PixelWithEverySampleDiscardedIsTransparentBlack) {
  testing::TestSettings settings = small_settings();
  settings.width = settings.height = 4;
  SceneDescription scene = floor_scene(kInf);
  scene.cameras[0].xmag = scene.cameras[0].ymag = 0.5;  // the floor fills the view
  for (int spp : {1, 7}) {
    settings.spp = spp;
    const auto integrator = make_integrator("whitted");
    const testing::Rendered r = testing::render_scene(scene, *integrator, settings);
    EXPECT_EQ(r.result.rays.discarded_samples, static_cast<uint64_t>(16 * spp));
    for (float v : r.image.rgba) EXPECT_EQ(v, 0.0f);
  }
}

}  // namespace
}  // namespace prism
