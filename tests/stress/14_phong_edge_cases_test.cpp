// Stress case 14: the local shading equation at its edges. Phong exponents 0, 32.5 and
// 1e4 (the cap), R.V <= 0, a point light exactly on (and a hair above) the surface,
// zero-intensity lights and a light inside a closed mesh all give finite results with the
// values docs/stress-shading.md documents:
//   L = I_a (rho_d + k_s) + sum (rho_d / pi + k_s s) E cos(theta_l),
//   s = (n + 2) / (2 pi) max(0, R.V)^n for n > 0, and 1 / pi for n = 0 (uniform, any R.V).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "integrators/local_shading.h"
#include "integrators/registry.h"
#include "renderer/geometry/sphere_mesh.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::ortho_camera_looking_down_y;
using testing::quad_mesh;
using testing::render_scene;

constexpr double kPiD = std::numbers::pi;

// shade_local at one hand-made hit, in a scene holding only `lights`.
struct Shading {
  explicit Shading(std::vector<Light> lights, float ambient = 0.0f) {
    description.lights = std::move(lights);
    description.cameras.push_back(ortho_camera_looking_down_y(1.0, 1.0));
    scene = std::make_unique<RenderScene>(description, GeometryOptions{}, colour);
    camera = std::make_unique<Camera>(scene->camera(description.cameras[0], 4, 4));
    settings.ambient = ambient;
  }
  // A surface at the origin facing +Y.
  float at(const SurfaceResponse& surface, const V3f& to_viewer, bool shadows = true,
           const V3f& position = V3f(0.0f)) {
    SurfaceHit hit;
    hit.position = position;
    hit.geometric_normal = hit.shading_normal = V3f(0.0f, 1.0f, 0.0f);
    const RenderContext context{*scene, *camera, settings};
    const V3f v = normalize(to_viewer);
    const AmbientLight ambient{V3f(settings.ambient)};
    const V3f L = shadows ? shade_local<true>(context, ambient, hit, surface, v, {}, &counters)
                          : shade_local<false>(context, ambient, hit, surface, v, {}, &counters);
    EXPECT_TRUE(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z));
    EXPECT_EQ(L.x, L.y);
    EXPECT_EQ(L.y, L.z);
    return L.x;
  }
  SceneDescription description;
  ColourPipeline colour{WorkingSpace::linear_rec709};
  std::unique_ptr<RenderScene> scene;
  std::unique_ptr<Camera> camera;
  testing::TestSettings settings;
  RayCounters counters;
};

constexpr double kRhoD = 0.3, kKs = 0.2;

SurfaceResponse surface_with_exponent(float n) {
  BsdfLobes lobes;
  lobes.model = BrdfModel::lecture;
  lobes.diffuse_albedo = V3f(static_cast<float>(kRhoD));
  lobes.specular_f0 = V3f(static_cast<float>(kKs));
  lobes.phong_exponent = n;
  SurfaceResponse s{};
  s.bsdf = Bsdf(V3f(0.0f, 1.0f, 0.0f), lobes);  // the surface's normal, as the hit's
  return s;
}

// The documented value for a light of irradiance E at cos_l, seen where R.V = rv.
double expected(double n, double E, double cos_l, double rv) {
  const double lobe =
      n > 0.0 ? (n + 2.0) / (2.0 * kPiD) * std::pow(std::max(0.0, rv), n) : 1.0 / kPiD;
  return (kRhoD / kPiD + kKs * lobe) * E * cos_l;
}

Light sun_from(const V3d& to_light, float intensity) {
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = intensity;
  sun.direction = -to_light.normalized();
  return sun;
}

