// Integrators against scenes with analytic answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "integrators/registry.h"
#include "renderer/shading/material.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::ortho_camera_looking_down_y;
using testing::ortho_camera_looking_down_z;
using testing::quad_mesh;
using testing::render_scene;

constexpr float kPi = std::numbers::pi_v<float>;

SceneDescription disc_scene() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, "ball"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = kPi;
  sun.direction = V3d(0.0, 0.0, -1.0);  // travelling away from the camera
  scene.lights.push_back(sun);
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.05));
  return scene;
}

struct DiscMeasurement {
  double centre = 0.0;
  double mean = 0.0;
  double covered_pixels = 0.0;
};

DiscMeasurement measure_disc(const Image& image) {
  DiscMeasurement m;
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      sum += p[0];
      m.covered_pixels += p[3];
    }
  }
  m.mean = sum / m.covered_pixels;
  m.centre = image.pixel(image.width / 2, image.height / 2)[0];
  return m;
}

// Lit straight from the viewer, a Lambertian sphere's radiance is proportional to
// cos(theta) = sqrt(1 - r^2) over the projected disc, whose mean is 2/3 of the centre value.
TEST(OrthographicDisc, MeanIsTwoThirdsOfCentreInEverySphereMode) {
  const auto integrator = make_integrator("shadow");
  testing::TestSettings settings;
  settings.width = settings.height = 401;  // odd: one pixel centre sits on the disc's centre
  for (const char* mode : {"analytic", "embree-points", "mesh:6"}) {
    SCOPED_TRACE(mode);
    GeometryOptions options;
    ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
    const auto r = render_scene(disc_scene(), *integrator, settings, options);
    const DiscMeasurement m = measure_disc(r.image);
    std::printf("disc %-14s centre %.8f  mean/centre %.6f  covered %.0f px\n", mode, m.centre,
                m.mean / m.centre, m.covered_pixels);
    // Centre: rho / pi * E with rho = 0.5, E = pi.
    const double expected_centre = 0.5;
    // Mesh level 6 puts a vertex at the centre; the relative error of the pixel-grid mean is
    // dominated by the silhouette pixels (about 1/401 of the radius).
    EXPECT_NEAR(m.centre, expected_centre, 1e-5 * expected_centre);
    // Measured: 0.666856 (analytic, points) and 0.666819 (mesh:6), from 401 x 401 pixels.
    EXPECT_NEAR(m.mean / m.centre, 2.0 / 3.0, 5e-4);
    // One spp through pixel centres: coverage counts pixel centres inside the disc, within
    // a perimeter's worth of pixels of the disc's area pi r^2.
    const double pixels_per_unit = 401.0 / 2.1;
    const double area = kPi * pixels_per_unit * pixels_per_unit;
    // (The lattice-point error of a circle grows like r^(2/3); 5% of the perimeter is ~60 px.)
    EXPECT_NEAR(m.covered_pixels, area, 0.05 * 2.0 * kPi * pixels_per_unit);
  }
}

// glTF point lights are in candela: a Lambertian plane at distance h straight below a light
// of intensity I receives E = I / h^2 and, with albedo 1, reflects L = E / pi.
TEST(LightUnits, PointLightIrradianceIsIntensityOverDistanceSquared) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(1.0f));
  scene.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  Light bulb;
  bulb.type = LightType::point;
  bulb.intensity = 25.0f;
  bulb.position = V3d(0.0, 2.0, 0.0);
  scene.lights.push_back(bulb);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 4.0));
  testing::TestSettings settings;
  settings.width = settings.height = 81;
  const auto integrator = make_integrator("phong");
  const auto r = render_scene(scene, *integrator, settings);
  const float centre = r.image.pixel(40, 40)[0];
  EXPECT_NEAR(centre, 25.0f / 4.0f / kPi, 1e-5f * centre);
  // A pixel at horizontal distance x: E = I cos(theta) / d^2 = I h / d^3.
  const double x = (2.0 * (60 + 0.5) / 81.0 - 1.0) * 4.0;  // pixel column 60's centre
  const double d = std::sqrt(x * x + 4.0);
  EXPECT_NEAR(r.image.pixel(60, 40)[0], 25.0 * 2.0 / (d * d * d) / kPi, 1e-5);

  // The same light with a range: glTF's window (1 - (d/range)^4)^2 on top of 1/d^2.
  scene.lights[0].range = 4.0;
  const auto ranged = render_scene(scene, *integrator, settings);
  const double window = std::pow(1.0 - std::pow(2.0 / 4.0, 4.0), 2.0);
  EXPECT_NEAR(ranged.image.pixel(40, 40)[0], centre * window, 1e-5);
}

