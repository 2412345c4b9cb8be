#include "scene_passes/scene_defaults.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace prism {

M44d look_at(const V3d& eye, const V3d& target, const V3d& world_up) {
  const V3d back = (eye - target).normalized();  // the camera looks down its -Z
  V3d right = world_up.cross(back);
  if (right.length() < 1e-9) right = V3d(1, 0, 0);
  right.normalize();
  const V3d up = back.cross(right);
  return M44d(right.x, right.y, right.z, 0, up.x, up.y, up.z, 0, back.x, back.y, back.z, 0, eye.x,
              eye.y, eye.z, 1);
}

Imath::Box3d world_bounds(const SceneDescription& scene) {
  Imath::Box3d box;
  for (const MeshInstance& inst : scene.instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size())) continue;
    for (const Primitive& p : scene.meshes[inst.mesh].primitives) {
      for (const V3f& v : p.positions) {
        V3d w;
        inst.object_to_world.multVecMatrix(V3d(v), w);
        box.extendBy(w);
      }
    }
  }
  for (const Sphere& s : scene.spheres) {
    box.extendBy(s.centre - V3d(s.radius));
    box.extendBy(s.centre + V3d(s.radius));
  }
  return box;
}

Light default_key_light(const CameraDescription& camera) {
  const M44d& m = camera.camera_to_world;
  const V3d right = V3d(m[0][0], m[0][1], m[0][2]).normalized();
  const V3d up = V3d(m[1][0], m[1][1], m[1][2]).normalized();
  const V3d back = V3d(m[2][0], m[2][1], m[2][2]).normalized();
  Light light;
  light.name = "default key light";
  light.type = LightType::directional;
  light.intensity = std::numbers::pi_v<float>;
  // From behind the camera, above and to its right: close enough to the view that the
  // faces the camera sees mostly face the light too, far enough that shading shows shape.
  light.direction = -(back + 0.5 * up + 0.35 * right).normalized();
  return light;
}

bool has_emissive_geometry(const SceneDescription& scene) {
  const auto emits = [&](int material) {
    if (material < 0 || material >= static_cast<int>(scene.materials.size())) return false;
    const C3f& e = scene.materials[static_cast<size_t>(material)].emissive;
    return e.x > 0.0f || e.y > 0.0f || e.z > 0.0f;
  };
  for (const MeshInstance& inst : scene.instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size())) continue;
    for (const Primitive& p : scene.meshes[static_cast<size_t>(inst.mesh)].primitives)
      if (!p.indices.empty() && emits(p.material)) return true;
  }
  for (const Sphere& s : scene.spheres)
    if (emits(s.material)) return true;
  return false;
}

CameraDescription framing_camera(const SceneDescription& scene, const std::string& name) {
  Imath::Box3d box = world_bounds(scene);
  if (box.isEmpty()) box = Imath::Box3d(V3d(-1.0), V3d(1.0));
  const V3d centre = box.center();
  const double radius = std::max(0.5 * box.size().length(), 1e-6);
  CameraDescription camera;
  camera.name = name;
  camera.yfov = 0.8;
  // Far enough that the bounding sphere fits the vertical field of view, with a margin.
  const double distance = 1.1 * radius / std::sin(0.5 * camera.yfov);
  const V3d eye = centre + V3d(0.35, 0.3, 1.0).normalized() * distance;
  camera.camera_to_world = look_at(eye, centre, V3d(0, 1, 0));
  camera.znear = distance * 1e-4;
  return camera;
}

void add_scene_defaults(SceneDescription* scene) {
  if (scene->cameras.empty()) {
    scene->cameras.push_back(framing_camera(*scene, "default"));
    scene->warnings.push_back(
        "the scene has no camera: using a default perspective camera that frames the whole scene");
  }
  if (scene->lights.empty() && !has_emissive_geometry(*scene)) {
    scene->lights.push_back(default_key_light(scene->cameras.front()));
    scene->default_lighting = true;
    scene->default_sky = kDefaultSky;
    char sky[160];
    std::snprintf(sky, sizeof sky,
                  "a grey sky of radiance %g at the zenith to %g at the nadir, not seen by the "
                  "camera, unless the render names an environment or background",
                  double(kDefaultSky.zenith), double(kDefaultSky.nadir));
    scene->warnings.push_back(
        "the scene has no light: added a directional key light of pi lux from over the "
        "camera's right shoulder and " +
        std::string(sky) + " (docs/lights.md)");
  }
}

}  // namespace prism
