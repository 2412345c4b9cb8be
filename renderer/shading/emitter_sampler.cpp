#include "renderer/shading/emitter_sampler.h"

namespace prism {
namespace {

double luminance(const Imath::V3f& p) {
  return 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
}

}  // namespace

EmitterSampler::EmitterSampler(const std::vector<LightSource>& punctual,
                               const std::vector<AreaLight>& area, const Environment& environment,
                               float scene_radius) {
  std::vector<double> weights;
  weights.reserve(punctual.size() + area.size() + 1);
  for (const LightSource& light : punctual) weights.push_back(luminance(light.power(scene_radius)));
  area_offset_ = static_cast<uint32_t>(weights.size());
  for (const AreaLight& light : area) weights.push_back(luminance(light.power()));
  has_environment_ = !environment.black();
  environment_index_ = static_cast<uint32_t>(weights.size());
  if (has_environment_) weights.push_back(luminance(environment.power(scene_radius)));
  table_ = LightSampler(std::move(weights));
}

}  // namespace prism