TEST(LightUnits, SpotConeFallsOffBetweenInnerAndOuterAngle) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(1.0f));
  scene.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  Light spot;
  spot.type = LightType::spot;
  spot.intensity = 10.0f;
  spot.position = V3d(0.0, 1.0, 0.0);
  spot.direction = V3d(0.0, -1.0, 0.0);
  spot.inner_cone_angle = 0.2;
  spot.outer_cone_angle = 0.6;
  scene.lights.push_back(spot);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  testing::TestSettings settings;
  settings.width = settings.height = 101;
  const auto r = render_scene(scene, "phong", settings);
  EXPECT_NEAR(r.image.pixel(50, 50)[0], 10.0f / kPi, 1e-5f);  // inside the inner cone
  // Beyond tan(0.6) = 0.684 from the axis nothing arrives: pixel column 50 + 40 is at 1.6.
  EXPECT_EQ(r.image.pixel(90, 50)[0], 0.0f);
  // Between the cones, the smooth step t^2 of glTF's recommendation.
  const double x = (2.0 * (63 + 0.5) / 101.0 - 1.0) * 2.0;  // column 63: 0.51 from the axis
  const double angle = std::atan(x);
  ASSERT_GT(angle, 0.2);
  ASSERT_LT(angle, 0.6);
  const double t = (std::cos(angle) - std::cos(0.6)) / (std::cos(0.2) - std::cos(0.6));
  const double d2 = x * x + 1.0;
  EXPECT_NEAR(r.image.pixel(63, 50)[0], 10.0 * t * t / d2 * std::cos(angle) / kPi, 1e-5);
}

// A ball over a floor, lit and seen from straight above: only `shadow` casts shadow rays,
// one per hit facing the light.
TEST(ShadowIntegrator, OccluderDarkensTheFloorAndCountsItsRays) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(1.0f));
  scene.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.spheres.push_back(Sphere{V3d(0.0, 2.0, 0.0), 0.5, 0, "ball"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 1.0f;
  sun.direction = V3d(0.0, -1.0, 0.0);
  scene.lights.push_back(sun);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  testing::TestSettings settings;
  settings.width = settings.height = 41;
  const auto phong = render_scene(scene, "phong", settings);
  const auto shadow = render_scene(scene, "shadow", settings);
  EXPECT_EQ(phong.result.rays[RayKind::shadow], 0u);
  EXPECT_EQ(shadow.result.rays[RayKind::camera], 41u * 41u);
  // Every camera ray hits the floor or the ball, all facing the light.
  EXPECT_EQ(shadow.result.rays[RayKind::shadow], 41u * 41u);
  // Pixel (0, 0) sees the lit floor, well outside the ball's shadow.
  EXPECT_NEAR(shadow.image.pixel(0, 0)[0], 1.0f / kPi, 1e-6f);
  // Seen from the light's own direction the ball hides its whole shadow, so the two images
  // agree exactly: no shadow ray may find a false occluder (self-intersection).
  EXPECT_EQ(0, std::memcmp(phong.image.rgba.data(), shadow.image.rgba.data(),
                           phong.image.rgba.size() * sizeof(float)));
}

TEST(ShadowIntegrator, ObliqueLightCastsTheBallsShadowOnTheFloor) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(1.0f));
  scene.meshes.push_back(quad_mesh(10.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.spheres.push_back(Sphere{V3d(0.0, 1.0, 0.0), 0.5, 0, "ball"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 1.0f;
  sun.direction = V3d(1.0, -1.0, 0.0).normalized();  // shadow centre lands at x = +1
  scene.lights.push_back(sun);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  testing::TestSettings settings;
  settings.width = settings.height = 41;  // 0.1 units per pixel, centre pixel 20
  const auto phong = render_scene(scene, "phong", settings);
  const auto shadow = render_scene(scene, "shadow", settings);
  const float lit = std::cos(kPi / 4.0f) / kPi;
  // x = +1 (column 30): in the shadow's centre for `shadow`, lit for `phong`.
  EXPECT_NEAR(phong.image.pixel(30, 20)[0], lit, 1e-6f);
  EXPECT_EQ(shadow.image.pixel(30, 20)[0], 0.0f);
  // x = -1 (column 10): lit for both.
  EXPECT_NEAR(shadow.image.pixel(10, 20)[0], lit, 1e-6f);
}

// A perfect white metal mirror (metallic 1, roughness 0) seen head-on reflects the
// background exactly: Schlick's F with F0 = 1 is 1 at every angle.
TEST(WhittedIntegrator, MirrorSphereReflectsTheBackground) {
  SceneDescription scene;
  MaterialDescription mirror;
  mirror.base_colour = C3f(1.0f, 1.0f, 1.0f);
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  scene.materials.push_back(mirror);
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, "mirror"});
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.2));
  testing::TestSettings settings;
  settings.width = settings.height = 31;
  settings.background = V3f(0.25f, 0.5f, 0.75f);
  const auto r = render_scene(scene, "whitted", settings);
  const float* centre = r.image.pixel(15, 15);
  EXPECT_FLOAT_EQ(centre[0], 0.25f);
  EXPECT_FLOAT_EQ(centre[1], 0.5f);
  EXPECT_FLOAT_EQ(centre[2], 0.75f);
  EXPECT_EQ(centre[3], 1.0f);
  EXPECT_GT(r.result.rays[RayKind::reflection], 0u);
  EXPECT_EQ(r.result.rays[RayKind::refraction], 0u);
  EXPECT_EQ(r.result.rays[RayKind::shadow], 0u);  // no lights, no shadow rays
}

