#include "renderer/render_scene.h"

#include <memory>
#include <utility>

#include "renderer/image/colour.h"

namespace prism {
namespace {

std::vector<Material> make_materials(const SceneDescription& scene,
                                     const std::vector<Texture>& textures,
                                     const ColourPipeline& colour) {
  std::vector<Material> materials;
  materials.reserve(scene.materials.size());
  for (const MaterialDescription& m : scene.materials)
    materials.push_back(make_material(m, textures, colour));
  return materials;
}

}  // namespace

RenderScene::RenderScene(const SceneDescription& scene, const GeometryOptions& options,
                         const ColourPipeline& colour)
    : RenderScene(std::make_shared<EmbreeDevice>(), scene, options, colour) {}

RenderScene::RenderScene(std::shared_ptr<EmbreeDevice> device, const SceneDescription& scene,
                         const GeometryOptions& options, const ColourPipeline& colour)
    : textures_(make_textures(scene.textures, colour)),
      materials_(make_materials(scene, textures_, colour)),
      default_material_(make_material(MaterialDescription{}, textures_, colour)),
      geometry_(std::move(device), scene, options, materials_),
      features_(derive_scene_features(scene, options.spheres)) {
  lights_.reserve(scene.lights.size());
  for (Light light : scene.lights) {
    // Into the geometry's shifted frame, in double (embree_scene.h).
    light.position -= geometry_.world_origin();
    lights_.push_back(make_light_source(light, colour));
  }
}

}  // namespace prism
