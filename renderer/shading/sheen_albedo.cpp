#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "renderer/shading/clearcoat_sheen.h"

namespace prism {
namespace {

constexpr int kCosSteps = 32, kRoughnessSteps = 32, kTableStrata = 64;

using SheenTable = std::array<std::array<float, kCosSteps>, kRoughnessSteps>;

// Integrated once per process, on the first sheen material's first lookup (a scene without
// sheen never builds it): 1024 entries of 64 x 128 points (about 0.1 s on one core;
// docs/accuracy.md).
const SheenTable& sheen_table() {
  static const SheenTable table = [] {
    SheenTable t{};
    for (int j = 0; j < kRoughnessSteps; ++j) {
      const float roughness = float(j) / float(kRoughnessSteps - 1);
      for (int i = 0; i < kCosSteps; ++i) {
        // Nodes at cos_v = x^2; cos_v = 0 is the limit of grazing views.
        const float x = float(i) / float(kCosSteps - 1);
        const float cos_v = std::max(1e-4f, x * x);
        t[j][i] = integrate_sheen_albedo(cos_v, roughness * roughness, kTableStrata);
      }
    }
    return t;
  }();
  return table;
}

}  // namespace

float integrate_sheen_albedo(float cos_v, float alpha, int strata) {
  alpha = std::max(alpha, kMinSheenAlpha);
  cos_v = std::clamp(cos_v, 1e-4f, 1.0f);
  const float sin_v = std::sqrt(1.0f - cos_v * cos_v);
  // f cos_l = D V cos_l is even in phi (v lies in the xz plane): phi over [0, pi], doubled.
  const int phi_strata = 2 * strata;
  std::vector<float> cos_phi(phi_strata), sin_phi(phi_strata);
  for (int b = 0; b < phi_strata; ++b) {
    const float phi = kPi * (b + 0.5f) / phi_strata;
    cos_phi[b] = std::cos(phi);
    sin_phi[b] = std::sin(phi);
  }
  double total = 0.0;
  for (int a = 0; a < strata; ++a) {
    const float cos_l = (a + 0.5f) / strata;
    const float sin_l = std::sqrt(1.0f - cos_l * cos_l);
    const float v = charlie_visibility(cos_l, cos_v, alpha);
    for (int b = 0; b < phi_strata; ++b) {
      const float hx = sin_l * cos_phi[b] + sin_v, hy = sin_l * sin_phi[b];
      const float hz = cos_l + cos_v;
      const float cos_h = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      total += double(charlie_d(cos_h, alpha) * v * cos_l);
    }
  }
  // d omega = d cos_l d phi; the doubled half-circle covers 2 pi.
  return float(total * (1.0 / strata) * (2.0 * kPi / phi_strata));
}

float sheen_albedo(float cos_v, float alpha) {
  const SheenTable& t = sheen_table();
  const float x = std::sqrt(std::clamp(cos_v, 0.0f, 1.0f)) * (kCosSteps - 1);
  const float y = std::clamp(std::sqrt(std::max(alpha, 0.0f)), 0.0f, 1.0f) * (kRoughnessSteps - 1);
  const int i = std::min(int(x), kCosSteps - 2), j = std::min(int(y), kRoughnessSteps - 2);
  const float fx = x - i, fy = y - j;
  const float bottom = t[j][i] * (1.0f - fx) + t[j][i + 1] * fx;
  const float top = t[j + 1][i] * (1.0f - fx) + t[j + 1][i + 1] * fx;
  return bottom * (1.0f - fy) + top * fy;
}

}  // namespace prism
