// Stress case 9: rays inside glass. Total internal reflection, cameras inside a glass sphere
// and a glass slab: no NaN, and with a uniform background of radiance 1 and nothing else
// in the scene no pixel may exceed 1 (a clear dielectric only splits light). From inside an
// analytic sphere every path keeps its angle of incidence, so each pixel has a closed form;
// the same camera inside a finely tessellated glass sphere must agree to a tolerance that
// follows from tessellation_max_error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "integrators/registry.h"
#include "renderer/geometry/sphere_mesh.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::render_scene;

constexpr double kIor = 1.5;
constexpr double kPiD = 3.14159265358979323846;

MaterialDescription clear_glass() {
  MaterialDescription glass;
  glass.metallic = 0.0f;
  glass.roughness = 0.0f;
  glass.transmission = 1.0f;
  glass.ior = static_cast<float>(kIor);
  return glass;
}

CameraDescription perspective(const V3d& position, const V3d& euler, double yfov) {
  CameraDescription c;
  c.yfov = yfov;
  c.camera_to_world.setEulerAngles(euler);
  c.camera_to_world[3][0] = position.x;
  c.camera_to_world[3][1] = position.y;
  c.camera_to_world[3][2] = position.z;
  return c;
}

// Exact dielectric Fresnel for light inside glass meeting the surface at theta (radians),
// in double: 1 under total internal reflection.
double fresnel_from_inside(double theta) {
  const double eta = 1.0 / kIor;  // n_transmitted / n_incident
  const double cos_i = std::cos(theta);
  const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rp * rp + rs * rs);
}

struct Range {
  double lo = 1e30, hi = -1e30;
};

Range check_energy(const Image& image) {
  Range r;
  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) {
      const float v = image.rgba[i + c];
      EXPECT_TRUE(std::isfinite(v));
      r.lo = std::min(r.lo, static_cast<double>(v));
      r.hi = std::max(r.hi, static_cast<double>(v));
    }
  }
  EXPECT_GE(r.lo, 0.0);
  EXPECT_LE(r.hi, 1.0 + 1e-6) << "energy gained";
  return r;
}

TEST(StressGlassInternal, SphereAndSlabNeverGainEnergyFromOutsideOrInside) {
  testing::TestSettings settings;
  settings.width = 96;
  settings.height = 72;
  settings.max_depth = 16;
  settings.background = V3f(1.0f);
  const auto whitted = make_integrator("whitted");

  SceneDescription sphere;
  sphere.materials.push_back(clear_glass());
  sphere.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "glass"});
  sphere.cameras.push_back(perspective(V3d(0.0, 0.5, 3.5), V3d(-0.1, 0.0, 0.0), 0.8));
  sphere.cameras.push_back(perspective(V3d(0.2, -0.3, 0.6), V3d(0.3, 0.9, 0.0), 2.0));

  // A slab 6 x 0.5 x 6 from a flat box mesh, seen from above at an angle and from inside
  // along its length, where most rays meet the faces past the critical angle.
  SceneDescription slab;
  slab.materials.push_back(clear_glass());
  Mesh box;
  Primitive p;
  const float x = 3.0f, y = 0.25f, z = 3.0f;
  p.positions = {V3f(-x, -y, -z), V3f(x, -y, -z), V3f(x, y, -z), V3f(-x, y, -z),
                 V3f(-x, -y, z),  V3f(x, -y, z),  V3f(x, y, z),  V3f(-x, y, z)};
  p.indices = {4, 5, 6, 4, 6, 7, 1, 0, 3, 1, 3, 2, 5, 1, 2, 5, 2, 6,
               0, 4, 7, 0, 7, 3, 7, 6, 2, 7, 2, 3, 0, 1, 5, 0, 5, 4};
  p.material = 0;
  box.primitives.push_back(p);
  slab.meshes.push_back(box);
  slab.instances.push_back(MeshInstance{0, M44d(), "slab"});
  slab.cameras.push_back(perspective(V3d(0.0, 3.0, 6.0), V3d(-0.5, 0.0, 0.0), 0.9));
  slab.cameras.push_back(perspective(V3d(-1.0, 0.05, 0.3), V3d(0.0, -1.2, 0.0), 2.0));

  for (const char* mode : {"analytic", "mesh:6"}) {
    GeometryOptions options;
    ASSERT_TRUE(parse_sphere_options(mode, &options.spheres, nullptr));
    for (int camera : {0, 1}) {
      const auto r = render_scene(sphere, "whitted", settings, options, camera);
      const Range range = check_energy(r.image);
      std::printf("glass sphere %s, camera %s: radiance in [%.6f, %.6f]\n", mode,
                  camera ? "inside" : "outside", range.lo, range.hi);
      EXPECT_GT(r.result.rays[RayKind::refraction], 0u);
    }
  }
  for (int camera : {0, 1}) {
    const auto r = render_scene(slab, "whitted", settings, {}, camera);
    const Range range = check_energy(r.image);
    std::printf("glass slab, camera %s: radiance in [%.6f, %.6f]\n", camera ? "inside" : "outside",
                range.lo, range.hi);
  }
}

