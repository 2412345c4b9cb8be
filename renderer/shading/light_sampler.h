// Chooses one light for a shading point, in proportion to its power (pbrt-v4's
// PowerLightSampler), so that an integrator sampling one light per hit spends its shadow
// rays where the light is, and a scene with thousands of lights costs one ray per hit, not
// thousands. The Whitted integrators still sum every light: that is their model.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "renderer/shading/lights.h"

namespace prism {

struct SampledLight {
  uint32_t index = 0;  // into RenderScene::lights()
  float pmf = 0.0f;    // the probability it was chosen
};

class LightSampler {
 public:
  LightSampler() = default;
  // `scene_radius` sizes directional lights' power (LightSource::power). Lights of zero or
  // non-finite power are never chosen; if every light is so, each is chosen uniformly.
  LightSampler(const std::vector<LightSource>& lights, float scene_radius);
  // Over any items, by their weights (non-negative; non-finite counts as zero), with the same
  // fallback to a uniform choice when none is positive.
  explicit LightSampler(std::vector<double> weights);

  bool empty() const { return cdf_.empty(); }
  // The light whose share of the cumulative power contains u in [0, 1); false when there
  // are no lights.
  // Inline, with the probabilities tabulated: a path tracer chooses once per vertex.
  bool sample(float u, SampledLight* out) const {
    if (cdf_.empty()) return false;
    // The first light whose cumulative share exceeds u; zero-power lights have cdf equal to
    // their predecessor's and are skipped by upper_bound.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), static_cast<double>(u));
    const size_t i = std::min(static_cast<size_t>(it - cdf_.begin()), cdf_.size() - 1);
    out->index = static_cast<uint32_t>(i);
    out->pmf = pmf_[i];
    return true;
  }
  // The probability sample() chooses light `index`.
  float pmf(uint32_t index) const { return index < pmf_.size() ? pmf_[index] : 0.0f; }
  // The cumulative share of lights [0, index): sample() chooses from `first` to `last - 1`
  // exactly when cdf_below(first) <= u < cdf_below(last).
  double cdf_below(uint32_t index) const { return index == 0 ? 0.0 : cdf_[index - 1]; }

 private:
  std::vector<double> cdf_;  // cdf_[i] = power of lights [0, i] / total; cdf_.back() = 1
  std::vector<float> pmf_;   // cdf_[i] - cdf_[i - 1], rounded once
};

}  // namespace prism
