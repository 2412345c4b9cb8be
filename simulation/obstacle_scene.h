// Obstacles from a glTF file: its analytic spheres (PRISM_sphere, docs/spheres.md) and, when
// asked, its meshes that are tessellated spheres (the test `prism render --detect-spheres`
// uses, scene_passes/sphere_detection.h), so any shape approximated by spheres can stand in
// a flock's way.
#pragma once

#include <filesystem>
#include <vector>

#include "simulation/flock_config.h"

namespace prism {

// Loads `path` as untrusted input (the loader's default options) and returns its spheres in
// world space, the analytic ones first. Throws LoadError (scene_io/gltf_loader.h).
std::vector<SphereObstacle> scene_spheres(const std::filesystem::path& path, bool detect_spheres);

}  // namespace prism
