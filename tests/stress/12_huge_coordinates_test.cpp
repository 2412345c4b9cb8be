// Stress case 12: huge coordinates. The same scene and camera, once near the world's origin
// and once translated by 1e6 m on every axis, where float's spacing is 6.25 cm. With the
// geometry, the lights and the camera rebased on the camera's position in double
// (GeometryOptions::world_origin, Camera's world_origin), rays live near 0 in both renders
// and the images agree. docs/stress-shading.md has the design and the figures.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "integrators/registry.h"
#include "renderer/geometry/sphere_mesh.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::quad_mesh;

M44d placed(const V3d& translation, const V3d& scale) {
  M44d m;
  m.setScale(scale);
  m[3][0] = translation.x;
  m[3][1] = translation.y;
  m[3][2] = translation.z;
  return m;
}

// A floor, a smooth mesh sphere placed twice (so instanced), an analytic diffuse sphere and
// a mirror sphere, a point light and a spot light, seen by a perspective camera looking
// down at them: every path the renderer has (baked and instanced triangles, analytic
// spheres, shadow and reflection rays, positional lights) at 0 or at `offset`.
SceneDescription test_scene(const V3d& offset) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.7f));
  MaterialDescription shiny = lambert_like(0.9f);
  shiny.roughness = 0.4f;  // a Phong highlight
  scene.materials.push_back(shiny);
  MaterialDescription mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  scene.materials.push_back(mirror);

  scene.meshes.push_back(quad_mesh(4.0f, 0.0f, 0));
  Mesh ball;
  ball.primitives.push_back(tessellate_sphere(Sphere{V3d(0.0), 1.0, 1, ""}, 3));
  scene.meshes.push_back(ball);
  scene.instances.push_back(MeshInstance{0, placed(offset, V3d(1.0)), "floor"});
  scene.instances.push_back(
      MeshInstance{1, placed(offset + V3d(-1.5, 0.5, 0.0), V3d(0.5)), "ball a"});
  scene.instances.push_back(
      MeshInstance{1, placed(offset + V3d(1.5, 0.75, -0.5), V3d(0.7, 0.7, 0.7)), "ball b"});
  scene.spheres.push_back(Sphere{offset + V3d(0.0, 0.625, 0.5), 0.6, 0, "diffuse"});
  scene.spheres.push_back(Sphere{offset + V3d(0.25, 0.375, 1.75), 0.35, 2, "mirror"});

  Light bulb;
  bulb.type = LightType::point;
  bulb.intensity = 20.0f;
  bulb.position = offset + V3d(2.0, 3.0, 2.0);
  scene.lights.push_back(bulb);
  Light spot;
  spot.type = LightType::spot;
  spot.intensity = 30.0f;
  spot.position = offset + V3d(-2.0, 4.0, 1.0);
  spot.direction = V3d(0.4, -1.0, -0.2).normalized();
  spot.outer_cone_angle = 0.6;
  scene.lights.push_back(spot);

  CameraDescription camera;
  camera.name = "view";
  camera.yfov = 0.9;
  camera.camera_to_world.setEulerAngles(V3d(-0.45, 0.1, 0.0));
  camera.camera_to_world[3][0] = offset.x + 0.40625;
  camera.camera_to_world[3][1] = offset.y + 3.0;
  camera.camera_to_world[3][2] = offset.z + 6.0;
  scene.cameras.push_back(camera);
  return scene;
}

Image render_with_origin(const SceneDescription& scene, const V3d& world_origin) {
  testing::TestSettings settings;
  settings.width = 160;
  settings.height = 120;
  settings.max_depth = 4;
  GeometryOptions options;
  options.world_origin = world_origin;
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const RenderScene render_scene(scene, options, colour);
  const Camera camera = render_scene.camera(scene.cameras[0], settings.width, settings.height);
  Image image;
  render(*make_integrator("whitted", {{"max-depth", settings.max_depth}}),
         RenderContext{render_scene, camera, settings}, &image);
  return image;
}

struct Difference {
  double max_abs = 0.0;
  double max_value = 0.0;
  int pixels = 0;  // differing in any channel
};

Difference compare(const Image& a, const Image& b) {
  Difference d;
  for (size_t i = 0; i < a.rgba.size(); i += 4) {
    bool differs = false;
    for (size_t c = 0; c < 4; ++c) {
      const double x = a.rgba[i + c], y = b.rgba[i + c];
      EXPECT_TRUE(std::isfinite(x) && std::isfinite(y));
      d.max_abs = std::max(d.max_abs, std::fabs(x - y));
      d.max_value = std::max(d.max_value, std::fabs(x));
      differs = differs || x != y;
    }
    d.pixels += differs ? 1 : 0;
  }
  return d;
}

TEST(StressHugeCoordinates, SceneTranslatedBy1e6RendersLikeTheOriginalWhenRebased) {
  const V3d far(1e6, 1e6, 1e6);
  const SceneDescription near_scene = test_scene(V3d(0.0));
  const SceneDescription far_scene = test_scene(far);
  const Image reference = render_with_origin(near_scene, camera_position(near_scene.cameras[0]));
  const Image rebased = render_with_origin(far_scene, camera_position(far_scene.cameras[0]));
  const Difference d = compare(reference, rebased);
  std::printf(
      "1e6 away, rebased on the camera: max |difference| %.3g (max value %.3g), %d "
      "pixels differ\n",
      d.max_abs, d.max_value, d.pixels);
  ASSERT_GT(d.max_value, 0.1);  // the image is not black
  // Node translations, sphere centres, light positions and the camera are doubles whose
  // difference from the camera is exact for these values (their fractions are dyadic, so
  // 1e6 + x loses none of them; 1e6 + 0.6 is another scene by 6e-11, which left one pixel
  // one float ulp apart once camera rays were generated in double), so every number the renderer
  // sees is the same in both scenes: the images are expected bit-identical (measured: they are).
  EXPECT_EQ(d.max_abs, 0.0);
  EXPECT_EQ(d.pixels, 0);

  // Near the world's origin, rebasing on the camera instead of (0, 0, 0) moves every float
  // by a few metres, so positions round differently (float's spacing at 6 m is 4.8e-7):
  // most pixels change in their last bits, amplified by the Phong lobe (n = 76 at roughness
  // 0.4). Tolerance 1e-4 of the brightest value; measured 6.15e-5 absolute, 3.3e-5 relative.
  const Image unshifted = render_with_origin(near_scene, V3d(0.0));
  const Difference near = compare(reference, unshifted);
  std::printf("near 0, rebased vs not: max |difference| %.3g, %d pixels differ\n", near.max_abs,
              near.pixels);
  EXPECT_LE(near.max_abs, 1e-4 * near.max_value);

  // Without rebasing, the far scene is visibly broken (6 cm steps on a 0.35 m sphere): the
  // test scene really needs it.
  const Image broken = render_with_origin(far_scene, V3d(0.0));
  const Difference b = compare(reference, broken);
  std::printf("1e6 away, not rebased: max |difference| %.3g, %d pixels differ\n", b.max_abs,
              b.pixels);
  EXPECT_GT(b.pixels, 160 * 120 / 10);
}

}  // namespace
}  // namespace prism
