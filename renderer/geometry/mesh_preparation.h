// A scene primitive made ready for Embree and for shading, apart from any BVH so that it can
// be checked on its own (tests/mesh_preparation_test.cpp). The renderer does not trust its
// input (docs/stress-shading.md): triangles that cannot be hit meaningfully are dropped and
// broken vertex normals rebuilt here, and the counts say how much was wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>

#include "renderer/geometry/surface_hit.h"
#include "renderer/scene_description.h"

namespace prism {

struct MeshPreparationStatistics {
  // An index out of range or repeated, zero area, or a trailing partial triangle.
  size_t degenerate_triangles = 0;
  size_t nonfinite_triangles = 0;  // a vertex not finite
  size_t normals_repaired = 0;     // zero or non-finite vertex normals rebuilt from the faces
};

// Vertex data as Embree sees it, kept for rebuilding hit points and interpolating normals,
// and the attributes the material reads (texture coordinates, colours, tangents).
//
// attributes.positions points into `positions`: a move keeps it valid, a copy would not, so
// there is none.
struct PreparedMesh {
  // One padding element past the last vertex: Embree reads 16 bytes per float3 vertex, 4
  // past the end of the last one.
  std::vector<Imath::V3f> positions;
  std::vector<Imath::V3f> normals;  // unit or zero; empty: shade with the geometric normal
  VertexAttributes attributes;
  bool has_attributes = false;  // any of them: hits point the material at `attributes`
  std::vector<uint32_t> indices;
  // Per triangle: the unit normal of its float vertices, formed in double. Embree's float Ng
  // of a long sliver triangle can point well off the plane, or be zero, and a ray offset
  // along a wrong normal re-hits the triangle it leaves (tests/stress/02_reintersect_test.cpp).
  // Formed once here rather than at every hit, where it cost more than the rest of the hit.
  // Out of the counter-clockwise front face, as Embree's Ng.
  std::vector<Imath::V3f> face_normals;
  // Every triangle's vertex normals are its face normal to rounding (within 2^-21 in each
  // component: the same direction rounded to float twice), as in a flat-shaded mesh that
  // stores its normals. Its hits take the face normal: interpolating would give it back to
  // rounding, and the terminator offset, which lifts a point onto the patch the normals
  // describe, is zero to rounding on a patch that is the triangle's own plane.
  bool shading_is_flat = false;
  int material = -1;
  MeshPreparationStatistics statistics;

  PreparedMesh() = default;
  PreparedMesh(PreparedMesh&&) = default;
  PreparedMesh& operator=(PreparedMesh&&) = default;
  PreparedMesh(const PreparedMesh&) = delete;
  PreparedMesh& operator=(const PreparedMesh&) = delete;

  size_t vertex_count() const { return positions.empty() ? 0 : positions.size() - 1; }
  size_t triangle_count() const { return indices.size() / 3; }
};

// The primitive in its own space (a prototype of instanced meshes, a tessellated sphere),
// cleaned:
//   - drops triangles with an index out of range or repeated, with a non-finite vertex, or
//     with zero area: twice the area |e1 x e2|, in double, at most 1e-12 times the longest
//     edge squared, i.e. a height below 1e-12 of the base, far under float's resolution of
//     1.2e-7, so only triangles that are collinear to rounding go. Embree would never report
//     a useful hit on them (Ng is zero or noise), and garbage indices could crash it;
//   - zeroes the positions of vertices no kept triangle uses, so no NaN reaches Embree;
//   - drops normals that are not one per vertex (the primitive is shaded flat), and rebuilds
//     each zero or non-finite normal of a used vertex as the area-weighted mean of the faces
//     around it (what a loader would generate), normalising the rest.
// The kept triangles keep their order, so a mesh that differs from a clean one only by the
// dropped triangles and unused vertices gives Embree the same primitives and the same BVH.
// Attributes that are not one per vertex are left out. When no triangle is left, only
// `indices` (empty) and `statistics` are meaningful.
PreparedMesh prepare_mesh(const Primitive& primitive);

// The same, baked into the space `to_world` maps to (the world, shifted by the world origin
// for baked meshes), in double before rounding to float. A transform that mirrors (negative
// determinant) would turn counter-clockwise triangles clockwise, so their winding is flipped
// to keep the authored front face in front, as glTF requires; tangents flip their
// bitangent sign with it. `to_world` must be finite and invertible.
PreparedMesh prepare_mesh(const Primitive& primitive, const Imath::M44d& to_world);

}  // namespace prism
