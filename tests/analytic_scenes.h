// Scenes with known answers and the estimates tests measure them by, shared by the path
// tracer's tests and the local model's (tests/path_test.cpp, tests/local_area_lights_test.cpp):
// each test prints what it measured with the noise its bound is made of (docs/accuracy.md).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/test_scenes.h"

namespace prism::testing {

inline constexpr double kPiD = std::numbers::pi;

// The image's mean red value and the standard error of that mean: pixels are independent
// (each has its own scrambled samples), so the error is their spread over sqrt(count).
struct Estimate {
  double mean = 0.0;
  double error = 0.0;
};

inline Estimate estimate(const Image& image) {
  double sum = 0.0, sum2 = 0.0;
  const double n = double(image.width) * image.height;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double v = image.pixel(x, y)[0];
      sum += v;
      sum2 += v * v;
    }
  const double mean = sum / n;
  const double variance = std::max(0.0, sum2 / n - mean * mean);
  return {mean, std::sqrt(variance / (n - 1.0))};
}

inline TestSettings film(int size, int spp) {
  TestSettings s;
  s.width = s.height = size;
  s.spp = spp;
  return s;
}

// Asserts |measured - exact| within four standard errors, plus float rounding (2e-5 of the
// value: samples are formed and summed in float; the sphere's cone sampling, whose estimate is
// all but noiseless, measured 1e-5), and prints the figures.
inline void expect_close(const char* what, const Estimate& e, double exact) {
  std::printf("%s: %.6f +- %.6f (exact %.6f, error %+.6f = %.2f sigma)\n", what, e.mean, e.error,
              exact, e.mean - exact, (e.mean - exact) / std::max(e.error, 1e-12));
  EXPECT_NEAR(e.mean, exact, 4.0 * e.error + 2e-5 * exact) << what;
}

inline MaterialDescription emissive(float radiance, float albedo = 0.0f) {
  MaterialDescription m = lambert_like(albedo);
  m.emissive = C3f(radiance, radiance, radiance);
  return m;
}

// A Lambert floor (rho = 0.5) under an emissive sphere of radius R, radiance Le, centre at
// height d: the irradiance below it is pi Le (R / d)^2, so the floor sends rho Le (R / d)^2.
inline SceneDescription floor_under_sphere() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.5f));
  scene.materials.push_back(emissive(2.0f));
  scene.meshes.push_back(quad_mesh(50.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.spheres.push_back(Sphere{V3d(0.0, 3.0, 0.0), 1.0, 1, "lamp"});
  scene.cameras.push_back(ortho_camera_looking_down_y(0.5, 0.02));
  return scene;
}

// The same floor under a square of side 2 at height 2 made of two emissive triangles: the
// form factor from a point below a corner of an a x b rectangle at height h is
// (1 / 2 pi) [A / sqrt(1 + A^2) atan(B / sqrt(1 + A^2)) + B / sqrt(1 + B^2) atan(A / sqrt(1 +
// B^2))] with A = a / h, B = b / h; four such corners meet below the centre, and the floor sends
// rho Le F.
inline SceneDescription floor_under_square() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.5f));
  scene.materials.push_back(emissive(1.0f));
  scene.meshes.push_back(quad_mesh(50.0f, 0.0f, 0));
  scene.meshes.push_back(quad_mesh(1.0f, 2.0f, 1));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.instances.push_back(MeshInstance{1, M44d(), "panel"});
  scene.cameras.push_back(ortho_camera_looking_down_y(0.5, 0.02));
  return scene;
}

inline double square_form_factor(double half, double h) {
  const double a = half / h;
  const double s = std::sqrt(1.0 + a * a);
  return 4.0 * (2.0 * a / s * std::atan(a / s)) / (2.0 * kPiD);
}

// The mean of b - a over the pixels and its standard error: the images' own structure cancels
// in the differences, which leaves the two estimates' noise.
inline Estimate difference(const Image& a, const Image& b) {
  double sum = 0.0, sum2 = 0.0;
  const double n = double(a.width) * a.height;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double d = double(b.pixel(x, y)[0]) - a.pixel(x, y)[0];
      sum += d;
      sum2 += d * d;
    }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1.0))};
}

// The floor_under_sphere() image: at a distance r from the point below the centre the floor
// sends rho Le R^2 d / (d^2 + r^2)^(3/2), averaged over the camera's square.
inline double floor_under_sphere_exact() {
  double exact = 0.0;
  constexpr int kCells = 200;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      const double x = -0.02 + 0.04 * (i + 0.5) / kCells, z = -0.02 + 0.04 * (j + 0.5) / kCells;
      exact += 0.5 * 2.0 * 3.0 / std::pow(9.0 + x * x + z * z, 1.5);
    }
  return exact / (kCells * kCells);
}

// The floor_under_square() image: rho Le F below the centre (the camera's square is small).
inline double floor_under_square_exact() {
  return 0.5 * 1.0 * square_form_factor(1.0, 2.0);
}

}  // namespace prism::testing
