// Mesh preparation on its own (renderer/geometry/mesh_preparation.h): what is dropped, what
// is repaired, and where baking puts the vertices, without building a BVH.
#include <gtest/gtest.h>

#include <limits>
#include <utility>

#include <tbb/task_arena.h>

#include "renderer/geometry/mesh_preparation.h"

namespace prism {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A unit square in the XY plane, counter-clockwise seen from +Z, as two triangles.
Primitive square() {
  Primitive p;
  p.positions = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(1, 1, 0), V3f(0, 1, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = 7;
  return p;
}

TEST(MeshPreparation, DropsDegenerateAndNonFiniteTrianglesKeepingTheOrder) {
  Primitive p = square();
  p.positions.push_back(V3f(2, 0, 0));     // 4: collinear with 0 and 1
  p.positions.push_back(V3f(kNaN, 0, 0));  // 5: used only by a dropped triangle
  p.indices = {0, 0, 1,                    // repeated index
               0, 1, 2,                    // kept
               0, 1, 99,                   // out of range
               0, 1, 4,                    // zero area
               0, 5, 2,                    // non-finite vertex
               0, 2, 3,                    // kept
               1, 2};                      // a trailing partial triangle
  const PreparedMesh mesh = prepare_mesh(p);
  EXPECT_EQ(mesh.statistics.degenerate_triangles, 4u);
  EXPECT_EQ(mesh.statistics.nonfinite_triangles, 1u);
  EXPECT_EQ(mesh.statistics.normals_repaired, 0u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(mesh.triangle_count(), 2u);
  // Every vertex stays (indices keep their meaning), the unused NaN one zeroed, plus the
  // padding Embree reads past the last.
  EXPECT_EQ(mesh.vertex_count(), 6u);
  ASSERT_EQ(mesh.positions.size(), 7u);
  EXPECT_EQ(mesh.positions[4], V3f(2, 0, 0));
  EXPECT_EQ(mesh.positions[5], V3f(0, 0, 0));
  ASSERT_EQ(mesh.face_normals.size(), 2u);
  EXPECT_EQ(mesh.face_normals[0], V3f(0, 0, 1));
  EXPECT_EQ(mesh.face_normals[1], V3f(0, 0, 1));
  EXPECT_EQ(mesh.material, 7);
}

TEST(MeshPreparation, NothingLeftWhenEveryTriangleIsDropped) {
  Primitive p = square();
  p.indices = {0, 1, 1, 2, 2, 3};
  const PreparedMesh mesh = prepare_mesh(p);
  EXPECT_TRUE(mesh.indices.empty());
  EXPECT_EQ(mesh.statistics.degenerate_triangles, 2u);
}

TEST(MeshPreparation, RebuildsBrokenNormalsOfUsedVerticesFromTheFaces) {
  Primitive p = square();
  p.positions.push_back(V3f(5, 5, 5));  // 4: no triangle uses it
  p.normals = {V3f(0, 0, 0), V3f(kNaN, 0, 0), V3f(0, 0, 5), V3f(0, 3, 4), V3f(0, 0, 0)};
  const PreparedMesh mesh = prepare_mesh(p);
  EXPECT_EQ(mesh.statistics.normals_repaired, 2u);  // not the unused vertex's
  ASSERT_EQ(mesh.normals.size(), 5u);
  EXPECT_EQ(mesh.normals[0], V3f(0, 0, 1));  // the mean of the two faces around it
  EXPECT_EQ(mesh.normals[1], V3f(0, 0, 1));
  EXPECT_EQ(mesh.normals[2], V3f(0, 0, 1));        // normalised
  EXPECT_EQ(mesh.normals[3], V3f(0, 0.6f, 0.8f));  // normalised, not repaired
  EXPECT_EQ(mesh.normals[4], V3f(0, 0, 0));        // left zero
}

TEST(MeshPreparation, NormalsThatAreNotOnePerVertexAreDropped) {
  Primitive p = square();
  p.normals = {V3f(0, 0, 1), V3f(0, 0, 1)};
  const PreparedMesh mesh = prepare_mesh(p);
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_EQ(mesh.statistics.normals_repaired, 0u);
}

TEST(MeshPreparation, KeepsOnlyPerVertexAttributesPointingAtItsOwnPositions) {
  Primitive p = square();
  p.uv0 = {V2f(0, 0), V2f(1, 0), V2f(1, 1), V2f(0, 1)};
  p.uv1 = {V2f(0, 0)};  // not one per vertex
  PreparedMesh prepared = prepare_mesh(p);
  const PreparedMesh mesh = std::move(prepared);
  EXPECT_TRUE(mesh.has_attributes);
  EXPECT_EQ(mesh.attributes.texcoords[0], p.uv0);
  EXPECT_TRUE(mesh.attributes.texcoords[1].empty());
  EXPECT_EQ(mesh.attributes.positions, mesh.positions.data());

  const PreparedMesh bare = prepare_mesh(square());
  EXPECT_FALSE(bare.has_attributes);
}

TEST(MeshPreparation, BakesPositionsNormalsAndTangentsIntoTheWorld) {
  Primitive p = square();
  p.normals.assign(4, V3f(0, 0, 1));
  p.tangents.assign(4, Imath::V4f(1, 0, 0, 1));
  M44d to_world;
  to_world.setScale(V3d(2, 2, 4));
  to_world[3][0] = 10;
  to_world[3][2] = -1;
  const PreparedMesh mesh = prepare_mesh(p, to_world);
  ASSERT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.positions[0], V3f(10, 0, -1));
  EXPECT_EQ(mesh.positions[2], V3f(12, 2, -1));
  EXPECT_EQ(mesh.indices, p.indices);
  EXPECT_EQ(mesh.normals[1], V3f(0, 0, 1));
  EXPECT_EQ(mesh.attributes.tangents[3], Imath::V4f(1, 0, 0, 1));
  EXPECT_EQ(mesh.face_normals[0], V3f(0, 0, 1));
}

// A flat-shaded mesh that stores its normals (each triangle's three are its face normal)
// shades with the face normal; normals that bend, or point against the winding, are used.
TEST(MeshPreparation, NormalsThatAreTheFaceNormalsToRoundingShadeItFlat) {
  Primitive p = square();
  p.normals.assign(4, V3f(0, 0, 1));
  EXPECT_TRUE(prepare_mesh(p).shading_is_flat);
  p.normals[2] = V3f(0, 3e-7f, 1);  // tilted by less than 2^-21: float rounding
  EXPECT_TRUE(prepare_mesh(p).shading_is_flat);
  p.normals[2] = V3f(0, 1e-5f, 1);  // a real bend, however small
  EXPECT_FALSE(prepare_mesh(p).shading_is_flat);
  p.normals.assign(4, V3f(0, 0, -1));  // against the winding: the hit flips them
  EXPECT_FALSE(prepare_mesh(p).shading_is_flat);
  p.normals.clear();  // no normals: shaded by the geometric normal anyway
  EXPECT_FALSE(prepare_mesh(p).shading_is_flat);

  // Baked by a rotation about X (0.3 rad) and a non-uniform scale: positions and normals
  // move differently, in double, and still agree to rounding.
  p.normals.assign(4, V3f(0, 0, 1));
  M44d to_world;
  to_world.setAxisAngle(V3d(1, 0, 0), 0.3);
  M44d scale;
  scale.setScale(V3d(3, 1, 2));
  const PreparedMesh baked = prepare_mesh(p, scale * to_world);
  EXPECT_TRUE(baked.shading_is_flat);
  EXPECT_NE(baked.face_normals[0], V3f(0, 0, 1));  // really turned
}

// A curved mesh's normals are not its faces': it stays smooth.
TEST(MeshPreparation, ACurvedMeshIsNotFlat) {
  Primitive p = square();
  p.normals = {V3f(-0.1f, -0.1f, 1), V3f(0.1f, -0.1f, 1), V3f(0.1f, 0.1f, 1), V3f(-0.1f, 0.1f, 1)};
  const PreparedMesh mesh = prepare_mesh(p);
  EXPECT_FALSE(mesh.shading_is_flat);
  EXPECT_EQ(mesh.normals.size(), 4u);
}

// A mirroring transform keeps the authored front face in front: the winding flips with the
// vertices, and so does the bitangent's sign.
TEST(MeshPreparation, MirroringFlipsTheWindingAndTheBitangentSign) {
  Primitive p = square();
  p.normals.assign(4, V3f(0, 0, 1));
  p.tangents.assign(4, Imath::V4f(1, 0, 0, 1));
  M44d mirror;
  mirror.setScale(V3d(-1, 1, 1));
  const PreparedMesh mesh = prepare_mesh(p, mirror);
  EXPECT_EQ(mesh.positions[1], V3f(-1, 0, 0));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 2, 1, 0, 3, 2}));
  EXPECT_EQ(mesh.face_normals[0], V3f(0, 0, 1));
  EXPECT_EQ(mesh.face_normals[1], V3f(0, 0, 1));
  EXPECT_EQ(mesh.normals[0], V3f(0, 0, 1));
  EXPECT_EQ(mesh.attributes.tangents[0], Imath::V4f(-1, 0, 0, -1));
}

