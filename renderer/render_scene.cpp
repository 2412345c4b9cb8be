#include "renderer/render_scene.h"

#include <cmath>
#include <memory>
#include <utility>

#include "renderer/image/colour.h"

namespace prism {
namespace {

std::vector<Material> make_materials(const SceneDescription& scene,
                                     const std::vector<Texture>& textures,
                                     const ColourPipeline& colour, BrdfModel brdf) {
  std::vector<Material> materials;
  materials.reserve(scene.materials.size());
  for (const MaterialDescription& m : scene.materials)
    materials.push_back(make_material(m, textures, colour, brdf));
  return materials;
}

}  // namespace

RenderScene::RenderScene(const SceneDescription& scene, const GeometryOptions& options,
                         const ColourPipeline& colour, const Environment& environment,
                         BrdfModel brdf)
    : RenderScene(std::make_shared<EmbreeDevice>(), scene, options, colour, environment, brdf) {}

RenderScene::RenderScene(std::shared_ptr<EmbreeDevice> device, const SceneDescription& scene,
                         const GeometryOptions& options, const ColourPipeline& colour,
                         const Environment& environment, BrdfModel brdf)
    : textures_(make_textures(scene.textures, colour)),
      materials_(make_materials(scene, textures_, colour, brdf)),
      default_material_(make_material(MaterialDescription{}, textures_, colour, brdf)),
      geometry_(std::move(device), scene, options, materials_),
      environment_(environment),
      features_(derive_scene_features(scene, options.spheres)) {
  lights_.reserve(scene.lights.size());
  for (Light light : scene.lights) {
    // Into the geometry's shifted frame, in double (embree_scene.h).
    light.position -= geometry_.world_origin();
    LightSource source(light, colour);
    // A light that delivers nothing would still cost every hit its culling test and its
    // sample() call, and a share of the light choices' bookkeeping: it is left out. (The
    // scene still has it: whether a default light is added was decided on the description.)
    if (source.dark())
      ++dark_lights_;
    else
      lights_.push_back(source);
  }
  // A sphere around the geometry sizes directional lights' power for the light sampler.
  const Imath::Box3f bounds = geometry_.bounds();
  const float radius = bounds.isEmpty() ? 1.0f : 0.5f * (bounds.max - bounds.min).length();
  scene_radius_ = std::isfinite(radius) && radius > 0.0f ? radius : 1.0f;
  light_sampler_ = LightSampler(lights_, scene_radius_);
  area_lights_ = make_area_lights(geometry_.emitters(), materials_, default_material_);
  emitter_sampler_ = EmitterSampler(lights_, area_lights_, environment_, scene_radius_);
  area_light_sampler_ = EmitterSampler({}, area_lights_, Environment(), scene_radius_);
}

void RenderScene::set_environment(const Environment& environment) {
  environment_ = environment;
  // The environment's share of the light choices follows its power.
  emitter_sampler_ = EmitterSampler(lights_, area_lights_, environment_, scene_radius_);
}

}  // namespace prism
