// glTF's own BRDF in every integrator, against answers worked out here: a plane under a point
// light equals specification Appendix B evaluated in double at every pixel, and a white
// furnace (a uniform environment of 1, no lights) never renders above 1 with any
// material or integrator, and exactly 1 where the material is white and lossless.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/gltf_brdf_reference.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

constexpr double kPiD = std::numbers::pi;

// An orthographic camera 10 m from the origin, looking at it 50 degrees from the vertical.
CameraDescription tilted_ortho_camera(double half_extent) {
  CameraDescription c;
  c.name = "tilted";
  c.projection = Projection::orthographic;
  c.xmag = c.ymag = half_extent;
  const double tilt = 50.0 * kPiD / 180.0;
  // Local -Z (the view direction) to (0, -cos, -sin): a rotation by (90 - 50) degrees about X.
  const double a = -(kPiD / 2 - tilt);
  const M44d rotation(1, 0, 0, 0,                       //
                      0, std::cos(a), std::sin(a), 0,   //
                      0, -std::sin(a), std::cos(a), 0,  //
                      0, 0, 0, 1);
  const V3d forward(0.0, -std::cos(tilt), -std::sin(tilt));
  c.camera_to_world = rotation * M44d().setTranslation(-forward * 10.0);
  return c;
}

TEST(GltfBrdf, PointLitPlaneEqualsAppendixBAtEveryPixel) {
  struct Case {
    float metallic, roughness;
  };
  const Case cases[] = {{1.0f, 0.3f}, {1.0f, 0.5f}, {1.0f, 0.7f}, {0.0f, 0.5f}};
  const C3f base(0.9f, 0.6f, 0.3f);
  const V3d light(0.4, 1.5, -0.3);
  constexpr float kIntensity = 20.0f;  // candela: irradiance I / d^2 facing the light
  for (const Case& c : cases)
    for (const char* integrator : {"phong", "shadow", "whitted"}) {
      SceneDescription scene;
      MaterialDescription m;
      m.base_colour = base;
      m.metallic = c.metallic;
      m.roughness = c.roughness;
      scene.materials.push_back(m);
      scene.meshes.push_back(testing::quad_mesh(4.0f, 0.0f, 0));
      scene.instances.push_back(MeshInstance{0, M44d(), "plane"});
      scene.lights.push_back(testing::point_light(light, kIntensity));
      scene.cameras.push_back(tilted_ortho_camera(2.5));
      testing::TestSettings settings;
      settings.width = settings.height = 96;
      settings.spp = 1;
      const testing::Rendered r = testing::render_scene(scene, integrator, settings);
      // Where each pixel-centre ray meets the plane y = 0, in double.
      const ColourPipeline colour(WorkingSpace::linear_rec709);
      const RenderScene rs(scene, GeometryOptions{}, colour);
      const Camera camera = rs.camera(scene.cameras[0], settings.width, settings.height);
      double worst = 0.0, peak = 0.0;
      int on_plane = 0;
      for (int y = 0; y < settings.height; ++y)
        for (int x = 0; x < settings.width; ++x) {
          const Ray ray = camera.generate_ray(x + 0.5f, y + 0.5f);
          const V3d o(ray.origin.x, ray.origin.y, ray.origin.z);
          const V3d d = V3d(ray.direction.x, ray.direction.y, ray.direction.z).normalized();
          const double t = -o.y / d.y;
          const V3d p = o + d * t;
          if (std::fabs(p.x) > 3.9 || std::fabs(p.z) > 3.9) continue;
          ++on_plane;
          const V3d to_light = light - p;
          const double dist2 = to_light.length2();
          const V3d l = to_light / std::sqrt(dist2);
          const double irradiance = kIntensity / dist2 * l.y;
          for (int ch = 0; ch < 3; ++ch) {
            const double expected =
                testing::appendix_b_brdf(base[ch], c.metallic, double(c.roughness) * c.roughness,
                                         V3d(0, 1, 0), -d, l) *
                irradiance;
            const double got = r.image.pixel(x, y)[ch];
            worst = std::max(worst, std::fabs(got - expected) / expected);
            peak = std::max(peak, expected);
          }
        }
      std::printf("%-8s metallic %.0f roughness %.1f: peak %.4g, worst relative error %.3g\n",
                  integrator, c.metallic, c.roughness, peak, worst);
      EXPECT_GT(on_plane, 90 * 90 / 2);
      EXPECT_LT(worst, 1e-3) << integrator << " metallic " << c.metallic << " roughness "
                             << c.roughness;
    }
}

// One sphere of the material in a furnace of radiance 1 (a uniform environment, which phong
// and shadow take as their ambient term and whitted as well where it traces no ray), seen
// whole by an orthographic camera, so that its disc sweeps every viewing angle from head-on
// at the centre to grazing at the rim.
struct FurnaceCase {
  const char* name;
  MaterialDescription material;
  bool lossless;  // white, and nothing absorbed: exactly 1
};

MaterialDescription material(float rho, float metallic, float roughness, float transmission = 0.0f,
                             float specular = 1.0f) {
  MaterialDescription m;
  m.base_colour = C3f(rho, rho, rho);
  m.metallic = metallic;
  m.roughness = roughness;
  m.transmission = transmission;
  m.specular = specular;
  return m;
}

TEST(GltfBrdf, WhiteFurnaceNeverExceedsOneWithAnyIntegrator) {
  const FurnaceCase cases[] = {
      {"lambert", material(1.0f, 0.0f, 1.0f, 0.0f, 0.0f), true},
      {"rough dielectric", material(1.0f, 0.0f, 0.5f), true},
      {"smooth dielectric", material(1.0f, 0.0f, 0.0f), true},
      {"rough metal", material(1.0f, 1.0f, 0.5f), false},
      {"smooth metal", material(1.0f, 1.0f, 0.0f), true},
      {"glass", material(1.0f, 0.0f, 0.0f, 1.0f), true},
      {"tinted glass", material(0.6f, 0.0f, 0.0f, 1.0f), false},
      {"grey half metal", material(0.5f, 0.5f, 0.05f, 0.5f), false},
  };
  for (const FurnaceCase& c : cases)
    for (BrdfModel brdf : {BrdfModel::gltf, BrdfModel::lecture})
      for (const char* integrator : {"phong", "shadow", "whitted"}) {
        SceneDescription scene;
        scene.materials.push_back(c.material);
        Sphere s;
        s.material = 0;
        scene.spheres.push_back(s);
        scene.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.05));
        testing::TestSettings settings;
        settings.width = settings.height = 80;
        settings.spp = 1;
        settings.background = V3f(1.0f);
        settings.brdf = brdf;
        const testing::Rendered r = testing::render_scene(scene, integrator, settings);
        float highest = 0.0f, lowest = 2.0f;
        for (int y = 0; y < settings.height; ++y)
          for (int x = 0; x < settings.width; ++x)
            for (int ch = 0; ch < 3; ++ch) {
              highest = std::max(highest, r.image.pixel(x, y)[ch]);
              lowest = std::min(lowest, r.image.pixel(x, y)[ch]);
            }
        std::printf("furnace %-17s %-7s %-7s: %.7f .. %.7f\n", c.name, to_string(brdf), integrator,
                    lowest, highest);
        EXPECT_LE(highest, 1.0f + 1e-5f) << c.name << " " << integrator << " " << to_string(brdf);
        if (c.lossless) {
          EXPECT_GE(lowest, 1.0f - 1e-5f) << c.name << " " << integrator << " " << to_string(brdf);
        }
      }
}

}  // namespace
}  // namespace prism
