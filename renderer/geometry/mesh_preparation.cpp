#include "renderer/geometry/mesh_preparation.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "renderer/math.h"
#include "renderer/parallel_index.h"

namespace prism {

namespace {

enum class TriangleCheck : uint8_t { kept, degenerate, nonfinite };

TriangleCheck check_triangle(const std::vector<V3f>& positions, const uint32_t* t) {
  const size_t vertices = positions.size();
  const uint32_t a = t[0], b = t[1], c = t[2];
  if (a >= vertices || b >= vertices || c >= vertices || a == b || b == c || a == c)
    return TriangleCheck::degenerate;
  const V3f& pa = positions[a];
  const V3f& pb = positions[b];
  const V3f& pc = positions[c];
  if (!is_finite(pa) || !is_finite(pb) || !is_finite(pc)) return TriangleCheck::nonfinite;
  const V3d e1 = V3d(pb) - V3d(pa), e2 = V3d(pc) - V3d(pa), e3 = V3d(pc) - V3d(pb);
  const double longest2 = std::max({e1.length2(), e2.length2(), e3.length2()});
  // Finite float vertices keep every double here finite.
  if (!(e1.cross(e2).length2() > 1e-24 * longest2 * longest2)) return TriangleCheck::degenerate;
  return TriangleCheck::kept;
}

// The rules are prepare_mesh's (mesh_preparation.h); runs in the space Embree will see the
// mesh in.
void clean_mesh(std::vector<V3f>* positions, std::vector<V3f>* normals,
                std::vector<uint32_t>* indices, MeshPreparationStatistics* counts) {
  const size_t vertices = positions->size();
  const size_t triangles = indices->size() / 3;
  std::vector<TriangleCheck> checks(triangles);
  for_each_index(triangles,
                 [&](size_t t) { checks[t] = check_triangle(*positions, &(*indices)[3 * t]); });
  counts->degenerate_triangles +=
      count_if_index(triangles, [&](size_t t) { return checks[t] == TriangleCheck::degenerate; });
  counts->nonfinite_triangles +=
      count_if_index(triangles, [&](size_t t) { return checks[t] == TriangleCheck::nonfinite; });
  // A trailing partial triangle is not a triangle.
  if (indices->size() % 3 != 0) ++counts->degenerate_triangles;
  if (counts->degenerate_triangles + counts->nonfinite_triangles > 0) {
    // Kept triangles move down in place: a second index array would be as large as the
    // mesh's biggest, and on a big mesh fresh memory costs more than the cleaning itself.
    size_t kept = 0;
    for (size_t t = 0; t < triangles; ++t) {
      if (checks[t] != TriangleCheck::kept) continue;
      for (size_t k = 0; k < 3; ++k) (*indices)[kept + k] = (*indices)[3 * t + k];
      kept += 3;
    }
    indices->resize(kept);
  }
  // Which vertices the kept triangles use is needed only to clear or repair what is broken,
  // which a clean mesh has nothing of.
  std::vector<char> used;
  auto find_used = [&] {
    if (!used.empty()) return;
    used.assign(vertices, 0);
    for (uint32_t v : *indices) used[v] = 1;
  };
  if (count_if_index(vertices, [&](size_t v) { return !is_finite((*positions)[v]); }) > 0) {
    find_used();
    for (size_t v = 0; v < vertices; ++v)
      if (!used[v] && !is_finite((*positions)[v])) (*positions)[v] = V3f(0.0f);
  }

  if (normals->empty()) return;
  if (normals->size() != vertices) {
    normals->clear();
    return;
  }
  const size_t zero_normals = count_if_index(vertices, [&](size_t v) {
    V3f& n = (*normals)[v];
    const double len2 = V3d(n).length2();
    if (is_finite(n) && len2 > 1e-30) {
      n = V3f(V3d(n) / std::sqrt(len2));
      return false;
    }
    n = V3f(0.0f);
    return true;
  });
  if (zero_normals == 0) return;
  find_used();
  std::vector<char> broken(vertices, 0);
  bool any_broken = false;
  for (size_t v = 0; v < vertices; ++v) {
    broken[v] = (*normals)[v] == V3f(0.0f) && used[v];
    any_broken = any_broken || broken[v];
  }
  if (!any_broken) return;
  std::vector<V3d> sum(vertices, V3d(0.0));
  for (size_t i = 0; i < indices->size(); i += 3) {
    const uint32_t t[3] = {(*indices)[i], (*indices)[i + 1], (*indices)[i + 2]};
    // Counter-clockwise: the cross product points out of the front face, its length is
    // twice the area, which weights the mean.
    const V3d face = (V3d((*positions)[t[1]]) - V3d((*positions)[t[0]]))
                         .cross(V3d((*positions)[t[2]]) - V3d((*positions)[t[0]]));
    for (uint32_t v : t)
      if (broken[v]) sum[v] += face;
  }
  for (size_t v = 0; v < vertices; ++v) {
    if (!broken[v]) continue;
    ++counts->normals_repaired;
    const double len = sum[v].length();
    // Faces that cancel (a vertex of two back-to-back faces) leave it zero, and the hit
    // falls back to the geometric normal there.
    if (len > 0.0) (*normals)[v] = V3f(sum[v] / len);
  }
}

// Normals move with the inverse transpose, positions in double before they are rounded.
void bake(const Primitive& p, const M44d& to_world, std::vector<V3f>* positions,
          std::vector<V3f>* normals, std::vector<uint32_t>* indices) {
  const M44d normal_matrix = to_world.inverse().transposed();
  positions->reserve(p.positions.size() + 1);  // room for the padding
  positions->resize(p.positions.size());       // V3f leaves its floats unset: no extra pass
  for_each_index(p.positions.size(), [&](size_t v) {
    V3d w;
    to_world.multVecMatrix(V3d(p.positions[v]), w);
    (*positions)[v] = V3f(w);
  });
  normals->resize(p.normals.size());
  for_each_index(p.normals.size(), [&](size_t v) {
    V3d w;
    normal_matrix.multDirMatrix(V3d(p.normals[v]), w);
    (*normals)[v] = V3f(w.normalized());
  });
  *indices = p.indices;
  if (to_world.determinant() < 0.0) {
    for_each_index(indices->size() / 3,
                   [&](size_t t) { std::swap((*indices)[3 * t + 1], (*indices)[3 * t + 2]); });
  }
}

// Tangents move with the surface (as directions, unlike normals). A mirroring transform
// flips the bitangent cross(normal, tangent) relative to the surface, so w flips with it.
std::vector<Imath::V4f> bake_tangents(const std::vector<Imath::V4f>& tangents,
                                      const M44d& to_world) {
  const float handedness = to_world.determinant() < 0.0 ? -1.0f : 1.0f;
  std::vector<Imath::V4f> out;
  out.reserve(tangents.size());
  for (const Imath::V4f& t : tangents) {
    V3d w;
    to_world.multDirMatrix(V3d(t.x, t.y, t.z), w);
    const V3f d(w.normalized());
    out.emplace_back(d.x, d.y, d.z, t.w * handedness);
  }
  return out;
}

void compute_face_normals(PreparedMesh* mesh) {
  mesh->face_normals.resize(mesh->indices.size() / 3);
  for_each_index(mesh->face_normals.size(), [mesh](size_t t) {
    const uint32_t* tri = &mesh->indices[3 * t];
    const V3d p0(mesh->positions[tri[0]]), p1(mesh->positions[tri[1]]), p2(mesh->positions[tri[2]]);
    mesh->face_normals[t] = V3f((p1 - p0).cross(p2 - p0).normalized());
  });
}

// Whether every kept triangle's vertex normals equal its face normal to rounding.
bool normals_are_face_normals(const PreparedMesh& mesh) {
  if (mesh.normals.empty()) return false;
  constexpr float kRounding = 0x1.0p-21f;
  const size_t triangles = mesh.triangle_count();
  return count_if_index(triangles, [&](size_t t) {
           const V3f& face = mesh.face_normals[t];
           for (size_t k = 0; k < 3; ++k) {
             const V3f d = mesh.normals[mesh.indices[3 * t + k]] - face;
             if (!(std::fabs(d.x) <= kRounding && std::fabs(d.y) <= kRounding &&
                   std::fabs(d.z) <= kRounding))
               return true;
           }
           return false;
         }) == 0;
}

// The attributes with one value per vertex (the loader checks that; a primitive made in code
// may not), once `positions` is final.
void take_attributes(const Primitive& p, const std::vector<Imath::V4f>& tangents,
                     PreparedMesh* mesh) {
  const size_t n = p.positions.size();
  VertexAttributes& attributes = mesh->attributes;
  if (p.uv0.size() == n) attributes.texcoords[0] = p.uv0;
  if (p.uv1.size() == n) attributes.texcoords[1] = p.uv1;
  if (p.colours.size() == n) attributes.colours = p.colours;
  if (tangents.size() == n) attributes.tangents = tangents;
  attributes.positions = mesh->positions.data();
  mesh->has_attributes = !attributes.empty();
}

// What both forms share once the vertices are in their final space. `to_world` is null for
// the primitive's own space.
PreparedMesh finish(const Primitive& p, const M44d* to_world, PreparedMesh mesh) {
  clean_mesh(&mesh.positions, &mesh.normals, &mesh.indices, &mesh.statistics);
  if (mesh.indices.empty()) return mesh;
  compute_face_normals(&mesh);
  mesh.shading_is_flat = normals_are_face_normals(mesh);
  mesh.positions.push_back(V3f(0.0f));  // Embree's read-ahead padding
  if (to_world)
    take_attributes(p, bake_tangents(p.tangents, *to_world), &mesh);
  else
    take_attributes(p, p.tangents, &mesh);
  mesh.material = p.material;
  return mesh;
}

}  // namespace

PreparedMesh prepare_mesh(const Primitive& primitive) {
  PreparedMesh mesh;
  mesh.positions.reserve(primitive.positions.size() + 1);  // room for the padding
  mesh.positions = primitive.positions;
  mesh.normals = primitive.normals;
  mesh.indices = primitive.indices;
  return finish(primitive, nullptr, std::move(mesh));
}

PreparedMesh prepare_mesh(const Primitive& primitive, const M44d& to_world) {
  PreparedMesh mesh;
  bake(primitive, to_world, &mesh.positions, &mesh.normals, &mesh.indices);
  return finish(primitive, &to_world, std::move(mesh));
}

}  // namespace prism
