// One choice among every light a path tracer samples: the punctual lights, the area lights
// (renderer/shading/area_lights.h) and the environment, in proportion to their power
// (luminance), through one cumulative table searched in O(log n): a scene of 10^5 emissive
// triangles costs one binary search per sample, never a visit of each.
//
// A scene with a few emissive triangles (at most kMaxNearChoice, no spheres: a Cornell box's
// ceiling panel) has its area lights' share of the choice split again at each shading point,
// by what each triangle brings there (AreaLight::choice_weight: its solid angle times its
// luminance). By power alone, the two halves of a panel are chosen half the time each from
// everywhere, though from a wall beside the panel one half may subtend several times the other;
// split by solid angle, the panel is sampled uniformly within the solid angle of the whole.
// Measured on the Cornell box: relMSE at equal samples 0.85 times that of the choice by power
// (docs/lights.md, "A few area lights"). Each choice then forms every such triangle's view,
// which is why the number is small.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "renderer/shading/area_lights.h"
#include "renderer/shading/environment.h"
#include "renderer/shading/light_sampler.h"
#include "renderer/shading/lights.h"

namespace prism {

enum class EmitterKind : uint8_t { punctual, area, environment };

struct ChosenEmitter {
  EmitterKind kind = EmitterKind::punctual;
  uint32_t index = 0;  // into RenderScene::lights() or area_lights(); 0 for the environment
  float pmf = 0.0f;
  // A triangle chosen by the split near the point: its view from there, for its sample.
  bool has_view = false;
  TriangleView view;
};

class EmitterSampler {
 public:
  EmitterSampler() = default;
  // The environment takes part unless it is black; `scene_radius` sizes the directional
  // lights' and the environment's power.
  // `area` must outlive the sampler (RenderScene owns both): the split near a point reads it.
  EmitterSampler(const std::vector<LightSource>& punctual, const std::vector<AreaLight>& area,
                 const Environment& environment, float scene_radius);

  static constexpr size_t kMaxNearChoice = 4;

  bool empty() const { return table_.empty(); }
  // A light for a shading point at `point`; false when there is nothing to sample. Inline: a
  // path tracer chooses once per vertex.
  bool sample(float u, const Imath::V3f& point, ChosenEmitter* out) const {
    SampledLight chosen;
    if (!table_.sample(u, &chosen)) return false;
    out->pmf = chosen.pmf;
    out->has_view = false;
    if (has_environment_ && chosen.index == environment_index_) {
      out->kind = EmitterKind::environment;
      out->index = 0;
    } else if (chosen.index >= area_offset_) {
      out->kind = EmitterKind::area;
      out->index = chosen.index - area_offset_;
      if (near_choice_) return choose_near(u, point, out);
    } else {
      out->kind = EmitterKind::punctual;
      out->index = chosen.index;
    }
    return out->pmf > 0.0f;
  }
  // The probability sample() chooses area light `index` for a point at `point`.
  float pmf_area(uint32_t index, const Imath::V3f& point) const {
    return near_choice_ ? pmf_near(index, point) : table_.pmf(area_offset_ + index);
  }
  float pmf_environment() const { return has_environment_ ? table_.pmf(environment_index_) : 0.0f; }
  // Whether the area lights' share is split near each point (see the top of this file).
  bool splits_near() const { return near_choice_; }

 private:
  // The split: `u` (the table's, within the area lights' range) chooses among them again.
  bool choose_near(float u, const Imath::V3f& point, ChosenEmitter* out) const;
  float pmf_near(uint32_t index, const Imath::V3f& point) const;

  LightSampler table_;  // punctual lights, then area lights, then the environment
  uint32_t area_offset_ = 0;
  uint32_t environment_index_ = 0;
  bool has_environment_ = false;
  bool near_choice_ = false;
  std::span<const AreaLight> area_;
  double area_cdf_begin_ = 0.0;  // where the area lights' range of u starts
  double area_u_scale_ = 0.0;    // 1 / its width
  float area_share_ = 0.0f;      // the probability the table chooses an area light
};

}  // namespace prism
