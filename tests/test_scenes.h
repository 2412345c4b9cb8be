// Small scenes built in code for tests with analytic answers.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <tbb/task_arena.h>

#include "integrators/registry.h"
#include "renderer/image/colour.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "renderer/scene_description.h"

namespace prism::testing {

inline Light point_light(V3d position, float intensity = 1.0f) {
  Light l;
  l.type = LightType::point;
  l.position = position;
  l.intensity = intensity;
  return l;
}

// A sun whose light travels along `direction`.
inline Light directional_light(V3d direction) {
  Light l;
  l.type = LightType::directional;
  l.direction = direction;
  return l;
}

// A pure Lambertian material, f = rho / pi: a dielectric whose specular layer is switched
// off (KHR_materials_specular's factor 0).
inline MaterialDescription lambert_like(float rho) {
  MaterialDescription m;
  m.base_colour = C3f(rho, rho, rho);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;
  return m;
}

// An orthographic camera at `eye` looking down -Z (or along `forward` rotated frames) with
// half height `ymag`.
inline CameraDescription ortho_camera_looking_down_z(double z, double ymag) {
  CameraDescription c;
  c.name = "ortho";
  c.projection = Projection::orthographic;
  c.xmag = c.ymag = ymag;
  c.camera_to_world = M44d().setTranslation(V3d(0.0, 0.0, z));
  return c;
}

// A camera at height `y` looking straight down -Y.
inline CameraDescription ortho_camera_looking_down_y(double y, double ymag) {
  CameraDescription c;
  c.name = "top";
  c.projection = Projection::orthographic;
  c.xmag = c.ymag = ymag;
  // Local -Z to world -Y: rotate +90 degrees about X.
  c.camera_to_world = M44d(1, 0, 0, 0,   //
                           0, 0, -1, 0,  //
                           0, 1, 0, 0,   //
                           0, y, 0, 1);
  return c;
}

inline Mesh quad_mesh(float half, float y, int material) {
  Mesh mesh;
  Primitive p;
  p.positions = {V3f(-half, y, half), V3f(half, y, half), V3f(half, y, -half),
                 V3f(-half, y, -half)};
  p.normals = {V3f(0, 1, 0), V3f(0, 1, 0), V3f(0, 1, 0), V3f(0, 1, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = material;
  mesh.primitives.push_back(p);
  return mesh;
}

// Renders `scene` with `integrator` and returns the image.
struct Rendered {
  Image image;
  RenderResult result;
};

// What a test render sets besides the film, gathered so that tests read as one list of
// settings: the thread count (a task arena, as the session's), the integrator's parameters
// (given to those integrators that take them) and the scene's environment.
struct TestSettings : RenderSettings {
  int threads = 0;
  int max_depth = 5;
  float ambient = 0.0f;
  float environment_ambient = 1.0f;
  V3f background{0.0f, 0.0f, 0.0f};
  // A map instead of the uniform `background`, when set.
  std::optional<Environment> environment;
  BrdfModel brdf = BrdfModel::gltf;
};

// The integrator `name` with the settings' parameters that it takes.
inline std::unique_ptr<Integrator> make_test_integrator(std::string_view name,
                                                        const TestSettings& settings) {
  const IntegratorInfo* info = find_integrator(name);
  if (!info) throw std::invalid_argument("no integrator " + std::string(name));
  ParameterSettings given;
  if (takes_parameter(*info, "max-depth")) given["max-depth"] = settings.max_depth;
  if (takes_parameter(*info, "ambient")) given["ambient"] = settings.ambient;
  if (takes_parameter(*info, "environment-ambient"))
    given["environment-ambient"] = settings.environment_ambient;
  return configure_integrator(*info, given).integrator;
}

// The scene stays in world coordinates unless options.world_origin says otherwise, so that
// analytic tests see exactly the coordinates they wrote (`prism render` rebases on the
// camera; tests/stress/12_huge_coordinates_test.cpp checks that path).
inline Rendered render_scene(const SceneDescription& scene, const Integrator& integrator,
                             const TestSettings& settings, const GeometryOptions& options = {},
                             int camera = 0) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const CameraDescription& description = scene.cameras.at(static_cast<size_t>(camera));
  tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
  Rendered r;
  arena.execute([&] {
    const RenderScene render_scene(scene, options, colour,
                                   settings.environment.value_or(Environment(settings.background)),
                                   settings.brdf);
    const Camera cam = render_scene.camera(description, settings.width, settings.height);
    r.result = render(integrator, RenderContext{render_scene, cam, settings}, &r.image);
  });
  return r;
}
inline Rendered render_scene(const SceneDescription& scene, std::string_view integrator,
                             const TestSettings& settings, const GeometryOptions& options = {},
                             int camera = 0) {
  return render_scene(scene, *make_test_integrator(integrator, settings), settings, options,
                      camera);
}

}  // namespace prism::testing
