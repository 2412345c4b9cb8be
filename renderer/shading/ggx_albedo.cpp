#include "renderer/shading/ggx_albedo.h"

#include <algorithm>
#include <cmath>

#include "renderer/shading/microfacet.h"

namespace prism {
namespace {

// Tabulated at build time by make_ggx_albedo_table.cpp: kGgxAlbedoTable[roughness][cos_v],
// both from 0 to 1 in equal steps.
#include "renderer/ggx_albedo_table.inc"

}  // namespace

GgxAlbedo ggx_albedo(float cos_v, float alpha) {
  const float x = std::clamp(cos_v, 0.0f, 1.0f) * (kCosSteps - 1);
  const float y = std::clamp(std::sqrt(std::max(alpha, 0.0f)), 0.0f, 1.0f) * (kRoughnessSteps - 1);
  const int i = std::min(int(x), kCosSteps - 2), j = std::min(int(y), kRoughnessSteps - 2);
  const float fx = x - i, fy = y - j;
  const auto at = [&](int di, int dj) { return kGgxAlbedoTable[j + dj][i + di]; };
  const auto lerp2 = [&](float GgxAlbedo::*field) {
    const float bottom = at(0, 0).*field * (1.0f - fx) + at(1, 0).*field * fx;
    const float top = at(0, 1).*field * (1.0f - fx) + at(1, 1).*field * fx;
    return bottom * (1.0f - fy) + top * fy;
  };
  return {lerp2(&GgxAlbedo::e), lerp2(&GgxAlbedo::e_schlick)};
}

}  // namespace prism