// A clear glass sphere neither absorbs nor emits: every path ends in the background, so the
// image of a uniform background through it can only lose energy to the depth limit, never
// gain any, and the loss shrinks as the depth grows.
TEST(WhittedIntegrator, GlassSphereConservesEnergy) {
  SceneDescription scene;
  MaterialDescription glass;
  glass.metallic = 0.0f;
  glass.roughness = 0.0f;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  scene.materials.push_back(glass);
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, "glass"});
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.2));
  testing::TestSettings settings;
  settings.width = settings.height = 31;
  settings.background = V3f(1.0f);
  double previous_loss = 1.0;
  for (int depth : {2, 4, 8, 16}) {
    settings.max_depth = depth;
    const auto r = render_scene(scene, "whitted", settings);
    double worst = 0.0;
    for (size_t i = 0; i < r.image.rgba.size(); i += 4) {
      ASSERT_TRUE(std::isfinite(r.image.rgba[i]));
      ASSERT_LE(r.image.rgba[i], 1.0f + 1e-6f) << "energy gained at depth " << depth;
      worst = std::max(worst, 1.0 - r.image.rgba[i]);
    }
    EXPECT_LE(worst, previous_loss);
    previous_loss = worst;
    // Head-on: 0.04 reflected at entry, then 0.96 * 0.96 through, plus the internal echoes.
    if (depth == 16) {
      EXPECT_NEAR(r.image.pixel(15, 15)[0], 1.0f, 1e-5f);
    }
  }
  EXPECT_LT(previous_loss, 1e-3);
}