// Inside a sphere a chord meets the surface at the same angle at both ends, so a path keeps
// its angle theta: below the critical angle (41.81 degrees for ior 1.5) a pixel sees
// sum_{k<D} F^k (1 - F) = 1 - F^D of the background (D = max_depth); above it the light is
// trapped and the pixel is exactly 0 (no light can get in along that path either).
struct InsideView {
  Image image;
  std::vector<double> theta;  // per pixel, radians; < 0 where the camera ray missed
};

constexpr int kInsideDepth = 5;
constexpr double kBand = 0.5 * kPiD / 180.0;  // pixels this close to critical are skipped

// How far one bounce can move a path's angle of incidence, to first order: a start point
// moved by delta across the chord (towards or away from the centre) turns the next chord by
// delta tan(theta) / r. Every bounce's origin is moved off the surface by offset_ray_origin:
// along n by sum_i |n_i| 256 ulp(p_i) (or 2^-16 near 0), then one more float outward; with
// every |p_i| <= 1 an ulp is at most 2^-23 and sum_i |n_i| <= sqrt 3, so delta is at most
// sqrt(3) 257 2^-23 = 5.3e-5. A mesh adds its distance from the sphere, at most
// tessellation_max_error.
const double kOffset = std::sqrt(3.0) * 257.0 / 8388608.0;

// The largest slope d(1 - F^D)/d(theta) of an escaping pixel, outside the skipped band.
double escaping_slope() {
  const double critical = std::asin(1.0 / kIor);
  double slope = 0.0;
  for (double theta = 0.0; theta < critical - kBand; theta += 1e-4) {
    const double h = 1e-6;
    const double a = 1.0 - std::pow(fresnel_from_inside(theta), kInsideDepth);
    const double b = 1.0 - std::pow(fresnel_from_inside(theta + h), kInsideDepth);
    slope = std::max(slope, std::fabs(b - a) / h);
  }
  return slope;
}

// The first-order bound on a pixel's error when each of the D bounces can move the angle by
// `per_bounce_distance` tan(theta_c) / r.
double pixel_bound(double per_bounce_distance) {
  return escaping_slope() * kInsideDepth * per_bounce_distance * std::tan(std::asin(1.0 / kIor));
}

