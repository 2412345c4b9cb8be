#include "renderer/shading/emitter_sampler.h"

#include <algorithm>

namespace prism {
namespace {

// In double: the table sums the powers of up to 10^5 lights.
double power_luminance(const Imath::V3f& p) {
  return 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
}

}  // namespace

EmitterSampler::EmitterSampler(const std::vector<LightSource>& punctual,
                               const std::vector<AreaLight>& area, const Environment& environment,
                               float scene_radius) {
  std::vector<double> weights;
  weights.reserve(punctual.size() + area.size() + 1);
  for (const LightSource& light : punctual)
    weights.push_back(power_luminance(light.power(scene_radius)));
  area_offset_ = static_cast<uint32_t>(weights.size());
  for (const AreaLight& light : area) weights.push_back(power_luminance(light.power()));
  has_environment_ = !environment.black();
  environment_index_ = static_cast<uint32_t>(weights.size());
  if (has_environment_) weights.push_back(power_luminance(environment.power(scene_radius)));
  table_ = LightSampler(std::move(weights));
  const auto area_end = static_cast<uint32_t>(area_offset_ + area.size());
  area_cdf_begin_ = table_.cdf_below(area_offset_);
  const double area_cdf_end = table_.cdf_below(area_end);
  area_share_ = static_cast<float>(area_cdf_end - area_cdf_begin_);
  area_u_scale_ = area_cdf_end > area_cdf_begin_ ? 1.0 / (area_cdf_end - area_cdf_begin_) : 0.0;
  near_choice_ = area.size() >= 2 && area.size() <= kMaxNearChoice && area_share_ > 0.0f &&
                 std::all_of(area.begin(), area.end(), [](const AreaLight& light) {
                   return light.primitive().shape == EmissivePrimitive::Shape::triangle;
                 });
  if (near_choice_) area_ = std::span<const AreaLight>(area);
}

bool EmitterSampler::choose_near(float u, const Imath::V3f& point, ChosenEmitter* out) const {
  const size_t n = area_.size();
  TriangleView views[kMaxNearChoice];
  float weights[kMaxNearChoice];
  float total = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    views[i] = area_[i].view_from(point);
    weights[i] = area_[i].choice_weight(point, views[i]);
    total += weights[i];
  }
  if (!(total > 0.0f)) return false;
  // u within the area lights' range, stretched back to [0, 1): the choice among them.
  const double stretched = (static_cast<double>(u) - area_cdf_begin_) * area_u_scale_;
  float pick = static_cast<float>(std::clamp(stretched, 0.0, 1.0)) * total;
  size_t k = 0;
  while (k + 1 < n && pick >= weights[k]) pick -= weights[k++];
  // Rounding may leave the pick on a light of no weight at the end: the last one that has some.
  while (weights[k] == 0.0f) --k;
  out->index = static_cast<uint32_t>(k);
  out->pmf = area_share_ * (weights[k] / total);
  out->has_view = true;
  out->view = views[k];
  return out->pmf > 0.0f;
}

float EmitterSampler::pmf_near(uint32_t index, const Imath::V3f& point) const {
  float total = 0.0f, chosen = 0.0f;
  for (size_t i = 0; i < area_.size(); ++i) {
    const float w = area_[i].choice_weight(point, area_[i].view_from(point));
    total += w;
    if (i == index) chosen = w;
  }
  return total > 0.0f ? area_share_ * (chosen / total) : 0.0f;
}

}  // namespace prism