// A glossy disc over a floor, seen in an image whose sides are no multiple of a tile or of a
// packet block: for tests that compare renders pixel by pixel.
SceneDescription disc_over_floor() {
  SceneDescription scene = disc_scene();
  scene.materials[0].roughness = 0.3f;
  scene.meshes.push_back(quad_mesh(5.0f, -1.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  return scene;
}
testing::TestSettings odd_sized_settings() {
  testing::TestSettings settings;
  settings.width = 97;
  settings.height = 61;
  settings.spp = 4;
  return settings;
}

TEST(Determinism, ImageIsBitIdenticalWithOneAndTwoThreads) {
  const SceneDescription scene = disc_over_floor();
  testing::TestSettings settings = odd_sized_settings();
  settings.tile_size = 8;
  const auto whitted = make_integrator("whitted");
  settings.threads = 1;
  const auto one = render_scene(scene, *whitted, settings);
  settings.threads = 2;
  settings.tile_size = 16;
  const auto two = render_scene(scene, *whitted, settings);
  ASSERT_EQ(one.image.rgba.size(), two.image.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.image.rgba.data(), two.image.rgba.data(),
                           one.image.rgba.size() * sizeof(float)));
  EXPECT_EQ(one.result.rays.total(), two.result.rays.total());
  // A tile size that is not a multiple of the 4 x 4 camera-ray packet is rounded up to one
  // (renderer/render.cpp), so packets, and the image, stay the same.
  settings.tile_size = 3;
  const auto odd = render_scene(scene, *whitted, settings);
  EXPECT_EQ(0, std::memcmp(one.image.rgba.data(), odd.image.rgba.data(),
                           one.image.rgba.size() * sizeof(float)));
}

// A region's tiles are the full frame's tiles cut to it, widened to whole packet blocks: they
// cover every pixel of the region once and start on the block grid, for any tile size.
TEST(Region, TilesCoverItOnceOnThePacketGrid) {
  RenderSettings s;
  s.width = 97;
  s.height = 61;
  s.region = TileRect{13, 6, 59, 41};
  for (int tile_size : {3, 8, 16, 64}) {
    s.tile_size = tile_size;
    std::vector<int> covered(static_cast<size_t>(s.width) * s.height, 0);
    for (const TileRect& t : make_tiles(s)) {
      EXPECT_EQ(t.x0 % kPacketBlock, 0) << tile_size;
      EXPECT_EQ(t.y0 % kPacketBlock, 0) << tile_size;
      for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) ++covered[static_cast<size_t>(y) * s.width + x];
    }
    int outside_margin = 0, inside_missed = 0;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        const int n = covered[static_cast<size_t>(y) * s.width + x];
        EXPECT_LE(n, 1);
        const bool inside = x >= 13 && x < 59 && y >= 6 && y < 41;
        const bool margin = x >= 12 && x < 60 && y >= 4 && y < 44;  // widened to blocks of 4
        if (inside && n == 0) ++inside_missed;
        if (!margin && n > 0) ++outside_margin;
      }
    EXPECT_EQ(inside_missed, 0) << tile_size;
    EXPECT_EQ(outside_margin, 0) << tile_size;
  }
}

// Tiles are visited in a shuffled order so that any prefix of them, the tiles done when the
// progress line extrapolates its ETA, is spread over the whole frame like the rest: rows
// of cheap sky do not all come first.
TEST(TileOrder, EveryPrefixIsSpreadOverTheFrame) {
  RenderSettings s;
  s.width = 640;
  s.height = 480;
  const std::vector<TileRect> tiles = make_tiles(s);
  ASSERT_EQ(tiles.size(), 40u * 30u);
  for (double share : {0.1, 0.2, 0.5}) {
    const size_t n = static_cast<size_t>(share * static_cast<double>(tiles.size()));
    double mean_y = 0.0;
    int quarter[4] = {};
    for (size_t i = 0; i < n; ++i) {
      const double y = 0.5 * (tiles[i].y0 + tiles[i].y1);
      mean_y += y / static_cast<double>(n);
      ++quarter[static_cast<int>(4.0 * y / s.height)];
    }
    EXPECT_NEAR(mean_y, 240.0, 0.05 * 480.0) << share;
    for (int q = 0; q < 4; ++q) {
      EXPECT_GT(quarter[q], 0.15 * static_cast<double>(n)) << share << " quarter " << q;
      EXPECT_LT(quarter[q], 0.35 * static_cast<double>(n)) << share << " quarter " << q;
    }
  }
}

// Every pixel of a region is the full frame's, bit for bit, whatever the tile size and thread
// count; every pixel outside it is 0 with alpha 0.
TEST(Region, PixelsAreTheFullFramesAndTheRestIsEmpty) {
  const SceneDescription scene = disc_over_floor();
  testing::TestSettings settings = odd_sized_settings();
  const auto whitted = make_integrator("whitted");
  const auto full = render_scene(scene, *whitted, settings);
  settings.region = TileRect{13, 6, 59, 41};
  int lit = 0;
  for (int threads : {1, 2}) {
    settings.threads = threads;
    settings.tile_size = threads == 1 ? 8 : 16;
    const auto part = render_scene(scene, *whitted, settings);
    int differ = 0, not_empty = 0;
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x) {
        const float* a = full.image.pixel(x, y);
        const float* b = part.image.pixel(x, y);
        if (x >= 13 && x < 59 && y >= 6 && y < 41) {
          differ += std::memcmp(a, b, 4 * sizeof(float)) != 0;
          lit += b[3] > 0.0f;
        } else {
          not_empty += b[0] != 0.0f || b[1] != 0.0f || b[2] != 0.0f || b[3] != 0.0f;
        }
      }
    EXPECT_EQ(differ, 0) << threads;
    EXPECT_EQ(not_empty, 0) << threads;
  }
  EXPECT_GT(lit, 100);  // the region sees the scene: the comparison means something
}

}  // namespace
}  // namespace prism
