// One choice among every light a path tracer samples: the punctual lights, the area lights
// (renderer/shading/area_lights.h) and the environment, in proportion to their power
// (luminance), through one cumulative table searched in O(log n): a scene of 10^5 emissive
// triangles costs one binary search per sample, never a visit of each.
#pragma once

#include <cstdint>
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
};

class EmitterSampler {
 public:
  EmitterSampler() = default;
  // The environment takes part unless it is black; `scene_radius` sizes the directional
  // lights' and the environment's power.
  EmitterSampler(const std::vector<LightSource>& punctual, const std::vector<AreaLight>& area,
                 const Environment& environment, float scene_radius);

  bool empty() const { return table_.empty(); }
  // False when there is nothing to sample. Inline: a path tracer chooses once per vertex.
  bool sample(float u, ChosenEmitter* out) const {
    SampledLight chosen;
    if (!table_.sample(u, &chosen)) return false;
    out->pmf = chosen.pmf;
    if (has_environment_ && chosen.index == environment_index_) {
      out->kind = EmitterKind::environment;
      out->index = 0;
    } else if (chosen.index >= area_offset_) {
      out->kind = EmitterKind::area;
      out->index = chosen.index - area_offset_;
    } else {
      out->kind = EmitterKind::punctual;
      out->index = chosen.index;
    }
    return out->pmf > 0.0f;
  }
  // The probability sample() chooses each.
  float pmf_area(uint32_t index) const { return table_.pmf(area_offset_ + index); }
  float pmf_environment() const { return has_environment_ ? table_.pmf(environment_index_) : 0.0f; }

 private:
  LightSampler table_;  // punctual lights, then area lights, then the environment
  uint32_t area_offset_ = 0;
  uint32_t environment_index_ = 0;
  bool has_environment_ = false;
};

}  // namespace prism
