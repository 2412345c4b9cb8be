#include "renderer/geometry/tangents.h"

#include <algorithm>
#include <cmath>

namespace prism {

using Imath::V2f;
using Imath::V3d;
using Imath::V3f;
using Imath::V4f;

namespace {

// Any unit vector orthogonal to n (Duff et al., "Building an orthonormal basis, revisited").
V3d orthogonal_to(const V3d& n) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  return V3d(1.0 + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x);
}

double angle_between(const V3d& a, const V3d& b) {
  const double la = a.length(), lb = b.length();
  if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
  return std::acos(std::clamp(a.dot(b) / (la * lb), -1.0, 1.0));
}

}  // namespace

std::vector<V4f> generate_tangents(const std::vector<V3f>& positions,
                                   const std::vector<V3f>& normals, const std::vector<V2f>& uvs,
                                   const std::vector<uint32_t>& indices) {
  const size_t count = positions.size();
  std::vector<V3d> tangent(count, V3d(0.0)), bitangent(count, V3d(0.0)),
      face_normal(count, V3d(0.0));
  if (uvs.size() == count) {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) {
      const uint32_t t[3] = {indices[i], indices[i + 1], indices[i + 2]};
      if (t[0] >= count || t[1] >= count || t[2] >= count) continue;
      const V3d p0(positions[t[0]]), p1(positions[t[1]]), p2(positions[t[2]]);
      const V3d e1 = p1 - p0, e2 = p2 - p0;
      const double du1 = uvs[t[1]].x - uvs[t[0]].x, dv1 = uvs[t[1]].y - uvs[t[0]].y;
      const double du2 = uvs[t[2]].x - uvs[t[0]].x, dv2 = uvs[t[2]].y - uvs[t[0]].y;
      const V3d n = e1.cross(e2);
      const double r = du1 * dv2 - du2 * dv1;
      // UVs collapsed to a line or a point say nothing about the tangent's direction.
      const bool usable = std::isfinite(r) && std::fabs(r) > 1e-20;
      const V3d dp_du = usable ? (e1 * dv2 - e2 * dv1) / r : V3d(0.0);
      const V3d dp_dv = usable ? (e2 * du1 - e1 * du2) / r : V3d(0.0);
      const V3d corners[3] = {p0, p1, p2};
      for (int k = 0; k < 3; ++k) {
        const double angle =
            angle_between(corners[(k + 1) % 3] - corners[k], corners[(k + 2) % 3] - corners[k]);
        // Unit directions, so a triangle's UV scale does not outweigh its neighbours'.
        if (usable && dp_du.length() > 0.0) tangent[t[k]] += angle * dp_du.normalized();
        if (usable && dp_dv.length() > 0.0) bitangent[t[k]] += angle * dp_dv.normalized();
        face_normal[t[k]] += angle * n.normalized();
      }
    }
  }
  std::vector<V4f> out(count);
  for (size_t v = 0; v < count; ++v) {
    V3d n = normals.size() == count ? V3d(normals[v]) : face_normal[v];
    n = n.length() > 0.0 ? n.normalized() : V3d(0.0, 0.0, 1.0);
    V3d t = tangent[v] - n * n.dot(tangent[v]);
    if (!(t.length() > 1e-12)) t = orthogonal_to(n);
    t.normalize();
    // cross(n, t) points along -dP/dv (up in the image) for an unmirrored layout.
    const float w = n.cross(t).dot(bitangent[v]) > 0.0 ? -1.0f : 1.0f;
    out[v] = V4f(static_cast<float>(t.x), static_cast<float>(t.y), static_cast<float>(t.z), w);
  }
  return out;
}

}  // namespace prism
