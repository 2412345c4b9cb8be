// Scenes whose rendered values are known exactly: the furnace, the orthographic disc's
// coverage, a mirror sphere reflecting a known environment, and the chord a refracted ray
// cuts through a glass sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "integrators/registry.h"
#include "renderer/math.h"
#include "renderer/geometry/sphere_mesh.h"
#include "scene_io/gltf_loader.h"
#include "tests/test_scenes.h"

#ifndef PRISM_SOURCE_DIR
#define PRISM_SOURCE_DIR "."
#endif

namespace prism {
namespace {

using testing::ortho_camera_looking_down_z;
using testing::render_scene;

// The largest angle between the vertex normals of one edge of the tessellated sphere: the
// interpolated shading normal can be at most this far from the true radial direction.
double max_edge_normal_angle(int level) {
  const Primitive p = tessellate_sphere(Sphere{V3d(0.0), 1.0, -1, ""}, level);
  double worst = 0.0;
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    for (int e = 0; e < 3; ++e) {
      const V3d a(p.normals[p.indices[t + e]]), b(p.normals[p.indices[t + (e + 1) % 3]]);
      worst = std::max(worst, std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
    }
  }
  return worst;
}

// pbrt-v4's RadianceMatches: the camera inside a closed Lambertian sphere of radius 1 and
// albedo 0.5 (KHR_materials_specular specularFactor 0: no specular layer), an isotropic point
// light of pi candela at its centre. E = pi / 1^2 on every point, L = 0.5 / pi * E = 0.5.
TEST(AnalyticReference, FurnaceIsExactlyOneHalfInEverySphereMode) {
  SceneDescription scene = load_gltf(PRISM_SOURCE_DIR "/scenes/furnace.gltf");
  ASSERT_EQ(scene.spheres.size(), 1u);
  ASSERT_EQ(scene.lights.size(), 1u);
  testing::TestSettings settings;
  settings.width = settings.height = 64;
  for (const char* kind :
       {"phong", "shadow", "whitted"}) {
    for (const char* mode : {"analytic", "embree-points", "mesh:4"}) {
      SCOPED_TRACE(std::string(std::string(kind)) + " " + mode);
      GeometryOptions options;
      ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
      const auto r = render_scene(scene, *make_integrator(kind), settings, options);
      double tolerance = 1e-5 * 0.5;
      if (options.spheres.mode == SphereMode::mesh) {
        // Faces lie between 1 - s and 1 from the light (s: the level's sagitta), and the
        // interpolated normal is within one edge's normal angle of the light direction, so
        // 0.5 cos(angle) <= L <= 0.5 / (1 - s)^2.
        const double s = tessellation_max_error(1.0, options.spheres.mesh_level);
        const double angle = max_edge_normal_angle(options.spheres.mesh_level);
        tolerance = 0.5 * std::max(1.0 / ((1.0 - s) * (1.0 - s)) - 1.0, 1.0 - std::cos(angle));
      }
      double worst = 0.0;
      for (size_t i = 0; i < r.image.rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(r.image.rgba[i + c] - 0.5));
      EXPECT_LE(worst, tolerance);
      std::printf("furnace %-8s %-14s max |L - 0.5| = %.3g (bound %.3g)\n", kind, mode,
                  worst, tolerance);
    }
  }
}

// The disc's covered area, the sum of alpha, converges to pi r^2 pixels as samples spread
// over each pixel. The bound is the one for independent samples (each silhouette pixel's
// coverage a mean of spp Bernoulli trials, so the error's standard deviation is at most
// sqrt(boundary pixels / (4 spp))); the stratified Owen-scrambled Sobol samples the renderer
// uses (renderer/sampling/sampler.h) can only do better, which tests/sampler_test.cpp measures.
TEST(AnalyticReference, DiscAreaConvergesToPiRSquared) {
  SceneDescription scene;
  scene.materials.push_back(testing::lambert_like(0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "ball"});
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.25));
  testing::TestSettings settings;
  settings.width = settings.height = 101;
  const double r_pixels = 101.0 / 2.5;
  const double area = std::numbers::pi * r_pixels * r_pixels;
  const double boundary_pixels = 2.0 * std::numbers::pi * r_pixels + 8.0;
  double first_error = 0.0;
  for (int spp : {1, 16, 64, 256}) {
    settings.spp = spp;
    const auto r = render_scene(scene, "phong", settings);
    double covered = 0.0;
    for (size_t i = 3; i < r.image.rgba.size(); i += 4) covered += r.image.rgba[i];
    const double error = std::fabs(covered - area);
    std::printf("disc coverage spp %3d: %.2f px of %.2f (error %.2f)\n", spp, covered, area, error);
    if (spp == 1) {
      first_error = error;
      continue;
    }
    EXPECT_LE(error, 4.0 * std::sqrt(boundary_pixels / (4.0 * spp))) << spp;
  }
  EXPECT_GT(first_error, 0.0);  // pixel centres alone miss the exact area
}