InsideView render_inside(const GeometryOptions& options) {
  SceneDescription scene;
  scene.materials.push_back(clear_glass());
  scene.spheres.push_back(Sphere{V3d(0.0), 1.0, 0, "glass"});
  // 0.9 from the centre, looking at it: incidence from 0 to 53 degrees across the view.
  scene.cameras.push_back(perspective(V3d(0.0, 0.0, 0.9), V3d(0.0), 2.2));
  testing::TestSettings settings;
  settings.width = settings.height = 80;
  settings.max_depth = kInsideDepth;
  settings.background = V3f(1.0f);
  // The closed form counts the light the traced rays bring; the ambient term's stand-in for
  // the lobes left untraced at the depth limit would add the environment's there.
  settings.environment_ambient = 0.0f;
  InsideView view;
  view.image = render_scene(scene, "whitted", settings, options).image;
  const Camera camera(scene.cameras[0], settings.width, settings.height, V3d(0.0));
  for (int py = 0; py < settings.height; ++py) {
    for (int px = 0; px < settings.width; ++px) {
      const Ray ray = camera.generate_ray(px + 0.5f, py + 0.5f);
      const V3d o(ray.origin), d = V3d(ray.direction).normalized();
      // |o + t d| = 1 with |d| = 1, t > 0.
      const double b = o.dot(d), c = o.dot(o) - 1.0;
      const double t = -b + std::sqrt(b * b - c);
      const V3d hit = o + t * d;
      view.theta.push_back(std::acos(std::min(1.0, d.dot(hit))));
    }
  }
  return view;
}

TEST(StressGlassInternal, CameraInsideAnalyticSphereMatchesTheClosedFormWithTIR) {
  const InsideView view = render_inside({});
  const double critical = std::asin(1.0 / kIor);
  int escaping = 0, trapped = 0;
  double worst = 0.0;
  for (size_t i = 0; i < view.theta.size(); ++i) {
    const double theta = view.theta[i];
    const float value = view.image.rgba[4 * i];
    ASSERT_TRUE(std::isfinite(value));
    if (std::fabs(theta - critical) < kBand) continue;
    if (theta > critical) {
      ++trapped;
      EXPECT_EQ(value, 0.0f) << "pixel " << i << " at " << theta * 180 / kPiD << " degrees";
    } else {
      ++escaping;
      const double expected = 1.0 - std::pow(fresnel_from_inside(theta), kInsideDepth);
      worst = std::max(worst, std::fabs(value - expected));
    }
  }
  std::printf("inside analytic sphere: %d escaping pixels (worst error %.3g), %d trapped\n",
              escaping, worst, trapped);
  EXPECT_GT(escaping, 1000);
  EXPECT_GT(trapped, 1000);
  // The ray-origin offsets of the D bounces, plus float rounding (1e-6).
  const double tolerance = pixel_bound(kOffset) + 1e-6;
  std::printf("  tolerance %.3g (slope %.3g)\n", tolerance, escaping_slope());
  EXPECT_LE(worst, tolerance);
}

TEST(StressGlassInternal, CameraInsideMeshSphereMatchesAnalyticWithinTessellationBound) {
  constexpr int kLevel = 7;
  const InsideView analytic = render_inside({});
  GeometryOptions options;
  options.spheres.mode = SphereMode::mesh;
  options.spheres.mesh_level = kLevel;
  const InsideView mesh = render_inside(options);

  // The tolerance, to first order. The mesh's hit is within err / cos(theta) of the
  // sphere's along the ray; its interpolated normal points from the centre to that hit
  // (the icosphere's vertex normals are the radial unit vectors), so the angle of
  // incidence moves by at most err tan(theta) / r per bounce, on top of the origin offsets
  // both renders have (pixel_bound). Each render is within its bound of the closed form.
  const double err = tessellation_max_error(1.0, kLevel);
  const double critical = std::asin(1.0 / kIor);
  const double tolerance = pixel_bound(err + kOffset) + pixel_bound(kOffset) + 2e-6;
  const double slope = escaping_slope();

  double worst = 0.0;
  int compared = 0;
  for (size_t i = 0; i < analytic.theta.size(); ++i) {
    if (std::fabs(analytic.theta[i] - critical) < kBand) continue;
    const float a = analytic.image.rgba[4 * i], m = mesh.image.rgba[4 * i];
    ASSERT_TRUE(std::isfinite(m));
    worst = std::max(worst, static_cast<double>(std::fabs(a - m)));
    ++compared;
  }
  std::printf(
      "inside mesh:%d vs analytic: err %.3g, slope %.3g, tolerance %.3g, worst %.3g "
      "over %d pixels\n",
      kLevel, err, slope, tolerance, worst, compared);
  EXPECT_LE(worst, tolerance);
}

}  // namespace
}  // namespace prism
