// The directional albedo of glTF's GGX lobe, tabulated once per process: what a uniform
// environment of radiance 1 reflects towards a viewer at cos_v from the normal,
//   e         = integral of D V cos_l            over the hemisphere (Fresnel 1),
//   e_schlick = integral of (1 - v.h)^5 D V cos_l,
// so that a layer with Fresnel F0 + (F90 - F0)(1 - v.h)^5 reflects F0 e + (F90 - F0) e_schlick
// of it. The ambient term (the lecture's I_a k_a) is this albedo; its real-time name is the
// split-sum "DFG" table of image-based lighting.
#pragma once

namespace prism {

struct GgxAlbedo {
  float e = 1.0f;
  float e_schlick = 0.0f;
};

// Bilinear in (cos_v, roughness) over a 32 x 32 table whose first row is the mirror's
// (e = 1, e_schlick = (1 - cos_v)^5 at the nodes); `alpha` = roughness^2 as in glTF. A delta
// lobe's exact albedo is the Schlick weight itself, which callers use instead.
GgxAlbedo ggx_albedo(float cos_v, float alpha);

// The same integral by quadrature at any point, as the table is built: for tests and for
// the table's own construction.
GgxAlbedo integrate_ggx_albedo(float cos_v, float alpha, int strata);

}  // namespace prism
