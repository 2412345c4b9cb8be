// The GGX albedo integral by quadrature (ggx_albedo.h): compiled into the renderer and into
// the build-time program that tabulates it (make_ggx_albedo_table.cpp).
#include <algorithm>
#include <cmath>

#include "renderer/shading/ggx_albedo.h"
#include "renderer/shading/microfacet.h"

namespace prism {

GgxAlbedo integrate_ggx_albedo(float cos_v, float alpha, int strata) {
  if (!(alpha > 0.0f)) return {1.0f, schlick_weight(cos_v)};  // a mirror
  alpha = std::max(alpha, kMinGgxAlpha);
  cos_v = std::clamp(cos_v, 1e-4f, 1.0f);
  const Imath::V3f v(std::sqrt(1.0f - cos_v * cos_v), 0.0f, cos_v);
  // Visible normals drawn with density G1(v) D(h) max(0, v.h) / cos_v: for the reflected
  // direction l, f cos_l / pdf(l) = 4 V cos_l cos_v / G1(v) = G2(l, v) / G1(v).
  const float g1 = ggx_g1(cos_v, alpha);
  double e = 0.0, es = 0.0;
  // The light lost below the horizon comes from visible normals far from the view, u.x near
  // 1, which a midpoint rule in u.x misses at small alpha: u.x = 1 - (1 - t)^3 puts the
  // strata there (weight 3 (1 - t)^2), and 128 strata reach about 1e-5.
  for (int a = 0; a < strata; ++a)
    for (int b = 0; b < strata; ++b) {
      const double t = (a + 0.5) / strata;
      const double jacobian = 3.0 * (1.0 - t) * (1.0 - t);
      const Imath::V2f u(float(1.0 - (1.0 - t) * (1.0 - t) * (1.0 - t)), (b + 0.5f) / strata);
      const Imath::V3f h = sample_ggx_visible_normal(v, alpha, u);
      const float v_h = v.dot(h);
      const Imath::V3f l = h * (2.0f * v_h) - v;
      if (!(l.z > 0.0f) || !(v_h > 0.0f)) continue;
      const double weight = jacobian * 4.0 * ggx_visibility(l.z, cos_v, alpha) * l.z * cos_v / g1;
      e += weight;
      es += weight * schlick_weight(v_h);
    }
  const double n = double(strata) * strata;
  return {float(std::min(1.0, e / n)), float(std::min(1.0, es / n))};
}

}  // namespace prism
