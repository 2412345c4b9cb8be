#include "renderer/render_scene.h"

#include "renderer/colour.h"

namespace prism {

RenderScene::RenderScene(const SceneDescription& scene, const GeometryOptions& options,
                         const ColourPipeline& colour)
    : geometry_(scene, options) {
  textures_.reserve(scene.textures.size());
  for (const TextureImage& image : scene.textures) textures_.emplace_back(image, colour);
  materials_.reserve(scene.materials.size());
  for (const MaterialDescription& m : scene.materials)
    materials_.push_back(make_material(m, textures_, colour));
  default_material_ = make_material(MaterialDescription{}, textures_, colour);
  lights_.reserve(scene.lights.size());
  for (Light light : scene.lights) {
    // Into the geometry's shifted frame, in double (embree_scene.h).
    light.position -= geometry_.world_origin();
    lights_.push_back(make_light_source(light, colour));
  }
}

}  // namespace prism
