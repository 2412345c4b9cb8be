// Everything an integrator reads: the geometry's BVH, the materials with their textures, and
// the lights, all in the working colour space. Built once per scene.
//
// Positions (geometry, hits, lights) are in the frame shifted by
// GeometryOptions::world_origin; camera() makes cameras whose rays are too.
#pragma once

#include <memory>
#include <vector>

#include "renderer/camera.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/scene_features.h"
#include "renderer/shading/area_lights.h"
#include "renderer/shading/emitter_sampler.h"
#include "renderer/shading/environment.h"
#include "renderer/shading/light_sampler.h"
#include "renderer/shading/lights.h"
#include "renderer/shading/material.h"
#include "renderer/shading/texture.h"

namespace prism {

class ColourPipeline;

class RenderScene {
 public:
  // Builds the geometry on `device` (not null), which it keeps alive. `brdf` is the glossy
  // lobe every material evaluates (renderer/shading/bsdf.h).
  RenderScene(std::shared_ptr<EmbreeDevice> device, const SceneDescription& scene,
              const GeometryOptions& options, const ColourPipeline& colour,
              const Environment& environment = {}, BrdfModel brdf = BrdfModel::gltf);
  // On an Embree device of its own.
  RenderScene(const SceneDescription& scene, const GeometryOptions& options,
              const ColourPipeline& colour, const Environment& environment = {},
              BrdfModel brdf = BrdfModel::gltf);

  const EmbreeScene& geometry() const { return geometry_; }
  // A camera whose rays live in the same shifted frame as the geometry and lights, and start
  // at the geometry's bounds.
  Camera camera(const CameraDescription& description, int image_width, int image_height) const {
    return Camera(description, image_width, image_height, geometry_.world_origin(),
                  geometry_.bounds());
  }
  // The scene's lights that deliver anything; dark_lights() counts those left out.
  const std::vector<LightSource>& lights() const { return lights_; }
  size_t dark_lights() const { return dark_lights_; }
  // Chooses a light in proportion to its power, for integrators that sample one light per
  // hit instead of visiting them all (renderer/shading/light_sampler.h).
  const LightSampler& light_sampler() const { return light_sampler_; }
  const Environment& environment() const { return environment_; }
  // The environment changes nothing the build made: a render scene takes each job's own
  // (and the light choices that weigh it against the scene's lights follow).
  void set_environment(const Environment& environment);
  // The emissive triangles and spheres as lights, indexed by SurfaceHit::emitter.
  const std::vector<AreaLight>& area_lights() const { return area_lights_; }
  // Chooses among the punctual lights, the area lights and the environment by power, for
  // integrators that sample every kind of light (integrators/path.cpp).
  const EmitterSampler& emitter_sampler() const { return emitter_sampler_; }
  // Chooses among the area lights alone, for the integrators that visit every punctual light
  // and take the environment as ambient light (integrators/local_shading.h).
  const EmitterSampler& area_light_sampler() const { return area_light_sampler_; }
  // The material at a hit, -1 being glTF's default material (white, metallic 1, rough 1).
  const Material& material(int index) const {
    return index >= 0 && index < static_cast<int>(materials_.size()) ? materials_[index]
                                                                     : default_material_;
  }
  bool has_textures() const { return !textures_.empty(); }
  // What the scene uses, derived once here for the sphere mode the geometry was built with:
  // the integrators specialise on it (integrators/shading_flags.h).
  const SceneFeatures& features() const { return features_; }

 private:
  // In this order: materials point into textures_, the geometry's alpha filters into
  // materials_ (renderer/geometry/alpha_filter.h).
  std::vector<Texture> textures_;
  std::vector<Material> materials_;
  Material default_material_;
  EmbreeScene geometry_;
  std::vector<LightSource> lights_;
  size_t dark_lights_ = 0;
  LightSampler light_sampler_;
  Environment environment_;
  std::vector<AreaLight> area_lights_;  // point into materials_
  EmitterSampler emitter_sampler_;
  EmitterSampler area_light_sampler_;
  float scene_radius_ = 1.0f;  // a sphere around the geometry: sizes infinite lights' power
  SceneFeatures features_;
};

}  // namespace prism