TEST(StressPhongEdgeCases, ExponentsZeroFractionalAndCapWithRDotVPositiveZeroAndNegative) {
  // Light at 45 degrees in the XY plane: R = (-1, 1, 0) / sqrt 2.
  Shading s({sun_from(V3d(1, 1, 0), 2.0f)});
  const double cos_l = std::sqrt(0.5);
  const V3f along_r(-1.0f, 1.0f, 0.0f);
  const V3f rv_zero(1.0f, 1.0f, 0.0f);      // R.V = 0 exactly
  const V3f rv_negative(1.0f, 0.2f, 0.0f);  // R.V = -0.555
  const V3f near_r(-std::sin(0.7854f + 0.01f), std::cos(0.7854f + 0.01f), 0.0f);
  const double rv_near = static_cast<double>(dot(normalize(near_r), normalize(along_r)));
  for (float n : {0.0f, 32.5f, kMaxPhongExponent}) {
    SCOPED_TRACE(n);
    const SurfaceResponse surface = surface_with_exponent(n);
    const double peak = expected(n, 2.0, cos_l, 1.0);
    EXPECT_NEAR(s.at(surface, along_r), peak, 1e-5 * peak);
    // R.V = 0 and R.V < 0: only the diffuse part, except the uniform n = 0 lobe.
    const double none = expected(n, 2.0, cos_l, 0.0);
    EXPECT_NEAR(s.at(surface, rv_zero), none, 1e-6);
    EXPECT_NEAR(s.at(surface, rv_negative), none, 1e-6);
    // Just off the mirror direction (0.01 rad): n = 1e4 keeps about exp(-0.5) of its peak.
    // (R.V)^n turns R.V's float rounding (a few 6e-8) into a relative error of n times
    // that, 3e-7 n allowed (measured 6e-4 at n = 1e4).
    const double off = expected(n, 2.0, cos_l, rv_near);
    EXPECT_NEAR(s.at(surface, near_r), off, std::max(1e-5, 3e-7 * n) * off);
    if (n == kMaxPhongExponent) {
      EXPECT_NEAR(off / peak, std::exp(-0.5), 0.01);
    }
  }
  // The documented values themselves (E = 2, cos = 1/sqrt 2, rho_d = 0.3, k_s = 0.2).
  EXPECT_NEAR(expected(0.0, 2.0, cos_l, 1.0), 0.225079, 1e-6);
  EXPECT_NEAR(expected(0.0, 2.0, cos_l, -0.5), 0.225079, 1e-6);
  EXPECT_NEAR(expected(32.5, 2.0, cos_l, 1.0), 1.688093, 1e-6);
  EXPECT_NEAR(expected(32.5, 2.0, cos_l, 0.0), 0.135047, 1e-6);
  EXPECT_NEAR(expected(1e4, 2.0, cos_l, 1.0), 450.3832, 1e-4);
  // Through the material: roughness 0 hits the cap, roughness 1 is the uniform lobe, and
  // the roughness for 32.5 (n = 1 / (2 alpha^2) - 1/2) gives 32.5 to float precision.
  EXPECT_EQ(phong_exponent_from_roughness(0.0f), kMaxPhongExponent);
  EXPECT_EQ(phong_exponent_from_roughness(1.0f), 0.0f);
  EXPECT_NEAR(phong_exponent_from_roughness(static_cast<float>(std::pow(0.5 / 33.0, 0.25))), 32.5f,
              1e-3f);
}

