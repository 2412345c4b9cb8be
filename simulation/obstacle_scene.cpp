#include "simulation/obstacle_scene.h"

#include "scene_io/gltf_loader.h"
#include "scene_passes/sphere_detection.h"

namespace prism {

std::vector<SphereObstacle> scene_spheres(const std::filesystem::path& path, bool detect_spheres) {
  const SceneDescription scene = load_gltf(path.string());
  std::vector<SphereObstacle> spheres;
  const auto add = [&](const V3d& centre, double radius) {
    spheres.push_back({Imath::V3f(static_cast<float>(centre.x), static_cast<float>(centre.y),
                                  static_cast<float>(centre.z)),
                       static_cast<float>(radius)});
  };
  for (const Sphere& s : scene.spheres) add(s.centre, s.radius);
  // A mesh kept as a mesh for rendering (several materials, textures) is still a sphere to
  // fly around, so blocked candidates count too.
  if (detect_spheres)
    for (const SphereCandidate& c : find_sphere_meshes(scene, SphereDetectionOptions{}))
      add(c.centre, c.radius);
  return spheres;
}

}  // namespace prism
