// Light culling (renderer/shading/light_culling.h) and the shadow queue's light chunks
// (integrators/shadow_queue.h): culling never drops a light that lights the point, and a
// scene with more lights than one chunk gets every light's term and shadow ray.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "integrators/registry.h"
#include "renderer/image/colour.h"
#include "renderer/render_scene.h"
#include "renderer/shading/light_culling.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::ortho_camera_looking_down_y;
using testing::quad_mesh;
using testing::render_scene;

// Random lights of every kind (ranged and unlimited points, spots with narrow and wider-than-
// hemisphere cones, directional), random points around them and random unit normals. Where
// light_may_reach says no, LightSource::sample or N . L <= 0 must say no too; and of the
// cases they reject for range, cone or side, culling must catch at least 99 % (the margins
// are 1e-5 in a cosine, so only points within a hair of an edge slip through).
TEST(LightCulling, RejectsOnlyLightsThatCannotReachAndNearlyAllOfThose) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_unit = [&] {
    V3d v;
    do v = V3d(unit(rng), unit(rng), unit(rng));
    while (v.length2() < 1e-3 || v.length2() > 1.0);
    return v.normalized();
  };
  int culled = 0, rejected = 0;
  for (int l = 0; l < 400; ++l) {
    Light light;
    light.type = l % 4 == 0 ? LightType::directional : l % 2 ? LightType::spot : LightType::point;
    light.intensity = 5.0f;
    light.position = 2.0 * V3d(unit(rng), unit(rng), unit(rng));
    light.direction = random_unit();
    light.range = l % 3 == 0 ? 0.0 : 0.5 + 2.0 * (unit(rng) + 1.0);
    light.inner_cone_angle = 0.1 + 0.2 * (unit(rng) + 1.0);
    light.outer_cone_angle = light.inner_cone_angle + (l % 5 == 0 ? 1.6 : 0.3);
    const LightSource source(light, colour);
    for (int k = 0; k < 500; ++k) {
      const V3f point(4.0 * V3d(unit(rng), unit(rng), unit(rng)));
      const V3f n(random_unit());
      LightSample arrival;
      const bool reaches =
          source.sample(point, Imath::V2f(0.0f), &arrival) && dot(n, arrival.wi) > 0.0f;
      const bool may = light_may_reach(source, point, n);
      if (reaches) {
        ASSERT_TRUE(may) << "light " << l << " point " << point << " normal " << n;
      } else {
        ++rejected;
        culled += !may;
      }
    }
  }
  std::printf("culled %d of %d light/point pairs that cannot reach\n", culled, rejected);
  EXPECT_GT(rejected, 50000);
  EXPECT_GE(culled, 0.99 * rejected);
}

// 20 ranged point lights (more than ShadowQueue::kLightsPerChunk) over a Lambertian floor
// seen from above, and a ball outside every light's range so the scene can cast shadows:
// each pixel is the sum of the lights' terms, I window^2 cos / (pi d^2), and exactly one
// shadow ray leaves per (hit, light) pair that light reaches, whichever chunk it is in. The
// terms are formed here at the pixel centre's exact floor point, the renderer's at its
// ray's hit: 1e-4 relative leaves room for that rounding where a range's window is steep,
// while a lost or doubled light would be off by a whole term.
TEST(ShadowIntegrator, EveryLightBeyondTheFirstChunkIsShadedAndCounted) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(1.0f));
  scene.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.spheres.push_back(Sphere{V3d(9.0, 1.0, 9.0), 0.5, 0, "ball"});
  for (int i = 0; i < 20; ++i) {
    Light light;
    light.intensity = 1.0f + 0.1f * static_cast<float>(i);
    light.position = V3d(-1.8 + 0.9 * (i % 5), 0.4 + 0.05 * i, -1.5 + 1.0 * (i / 5));
    light.range = 1.2;
    scene.lights.push_back(light);
  }
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  testing::TestSettings settings;
  settings.width = settings.height = 41;
  const auto r = render_scene(scene, "shadow", settings);
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  uint64_t pairs = 0;
  double worst = 0.0;
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      // Pixel centres on the floor: image x is world x, image y world z.
      const V3f p(static_cast<float>((2.0 * (x + 0.5) / 41 - 1.0) * 2.0), 0.0f,
                  static_cast<float>((2.0 * (y + 0.5) / 41 - 1.0) * 2.0));
      double expected = 0.0;
      for (const Light& light : scene.lights) {
        LightSample arrival;
        if (!LightSource(light, colour).sample(p, Imath::V2f(0.0f), &arrival)) continue;
        if (arrival.wi.y <= 0.0f) continue;
        ++pairs;
        expected += arrival.radiance.x * arrival.wi.y / std::numbers::pi;
      }
      const double got = r.image.pixel(x, y)[0];
      worst = std::max(worst, std::fabs(got - expected) / std::max(expected, 1e-3));
    }
  }
  EXPECT_EQ(r.result.rays[RayKind::shadow], pairs);
  EXPECT_GT(pairs, 41u * 41u);  // on average a floor point sees more than one light
  EXPECT_LT(worst, 1e-4) << "largest relative difference from the sum of the lights' terms";
}

// A light that delivers nothing is left out of the render scene's list (it would cost every
// hit a culling test for no light), and the image and the shadow rays are those of the scene
// without it, bit for bit.
TEST(ShadowIntegrator, DarkLightsAreLeftOutAndChangeNothing) {
  SceneDescription lit;
  lit.materials.push_back(lambert_like(0.8f));
  lit.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  lit.instances.push_back(MeshInstance{0, M44d(), "floor"});
  lit.spheres.push_back(Sphere{V3d(0.3, 0.6, 0.2), 0.4, 0, "ball"});
  Light bright;
  bright.intensity = 3.0f;
  bright.position = V3d(-0.5, 2.0, 0.4);
  lit.lights.push_back(bright);
  lit.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  SceneDescription with_dark = lit;
  Light zero_intensity = bright;
  zero_intensity.intensity = 0.0f;
  Light black_colour = bright;
  black_colour.colour = C3f(0.0f, 0.0f, 0.0f);
  with_dark.lights = {zero_intensity, bright, black_colour};

  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const RenderScene built(with_dark, GeometryOptions{}, colour);
  ASSERT_EQ(built.lights().size(), 1u);
  EXPECT_EQ(built.dark_lights(), 2u);
  EXPECT_EQ(built.lights()[0].intensity().x, LightSource(bright, colour).intensity().x);

  testing::TestSettings settings;
  settings.width = settings.height = 24;
  const auto a = render_scene(lit, "shadow", settings);
  const auto b = render_scene(with_dark, "shadow", settings);
  EXPECT_GT(a.result.rays[RayKind::shadow], 0u);
  EXPECT_EQ(b.result.rays[RayKind::shadow], a.result.rays[RayKind::shadow]);
  ASSERT_EQ(a.image.rgba.size(), b.image.rgba.size());
  EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), b.image.rgba.data(),
                           a.image.rgba.size() * sizeof(float)));
}

}  // namespace
}  // namespace prism
