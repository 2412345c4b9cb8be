#include "renderer/shading/light_sampler.h"

#include <algorithm>
#include <cmath>

namespace prism {

namespace {

double luminance(const Imath::V3f& p) {
  // In double: thousands of lights of very different powers sum without losing the small ones.
  return 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
}

std::vector<double> power_weights(const std::vector<LightSource>& lights, float scene_radius) {
  std::vector<double> weight(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) weight[i] = luminance(lights[i].power(scene_radius));
  return weight;
}

}  // namespace

LightSampler::LightSampler(const std::vector<LightSource>& lights, float scene_radius)
    : LightSampler(power_weights(lights, scene_radius)) {}

LightSampler::LightSampler(std::vector<double> weight) {
  if (weight.empty()) return;
  double total = 0.0;
  for (double& w : weight) {
    w = std::isfinite(w) && w > 0.0 ? w : 0.0;
    total += w;
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    std::fill(weight.begin(), weight.end(), 1.0);
    total = static_cast<double>(weight.size());
  }
  cdf_.resize(weight.size());
  double sum = 0.0;
  for (size_t i = 0; i < weight.size(); ++i) {
    sum += weight[i];
    cdf_[i] = sum / total;
  }
  cdf_.back() = 1.0;
  pmf_.resize(cdf_.size());
  for (size_t i = 0; i < cdf_.size(); ++i)
    pmf_[i] = static_cast<float>(cdf_[i] - (i == 0 ? 0.0 : cdf_[i - 1]));
}

}  // namespace prism
