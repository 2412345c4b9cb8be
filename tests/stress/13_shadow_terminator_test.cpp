// Stress case 13: the shadow terminator. A low-poly sphere with smooth normals, lit from the
// side: the shading normal says "lit" up to the smooth terminator, but the flat triangles
// lie inside the smooth surface, and a shadow ray leaving the flat triangle near the
// terminator runs into the sphere's own neighbouring triangles. Hanika's fix (SurfaceHit::
// terminator_offset, used by integrators/local_shading.h) starts the ray on the smooth
// surface instead. docs/stress-shading.md has the figures.
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
using testing::ortho_camera_looking_down_z;
using testing::render_scene;

// The icosphere as an ordinary smooth-shaded mesh (baked, as a glTF mesh would be), so the
// fix is tested on the general triangle path rather than the sphere mode.
SceneDescription low_poly_sphere(int level, const V3d& light_direction) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.8f));
  Mesh mesh;
  mesh.primitives.push_back(tessellate_sphere(Sphere{V3d(0.0), 1.0, 0, "ball"}, level));
  scene.meshes.push_back(mesh);
  scene.instances.push_back(MeshInstance{0, M44d(), "ball"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 3.0f;
  sun.direction = light_direction.normalized();
  scene.lights.push_back(sun);
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.1));
  return scene;
}

struct TerminatorCount {
  int lit_pixels = 0;        // shading N.L > 0.1
  int shadowed_by_self = 0;  // of those, dark in the shadow render
  int naive_occluded = 0;    // of those, occluded from the unfixed origin
  int grazing_pixels = 0;    // 0 < N.L <= 0.1, reported only
  int grazing_shadowed = 0;
};

// Renders with and without shadow rays; only the sphere is in the scene, so a pixel that
// differs between the two, where the shading normal faces the light, was shadowed by the
// sphere itself.
TerminatorCount count_terminator(int level, const V3d& light_direction) {
  const SceneDescription scene = low_poly_sphere(level, light_direction);
  testing::TestSettings settings;
  settings.width = settings.height = 256;
  const auto phong = render_scene(scene, "phong", settings);
  const auto shadow = render_scene(scene, "shadow", settings);

  const EmbreeScene geometry(scene, {});
  const Camera camera(scene.cameras[0], settings.width, settings.height, V3d(0.0));
  const V3f to_light = -normalize(V3f(light_direction));
  TerminatorCount count;
  for (int y = 0; y < settings.height; ++y) {
    for (int x = 0; x < settings.width; ++x) {
      const Ray ray = camera.generate_ray(x + 0.5f, y + 0.5f);
      SurfaceHit hit;
      if (!geometry.intersect(ray, &hit)) continue;
      const V3f n = face_forward(hit.shading_normal, -ray.direction);
      const float cos_light = dot(n, to_light);
      if (cos_light <= 0.0f) continue;
      const bool differs = shadow.image.pixel(x, y)[0] != phong.image.pixel(x, y)[0];
      if (cos_light <= 0.1f) {
        // Hanika's point is still inside the smooth surface by a second-order term; at the
        // last few degrees before the terminator that is enough to be shadowed.
        ++count.grazing_pixels;
        count.grazing_shadowed += differs ? 1 : 0;
        continue;
      }
      ++count.lit_pixels;
      count.shadowed_by_self += differs ? 1 : 0;
      // The origin before the fix: the hit point pushed to the light's side of the flat
      // triangle, which near the terminator is its back.
      Ray naive;
      naive.origin = offset_ray_origin(hit.position, face_forward(hit.geometric_normal, to_light));
      naive.direction = to_light;
      if (geometry.occluded(naive)) ++count.naive_occluded;
    }
  }
  return count;
}

TEST(StressShadowTerminator, SmoothLowPolySphereIsNeverShadowedByItselfWhereNDotLAbove0_1) {
  // Grazing light from the side (the terminator runs down the middle of the image), and two
  // tilted directions so that the terminator crosses the facets at other angles.
  const V3d directions[] = {V3d(-1.0, 0.0, 0.0), V3d(-1.0, -0.3, 0.2), V3d(-0.4, 1.0, 0.3)};
  for (int level : {1, 2}) {
    int naive_total = 0;
    for (const V3d& d : directions) {
      SCOPED_TRACE(::testing::Message()
                   << "level " << level << " direction " << d.x << " " << d.y << " " << d.z);
      const TerminatorCount c = count_terminator(level, d);
      std::printf(
          "terminator level %d dir (%.1f %.1f %.1f): %d pixels with N.L > 0.1, "
          "%d shadowed by the sphere (fixed), %d occluded from the unfixed origin; "
          "0 < N.L <= 0.1: %d of %d shadowed\n",
          level, d.x, d.y, d.z, c.lit_pixels, c.shadowed_by_self, c.naive_occluded,
          c.grazing_shadowed, c.grazing_pixels);
      // A 256 x 256 image of a disc covering 65% of it, about half of it lit.
      ASSERT_GT(c.lit_pixels, 10000);
      EXPECT_EQ(c.shadowed_by_self, 0);
      naive_total += c.naive_occluded;
    }
    // The scene really has the problem: from the unfixed origin a band of pixels along the
    // terminator is shadowed by the sphere itself (measured: 821 at level 1, 65 at level 2).
    EXPECT_GT(naive_total, 0);
  }
}

}  // namespace
}  // namespace prism
