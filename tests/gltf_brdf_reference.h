// glTF 2.0's BRDF (specification Appendix B) written out in double, independently of
// renderer/shading/, for tests to compare the renderer's against: one channel of base colour
// rho, metallic m, alpha = roughness^2, ior 1.5 (F0 0.04), no extensions.
#pragma once

#include <cmath>
#include <numbers>

#include <Imath/ImathVec.h>

namespace prism::testing {

// `n`, `v` (to the viewer) and `l` (to the light) unit; 0 below either horizon.
inline double appendix_b_brdf(double rho, double m, double alpha, const Imath::V3d& n,
                              const Imath::V3d& v, const Imath::V3d& l) {
  const double nl = n.dot(l), nv = n.dot(v);
  if (nl <= 0.0 || nv <= 0.0) return 0.0;
  const Imath::V3d h = (v + l).normalized();
  const double vh = v.dot(h), nh = n.dot(h);
  const double a2 = alpha * alpha;
  const double denom = nh * nh * (a2 - 1.0) + 1.0;
  const double d = a2 / (std::numbers::pi * denom * denom);
  const double vis =
      0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
  const double s = std::pow(1.0 - vh, 5.0);
  const double metal_brdf = (rho + (1.0 - rho) * s) * vis * d;  // conductor_fresnel
  const double fr = 0.04 + 0.96 * s;                            // fresnel_mix
  const double dielectric_brdf = (1.0 - fr) * rho / std::numbers::pi + fr * vis * d;
  return (1.0 - m) * dielectric_brdf + m * metal_brdf;
}

}  // namespace prism::testing
