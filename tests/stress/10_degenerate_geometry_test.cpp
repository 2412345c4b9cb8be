// Stress case 10: degenerate geometry. Meshes with collinear and zero-area triangles,
// repeated and out-of-range indices, NaN and infinite vertices, and missing, zero-length or
// NaN normals must render exactly as the cleaned mesh does, with no non-finite pixel: the
// renderer cleans what it is given (renderer/geometry/mesh_preparation.h, prepare_mesh) rather
// than trusting it. (A glTF *file* with non-finite positions is still refused by the loader,
// tests/gltf_loader_test.cpp; this is the renderer's own guard for scenes built in code.)
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "integrators/registry.h"
#include "renderer/geometry/sphere_mesh.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::lambert_like;
using testing::quad_mesh;
using testing::render_scene;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// An axis-aligned box from unshared vertices, four per face, with the face's normal at
// each: exactly what flat shading gives, so a box with these normals, with none, or with
// repaired ones must render the same.
Primitive box(const V3f& lo, const V3f& hi, int material) {
  Primitive p;
  const V3f c[8] = {V3f(lo.x, lo.y, lo.z), V3f(hi.x, lo.y, lo.z), V3f(hi.x, hi.y, lo.z),
                    V3f(lo.x, hi.y, lo.z), V3f(lo.x, lo.y, hi.z), V3f(hi.x, lo.y, hi.z),
                    V3f(hi.x, hi.y, hi.z), V3f(lo.x, hi.y, hi.z)};
  // Counter-clockwise seen from outside.
  const int faces[6][4] = {{4, 5, 6, 7}, {1, 0, 3, 2}, {5, 1, 2, 6},
                           {0, 4, 7, 3}, {7, 6, 2, 3}, {0, 1, 5, 4}};
  const V3f normals[6] = {V3f(0, 0, 1),  V3f(0, 0, -1), V3f(1, 0, 0),
                          V3f(-1, 0, 0), V3f(0, 1, 0),  V3f(0, -1, 0)};
  for (int f = 0; f < 6; ++f) {
    const auto base = static_cast<uint32_t>(p.positions.size());
    for (int k = 0; k < 4; ++k) {
      p.positions.push_back(c[faces[f][k]]);
      p.normals.push_back(normals[f]);
    }
    p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  p.material = material;
  return p;
}

Primitive ball(int material) {
  Primitive p = tessellate_sphere(Sphere{V3d(0.0), 1.0, material, ""}, 2);
  return p;
}

// Inserts, after every fifth triangle, one of: repeated indices (three kinds), a triangle on
// three collinear new vertices, one on two coincident new vertices, and an index past the
// end. Returns how many were added.
size_t add_degenerate_triangles(Primitive* p) {
  std::vector<uint32_t> dirty;
  size_t added = 0;
  const auto n = static_cast<uint32_t>(p->positions.size());
  for (size_t t = 0; t * 3 < p->indices.size(); ++t) {
    const uint32_t a = p->indices[3 * t], b = p->indices[3 * t + 1], c = p->indices[3 * t + 2];
    dirty.insert(dirty.end(), {a, b, c});
    if (t % 5 != 4) continue;
    const auto first_new = static_cast<uint32_t>(p->positions.size());
    const V3f pa = p->positions[a];
    switch ((t / 5) % 6) {
      case 0:
        dirty.insert(dirty.end(), {a, a, b});
        break;
      case 1:
        dirty.insert(dirty.end(), {a, b, b});
        break;
      case 2:
        dirty.insert(dirty.end(), {c, a, c});
        break;
      case 3:  // collinear: three points on a line parallel to x, exactly (only x differs)
        p->positions.push_back(pa);
        p->positions.push_back(pa + V3f(0.25f, 0.0f, 0.0f));
        p->positions.push_back(pa + V3f(0.5f, 0.0f, 0.0f));
        dirty.insert(dirty.end(), {first_new, first_new + 1, first_new + 2});
        break;
      case 4:  // zero area from a duplicated vertex under another index
        p->positions.push_back(pa);
        dirty.insert(dirty.end(), {a, first_new, b});
        break;
      case 5:
        dirty.insert(dirty.end(), {a, b, n + 1000});
        break;
    }
    ++added;
  }
  // Normals for the new vertices: zero, as an exporter leaves unused ones.
  p->normals.resize(p->positions.size(), V3f(0.0f));
  p->indices = dirty;
  return added;
}

// Appends vertices with NaN and infinite coordinates (and NaN normals) and triangles that
// use them, mixed with valid vertices. Returns how many triangles were added.
size_t add_nonfinite_triangles(Primitive* p) {
  const auto base = static_cast<uint32_t>(p->positions.size());
  p->positions.insert(p->positions.end(), {V3f(kNaN, 0, 0), V3f(0, kInf, 0), V3f(0, 0, -kInf),
                                           V3f(kNaN, kNaN, kNaN), V3f(1e30f, kInf, -kInf)});
  p->normals.resize(p->positions.size(), V3f(kNaN, kNaN, kNaN));
  const uint32_t triangles[][3] = {{0, 1, base},
                                   {base + 1, 2, 3},
                                   {4, base + 2, 5},
                                   {base, base + 1, base + 2},
                                   {base + 3, base + 3, 0},
                                   {6, 7, base + 4}};
  // Interleaved at the front, so the kept triangles keep their order only if these go.
  std::vector<uint32_t> dirty;
  for (const auto& t : triangles) dirty.insert(dirty.end(), {t[0], t[1], t[2]});
  dirty.insert(dirty.end(), p->indices.begin(), p->indices.end());
  p->indices = dirty;
  return std::size(triangles) - 1;  // {base + 3, base + 3, 0} is counted as degenerate first
}

M44d at(const V3d& t, double scale) {
  M44d m;
  m.setScale(scale);
  m[3][0] = t.x;
  m[3][1] = t.y;
  m[3][2] = t.z;
  return m;
}

// A floor, the box, one ball baked (placed once) and one ball instanced (placed twice), a
// point light and a perspective camera; `box_prim` and `ball_prim` are the variants.
SceneDescription scene_with(const Primitive& box_prim, const Primitive& ball_prim) {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.6f));
  MaterialDescription glossy = lambert_like(0.8f);
  glossy.roughness = 0.5f;
  scene.materials.push_back(glossy);
  scene.meshes.push_back(quad_mesh(5.0f, 0.0f, 0));
  Mesh box_mesh, ball_mesh;
  box_mesh.primitives.push_back(box_prim);
  ball_mesh.primitives.push_back(ball_prim);
  scene.meshes.push_back(box_mesh);
  scene.meshes.push_back(ball_mesh);
  scene.meshes.push_back(ball_mesh);
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  scene.instances.push_back(MeshInstance{1, M44d(), "box"});
  scene.instances.push_back(MeshInstance{2, at(V3d(-1.8, 0.6, 0.3), 0.6), "baked ball"});
  scene.instances.push_back(MeshInstance{3, at(V3d(1.7, 0.5, 0.8), 0.5), "instanced ball 1"});
  scene.instances.push_back(MeshInstance{3, at(V3d(0.2, 0.4, 1.9), 0.4), "instanced ball 2"});
  Light bulb;
  bulb.intensity = 15.0f;
  bulb.position = V3d(1.5, 3.5, 2.5);
  scene.lights.push_back(bulb);
  CameraDescription camera;
  camera.yfov = 0.9;
  camera.camera_to_world.setEulerAngles(V3d(-0.5, 0.0, 0.0));
  camera.camera_to_world[3][1] = 3.5;
  camera.camera_to_world[3][2] = 6.0;
  scene.cameras.push_back(camera);
  return scene;
}