// A node that places a vertex at infinity loses the triangles that use it, as a bad vertex
// does.
TEST(MeshPreparation, CountsTrianglesABakeMakesNonFinite) {
  Primitive p = square();
  p.positions[3] = V3f(0, 3e38f, 0);
  M44d to_world;
  to_world.setScale(V3d(10, 10, 10));
  const PreparedMesh mesh = prepare_mesh(p, to_world);
  EXPECT_EQ(mesh.statistics.nonfinite_triangles, 1u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(mesh.positions[3], V3f(0, 0, 0));
}

// A grid far larger than one parallel chunk (renderer/parallel_index.h), with a dropped
// triangle and a broken normal in chunks other than the first: one thread and two prepare
// the same mesh bit for bit, and the counts are the serial rule's.
TEST(MeshPreparation, ABigMeshPreparesTheSameOnOneThreadAndOnTwo) {
  constexpr uint32_t kSide = 400;  // 400 x 400 vertices, 318 402 triangles
  Primitive p;
  for (uint32_t y = 0; y < kSide; ++y)
    for (uint32_t x = 0; x < kSide; ++x) {
      p.positions.push_back(V3f(float(x), float(y), 0.01f * float((x * 7 + y * 3) % 5)));
      p.normals.push_back(V3f(0.0f, 0.0f, 2.0f));
    }
  for (uint32_t y = 0; y + 1 < kSide; ++y)
    for (uint32_t x = 0; x + 1 < kSide; ++x) {
      const uint32_t v = y * kSide + x;
      p.indices.insert(p.indices.end(), {v, v + 1, v + kSide + 1, v, v + kSide + 1, v + kSide});
    }
  const size_t triangles = p.indices.size() / 3;
  p.indices[3 * 200000 + 1] = p.indices[3 * 200000];  // a repeated index, far past one chunk
  p.positions[150200].x = kNaN;                       // an inner vertex: its 6 triangles go
  p.normals[120000] = V3f(0.0f);                      // a broken normal, repaired
  PreparedMesh one, two;
  tbb::task_arena(1).execute([&] { one = prepare_mesh(p, M44d().translate(V3d(1, 2, 3))); });
  tbb::task_arena(2).execute([&] { two = prepare_mesh(p, M44d().translate(V3d(1, 2, 3))); });
  EXPECT_EQ(one.statistics.degenerate_triangles, 1u);
  EXPECT_EQ(one.statistics.nonfinite_triangles, 6u);
  EXPECT_EQ(one.statistics.normals_repaired, 1u);
  EXPECT_EQ(one.triangle_count(), triangles - 7);
  EXPECT_NEAR(one.normals[120000].length(), 1.0f, 1e-6f);
  EXPECT_GT(one.normals[120000].z, 0.99f);
  EXPECT_EQ(one.positions[150200], V3f(0.0f));  // used by dropped triangles only: zeroed
  EXPECT_EQ(one.indices, two.indices);
  EXPECT_EQ(one.positions, two.positions);
  EXPECT_EQ(one.normals, two.normals);
  EXPECT_EQ(one.face_normals, two.face_normals);
  EXPECT_EQ(one.statistics.degenerate_triangles, two.statistics.degenerate_triangles);
  EXPECT_EQ(one.statistics.nonfinite_triangles, two.statistics.nonfinite_triangles);
  EXPECT_EQ(one.statistics.normals_repaired, two.statistics.normals_repaired);
}

}  // namespace
}  // namespace prism