// A white metal mirror sphere (F0 = 1: Schlick's F is 1 at every angle) inside a box of six
// emitting walls of different colours that reflect nothing (black base, no specular layer:
// the walls light each other, and would show that through a dielectric layer's F0). Each
// pixel reflects the wall its mirror direction points at, exactly.
TEST(AnalyticReference, MirrorSphereReflectsTheEnvironmentItFaces) {
  SceneDescription scene;
  MaterialDescription mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  scene.materials.push_back(mirror);
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "mirror"});
  const C3f wall_colours[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  // Walls of a cube of half size 50 around the sphere, facing inwards: +x, -x, +y, -y, +z, -z.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int index = axis * 2 + side;
      MaterialDescription wall;
      wall.base_colour = C3f(0.0f);
      wall.metallic = 0.0f;
      wall.specular = 0.0f;
      wall.emissive = wall_colours[index];
      scene.materials.push_back(wall);
      const float s = side == 0 ? 50.0f : -50.0f;
      V3f corner[4];
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const float us[4] = {-50, 50, 50, -50}, vs[4] = {-50, -50, 50, 50};
      for (int k = 0; k < 4; ++k) {
        corner[k][axis] = s;
        corner[k][u] = us[k];
        corner[k][v] = vs[k];
      }
      Mesh mesh;
      Primitive p;
      p.positions.assign(corner, corner + 4);
      p.indices = {0, 1, 2, 0, 2, 3};
      p.material = index + 1;
      mesh.primitives.push_back(p);
      scene.meshes.push_back(mesh);
      scene.instances.push_back(
          MeshInstance{static_cast<int>(scene.meshes.size()) - 1, M44d(), ""});
    }
  }
  scene.cameras.push_back(ortho_camera_looking_down_z(5.0, 1.0));
  testing::TestSettings settings;
  settings.width = settings.height = 64;
  const auto r = render_scene(scene, "whitted", settings);
  int checked = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double px = (2.0 * (x + 0.5) / 64.0 - 1.0), py = (1.0 - 2.0 * (y + 0.5) / 64.0);
      const double rr = px * px + py * py;
      if (rr > 0.95) continue;  // stay off the silhouette, where the ray grazes
      const V3d n(px, py, std::sqrt(1.0 - rr));
      const V3d d(0, 0, -1);
      const V3d reflected = d - 2.0 * d.dot(n) * n;
      // The reflected ray leaves the surface point n (unit sphere) and first reaches the
      // wall with the smallest positive distance; directions that pass near a cube edge
      // (two walls within 1e-3 of each other) are skipped.
      double best = 1e30, runner_up = 1e30;
      int wall = -1;
      for (int a = 0; a < 3; ++a) {
        if (reflected[a] == 0.0) continue;
        const double t = ((reflected[a] > 0 ? 50.0 : -50.0) - n[a]) / reflected[a];
        if (t < best) {
          runner_up = best;
          best = t;
          wall = a * 2 + (reflected[a] > 0 ? 0 : 1);
        } else {
          runner_up = std::min(runner_up, t);
        }
      }
      if (runner_up - best < 1e-3 * best) continue;
      const C3f expected = wall_colours[wall];
      const float* pixel = r.image.pixel(x, y);
      ASSERT_EQ(pixel[0], expected.x) << x << "," << y;
      ASSERT_EQ(pixel[1], expected.y) << x << "," << y;
      ASSERT_EQ(pixel[2], expected.z) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2500);
}

// A ray entering a glass sphere at incidence theta refracts to theta_t and leaves after a
// chord of 2 r cos(theta_t).
TEST(AnalyticReference, RefractedChordThroughAGlassSphere) {
  SceneDescription scene;
  scene.spheres.push_back(Sphere{V3d(0.0), 2.0, -1, "glass"});
  const float eta = 1.5f;
  for (const char* mode : {"analytic", "embree-points"}) {
    GeometryOptions options;
    ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
    const EmbreeScene geometry(scene, options);
    for (double degrees : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0}) {
      SCOPED_TRACE(std::string(mode) + " " + std::to_string(degrees));
      // A ray parallel to -z, at height h = r sin(theta) hits at incidence theta.
      const double theta = degrees * std::numbers::pi / 180.0;
      Ray in;
      in.origin = V3f(0.0f, static_cast<float>(2.0 * std::sin(theta)), 10.0f);
      in.direction = V3f(0, 0, -1);
      SurfaceHit entry;
      ASSERT_TRUE(geometry.intersect(in, &entry));
      ASSERT_FALSE(entry.back_face);
      V3f t;
      ASSERT_TRUE(refract(in.direction, entry.geometric_normal, eta, &t));
      Ray chord;
      chord.origin = offset_ray_origin(entry.position, -entry.geometric_normal);
      chord.direction = t;
      SurfaceHit exit;
      ASSERT_TRUE(geometry.intersect(chord, &exit));
      EXPECT_TRUE(exit.back_face);
      const double sin_t = std::sin(theta) / eta;
      const double expected = 2.0 * 2.0 * std::sqrt(1.0 - sin_t * sin_t);
      EXPECT_NEAR((exit.position - entry.position).length(), expected, 2e-5 * expected);
    }
  }
}

}  // namespace
}  // namespace prism