TEST(StressPhongEdgeCases, PointLightOnTheSurfaceAndZeroIntensityLightsAddNothing) {
  const SurfaceResponse surface = surface_with_exponent(32.5f);
  // The ambient term alone: I_a times the surface's albedo towards each viewer.
  const V3f up(0, 1, 0), side = normalize(V3f(0.3f, 1, 0));
  const float ambient_only = 0.25f * surface.bsdf.albedo(up, up, false, AlbedoScope::all_lobes).x;
  const float ambient_side = 0.25f * surface.bsdf.albedo(side, up, false, AlbedoScope::all_lobes).x;
  EXPECT_GT(ambient_only, 0.25f * float(kRhoD));
  Light on_surface;
  on_surface.intensity = 5.0f;
  on_surface.position = V3d(0.0);  // exactly at the hit
  Light hair_above = on_surface;
  hair_above.position = V3d(0.0, 1e-20, 0.0);  // d^2 = 1e-40 is subnormal: 1/d^2 overflows
  Light dark_sun = sun_from(V3d(0, 1, 0), 0.0f);
  Light dark_bulb = on_surface;
  dark_bulb.intensity = 0.0f;  // 0 x (1 / 0) would be NaN
  Light dark_bulb_above = dark_bulb;
  dark_bulb_above.position = V3d(0.0, 1.0, 0.0);
  Shading s({on_surface, hair_above, dark_sun, dark_bulb, dark_bulb_above}, 0.25f);
  EXPECT_FLOAT_EQ(s.at(surface, V3f(0, 1, 0)), ambient_only);
  EXPECT_FLOAT_EQ(s.at(surface, V3f(0.3f, 1, 0), false), ambient_side);
  // Nothing arrives, so no light is worth a shadow ray.
  EXPECT_EQ(s.counters[RayKind::shadow], 0u);

  // Rendered: a point light lying in the floor's plane is at grazing incidence (cos = 0)
  // everywhere and at the light itself delivers nothing: the floor is exactly black.
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.8f));
  scene.meshes.push_back(quad_mesh(2.0f, 0.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  Light in_plane;
  in_plane.intensity = 10.0f;
  in_plane.position = V3d(0.0, 0.0, 0.0);  // the centre pixel's hit point
  scene.lights.push_back(in_plane);
  scene.cameras.push_back(ortho_camera_looking_down_y(3.0, 1.0));
  testing::TestSettings settings;
  settings.width = settings.height = 33;
  for (const char* kind : {"phong", "shadow"}) {
    const auto r = render_scene(scene, *make_integrator(kind), settings);
    for (size_t i = 0; i < r.image.rgba.size(); i += 4) ASSERT_EQ(r.image.rgba[i], 0.0f) << i;
    EXPECT_EQ(r.image.pixel(16, 16)[3], 1.0f);  // the floor was hit
  }
}

TEST(StressPhongEdgeCases, LightInsideAClosedMeshLightsOnlyItsInside) {
  constexpr double kRadius = 1.0;
  constexpr int kLevel = 4;
  constexpr float kIntensity = 6.0f;
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.8f));
  // Seen from inside: camera rays cull the back faces of single-sided materials.
  scene.materials[0].double_sided = true;
  scene.meshes.push_back(quad_mesh(6.0f, 0.0f, 0));
  Mesh shell;
  shell.primitives.push_back(tessellate_sphere(Sphere{V3d(0, 2, 0), kRadius, 0, ""}, kLevel));
  scene.meshes.push_back(shell);
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.instances.push_back(MeshInstance{1, M44d(), "shell"});
  Light bulb;
  bulb.intensity = kIntensity;
  bulb.position = V3d(0, 2, 0);
  scene.lights.push_back(bulb);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 4.0));
  CameraDescription inside;
  inside.yfov = 1.5;
  inside.camera_to_world = M44d(1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 2, 0, 1);  // looks down
  scene.cameras.push_back(inside);
  testing::TestSettings settings;
  settings.width = settings.height = 65;

  // From outside, with shadows: the shell's outside faces away from the light and the floor
  // is in its shadow: exactly black. Without shadows the floor is lit and the shell not.
  const auto shadow = render_scene(scene, "shadow", settings);
  const auto phong = render_scene(scene, "phong", settings);
  for (size_t i = 0; i < shadow.image.rgba.size(); i += 4)
    ASSERT_EQ(shadow.image.rgba[i], 0.0f) << i;
  EXPECT_GT(phong.image.pixel(1, 1)[0], 0.0f);    // floor corner, outside the shell
  EXPECT_EQ(phong.image.pixel(32, 32)[0], 0.0f);  // the shell's top, from outside

  // From the light's own position, every camera ray meets the shell's inside head-on: the
  // hit is on the ray, the interpolated normal of the icosphere points from the centre to
  // the hit, so cos = 1, and the distance d lies between r - err and r (the mesh is inside
  // the sphere). A Lambertian albedo of 0.8 scatters uniformly: L = 0.8 / pi * I / d^2.
  const auto from_inside = render_scene(scene, "shadow", settings, {}, 1);
  const double err = tessellation_max_error(kRadius, kLevel);
  const double albedo = 0.8;
  const double lo = albedo / kPiD * kIntensity / (kRadius * kRadius) * (1.0 - 1e-5);
  const double hi = albedo / kPiD * kIntensity / ((kRadius - err) * (kRadius - err)) * (1.0 + 1e-5);
  for (size_t i = 0; i < from_inside.image.rgba.size(); i += 4) {
    ASSERT_GE(from_inside.image.rgba[i], lo) << i;
    ASSERT_LE(from_inside.image.rgba[i], hi) << i;
  }
  EXPECT_EQ(from_inside.result.rays[RayKind::shadow], 65u * 65u);  // one per pixel, none blocked
}

}  // namespace
}  // namespace prism