Image render_image(const SceneDescription& scene) {
  testing::TestSettings settings;
  settings.width = 160;
  settings.height = 120;
  const auto r = render_scene(scene, "whitted", settings);
  for (float v : r.image.rgba) EXPECT_TRUE(std::isfinite(v));
  return r.image;
}

bool identical(const Image& a, const Image& b) {
  return a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

const Primitive kCleanBox = box(V3f(-0.5f, 0.0f, -0.8f), V3f(0.6f, 1.2f, 0.1f), 1);

TEST(StressDegenerateGeometry, DegenerateTrianglesAreDroppedAndTheImageIsUnchanged) {
  const SceneDescription clean = scene_with(kCleanBox, ball(1));
  Primitive dirty_ball = ball(1);
  const size_t added = add_degenerate_triangles(&dirty_ball);
  ASSERT_EQ(added, 64u);  // one after every fifth of the 320 triangles
  const SceneDescription dirty = scene_with(kCleanBox, dirty_ball);

  const EmbreeScene clean_geometry(clean, {});
  const EmbreeScene dirty_geometry(dirty, {});
  // The ball is placed three times (once baked, twice instanced); every placement counts.
  EXPECT_EQ(dirty_geometry.statistics().degenerate_triangles, 3 * added);
  EXPECT_EQ(dirty_geometry.statistics().nonfinite_triangles, 0u);
  EXPECT_EQ(dirty_geometry.statistics().triangles, clean_geometry.statistics().triangles);
  EXPECT_EQ(clean_geometry.statistics().degenerate_triangles, 0u);
  EXPECT_EQ(clean_geometry.statistics().normals_repaired, 0u);
  // Zero normals on the unused collinear vertices are not repaired: no kept triangle uses them.
  EXPECT_EQ(dirty_geometry.statistics().normals_repaired, 0u);

  // The kept triangles are the clean mesh's, in its order, so Embree builds the same BVH and
  // every hit is the same: bit-identical.
  EXPECT_TRUE(identical(render_image(clean), render_image(dirty)));
}

TEST(StressDegenerateGeometry, NonFiniteVerticesBuiltInCodeAreDroppedAndRenderCleanly) {
  const SceneDescription clean = scene_with(kCleanBox, ball(1));
  Primitive dirty_ball = ball(1);
  const size_t added = add_nonfinite_triangles(&dirty_ball);
  Primitive dirty_box = kCleanBox;
  const size_t added_box = add_nonfinite_triangles(&dirty_box);
  const SceneDescription dirty = scene_with(dirty_box, dirty_ball);
  const EmbreeScene geometry(dirty, {});
  EXPECT_EQ(geometry.statistics().nonfinite_triangles, 3 * added + added_box);
  EXPECT_EQ(geometry.statistics().degenerate_triangles, 3u + 1u);  // one {i, i, j} in each
  EXPECT_TRUE(identical(render_image(clean), render_image(dirty)));

  // A node transform that is not finite places nothing.
  SceneDescription broken_node = clean;
  broken_node.instances.push_back(broken_node.instances[1]);
  broken_node.instances.back().object_to_world[3][0] = kNaN;
  broken_node.instances.push_back(broken_node.instances[1]);
  broken_node.instances.back().object_to_world[0][0] = kInf;
  const EmbreeScene broken_geometry(broken_node, {});
  EXPECT_EQ(broken_geometry.statistics().nonfinite_triangles, 2 * kCleanBox.indices.size() / 3);
  EXPECT_TRUE(identical(render_image(clean), render_image(broken_node)));
}

TEST(StressDegenerateGeometry, MissingZeroAndNaNNormalsShadeAsTheCleanMesh) {
  const SceneDescription clean = scene_with(kCleanBox, ball(1));
  const Image reference = render_image(clean);

  // No normals: flat shading, which for the box is its face normals.
  Primitive no_normals = kCleanBox;
  no_normals.normals.clear();
  EXPECT_TRUE(identical(reference, render_image(scene_with(no_normals, ball(1)))));

  // Normals that do not match the vertices are dropped: flat again.
  Primitive short_normals = kCleanBox;
  short_normals.normals.resize(5);
  EXPECT_TRUE(identical(reference, render_image(scene_with(short_normals, ball(1)))));

  // Zero and NaN normals are rebuilt from the faces around the vertex: on a box face that
  // is the face's normal exactly.
  Primitive broken = kCleanBox;
  size_t broken_count = 0;
  for (size_t v = 0; v < broken.normals.size(); v += 3) {
    broken.normals[v] = v % 2 == 0 ? V3f(0.0f) : V3f(kNaN, 0.0f, kInf);
    ++broken_count;
  }
  const SceneDescription repaired = scene_with(broken, ball(1));
  const EmbreeScene geometry(repaired, {});
  EXPECT_EQ(geometry.statistics().normals_repaired, broken_count);
  EXPECT_TRUE(identical(reference, render_image(repaired)));
}

}  // namespace
}  // namespace prism
