// Sphere-shaped meshes (scene_passes/sphere_detection.h): tessellated spheres are found with their
// centre and radius, shapes that are not spheres (or not whole ones) are not, and replacing
// one keeps its material.
//
// Tolerances: the meshes are built in double and stored as float positions, so every vertex
// is off its sphere by at most about 6e-8 of its coordinates' size (half a float ulp); the
// fitted centre and radius must agree with the construction to 1e-6 of the radius, well above
// that rounding and far below the default detection tolerance of 1e-3.
#include <cmath>

#include <gtest/gtest.h>

#include "scene_passes/sphere_detection.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFitTolerance = 1e-6;  // of the radius

// A latitude/longitude sphere as exporters write it: the seam column repeats the first
// column's positions (its own UVs), each pole is one vertex per column, and the pole rows
// are quads collapsed to triangles with a repeated position.
Primitive uv_sphere(const V3d& centre, double radius, int segments, int rings, int material) {
  Primitive p;
  p.material = material;
  for (int i = 0; i <= rings; ++i) {
    const double theta = kPi * i / rings;
    for (int j = 0; j <= segments; ++j) {
      const double phi = 2.0 * kPi * (j % segments) / segments;
      const V3d n(std::sin(theta) * std::cos(phi), std::cos(theta),
                  -std::sin(theta) * std::sin(phi));
      const V3d v = centre + radius * n;
      p.positions.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y),
                               static_cast<float>(v.z));
      p.normals.emplace_back(static_cast<float>(n.x), static_cast<float>(n.y),
                             static_cast<float>(n.z));
      p.uv0.emplace_back(static_cast<float>(j) / segments, static_cast<float>(i) / rings);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      // Counter-clockwise seen from outside.
      p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return p;
}

Primitive icosphere(int level, int material) {
  const UnitIcosphere unit = make_unit_icosphere(level);
  Primitive p;
  p.material = material;
  for (const V3d& v : unit.vertices)
    p.positions.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y),
                             static_cast<float>(v.z));
  p.indices = unit.indices;
  return p;
}

// The upper half (y >= 0) of a latitude/longitude sphere; closed with a flat cap made of the
// rim's own vertices (no centre vertex), every vertex lies on the sphere.
Primitive hemisphere(bool closed) {
  const int segments = 32, rings = 16;
  Primitive full = uv_sphere(V3d(0.0), 1.0, segments, rings, -1);
  Primitive p;
  p.positions = full.positions;
  const size_t upper_triangles = static_cast<size_t>(segments) * (rings / 2) * 2;
  p.indices.assign(full.indices.begin(),
                   full.indices.begin() + static_cast<std::ptrdiff_t>(3 * upper_triangles));
  if (closed) {
    const uint32_t rim = static_cast<uint32_t>((rings / 2) * (segments + 1));
    for (uint32_t j = 1; j + 1 < static_cast<uint32_t>(segments); ++j)
      p.indices.insert(p.indices.end(), {rim, rim + j + 1, rim + j});  // facing -y
  }
  return p;
}

// A cube of half size 1 with 24 vertices (split by face, as exported with flat normals);
// its 8 distinct corners lie exactly on the sphere of radius sqrt(3).
Primitive cube() {
  Primitive p;
  // Faces listed counter-clockwise seen from outside.
  const float c[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                         {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  for (const auto& f : faces) {
    const uint32_t base = static_cast<uint32_t>(p.positions.size());
    for (int k = 0; k < 4; ++k) p.positions.emplace_back(c[f[k]][0], c[f[k]][1], c[f[k]][2]);
    p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return p;
}

SceneDescription scene_with(const Primitive& p, const M44d& object_to_world = M44d()) {
  SceneDescription scene;
  Mesh mesh;
  mesh.name = "ball";
  mesh.primitives.push_back(p);
  scene.meshes.push_back(mesh);
  scene.instances.push_back({0, object_to_world, "ball-node"});
  return scene;
}

M44d trs(const V3d& t, double angle, const V3d& scale) {
  M44d m;
  m.scale(scale);
  M44d r;
  r.setAxisAngle(V3d(1.0, 2.0, 0.5).normalized(), angle);
  M44d tr;
  tr.setTranslation(t);
  return m * r * tr;  // row vectors: scale, then rotate, then translate
}

void expect_sphere(const SphereCandidate& c, const V3d& centre, double radius) {
  EXPECT_NEAR(c.centre.x, centre.x, kFitTolerance * radius);
  EXPECT_NEAR(c.centre.y, centre.y, kFitTolerance * radius);
  EXPECT_NEAR(c.centre.z, centre.z, kFitTolerance * radius);
  EXPECT_NEAR(c.radius, radius, kFitTolerance * radius);
  EXPECT_LT(c.deviation, kFitTolerance);
}

TEST(SphereDetection, FindsUvSphereWithSeamsAndCollapsedPoles) {
  const V3d centre(1.5, -2.0, 0.25);
  const SceneDescription scene = scene_with(uv_sphere(centre, 0.75, 32, 16, -1));
  const auto found = find_sphere_meshes(scene, SphereDetectionOptions{});
  ASSERT_EQ(found.size(), 1u);
  expect_sphere(found[0], centre, 0.75);
  EXPECT_EQ(found[0].instance, 0u);
  EXPECT_EQ(found[0].mesh, 0);
}

TEST(SphereDetection, FindsIcosphereInWorldSpaceThroughItsNodeTransform) {
  // Unit icosphere, uniform scale 2.5, rotated and moved: radius 2.5 around the translation.
  const V3d t(-3.0, 10.0, 4.0);
  const SceneDescription scene = scene_with(icosphere(2, -1), trs(t, 0.7, V3d(2.5)));
  const auto found = find_sphere_meshes(scene, SphereDetectionOptions{});
  ASSERT_EQ(found.size(), 1u);
  expect_sphere(found[0], t, 2.5);
}

TEST(SphereDetection, MirroredPlacementIsStillASphere) {
  const SceneDescription scene = scene_with(icosphere(2, -1), trs(V3d(1.0), 0.0, V3d(-1, 1, 1)));
  const auto found = find_sphere_meshes(scene, SphereDetectionOptions{});
  ASSERT_EQ(found.size(), 1u);
  expect_sphere(found[0], V3d(1.0), 1.0);
}

TEST(SphereDetection, CubeIsNotASphereEvenThoughItsCornersAre) {
  SphereDetectionOptions options;
  EXPECT_TRUE(find_sphere_meshes(scene_with(cube()), options).empty());
  // Without the vertex count, the facets (planes at r / sqrt(3) from the centre) reject it.
  options.min_vertices = 0;
  EXPECT_TRUE(find_sphere_meshes(scene_with(cube()), options).empty());
}

TEST(SphereDetection, CoarseIcosahedronIsAPolyhedron) {
  SphereDetectionOptions options;
  options.min_vertices = 0;  // 12 vertices; its facets are 0.795 r from the centre
  EXPECT_TRUE(find_sphere_meshes(scene_with(icosphere(0, -1)), options).empty());
  // One split (facets at least 0.9 r out) is fine enough.
  EXPECT_EQ(find_sphere_meshes(scene_with(icosphere(1, -1)), options).size(), 1u);
}

TEST(SphereDetection, HemispheresAreNotSpheres) {
  EXPECT_TRUE(find_sphere_meshes(scene_with(hemisphere(false)), {}).empty());  // open
  // Closed by a flat cap of rim vertices: every vertex on the sphere, but the cap's plane
  // passes through the centre.
  EXPECT_TRUE(find_sphere_meshes(scene_with(hemisphere(true)), {}).empty());
}

TEST(SphereDetection, SphereWithOneTriangleMissingIsOpen) {
  Primitive p = icosphere(3, -1);
  ASSERT_EQ(find_sphere_meshes(scene_with(p), {}).size(), 1u);
  p.indices.resize(p.indices.size() - 3);
  EXPECT_TRUE(find_sphere_meshes(scene_with(p), {}).empty());
}

TEST(SphereDetection, NonUniformScaleMakesAnEllipsoid) {
  const Primitive p = icosphere(3, -1);
  // 1 % longer in z: the best sphere misses some vertex by about half a percent.
  const M44d stretched = trs(V3d(0.0), 0.3, V3d(1.0, 1.0, 1.01));
  EXPECT_TRUE(find_sphere_meshes(scene_with(p, stretched), {}).empty());
  SphereDetectionOptions loose;
  loose.tolerance = 0.02;
  const auto found = find_sphere_meshes(scene_with(p, stretched), loose);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_GT(found[0].deviation, 1e-3);
  EXPECT_LT(found[0].deviation, 0.02);
}

TEST(SphereDetection, EachPlacementOfAnInstancedMeshIsCheckedOnItsOwn) {
  SceneDescription scene = scene_with(icosphere(2, -1), trs(V3d(5, 0, 0), 0.0, V3d(0.5)));
  scene.instances.push_back({0, trs(V3d(-5, 0, 0), 0.0, V3d(0.5, 0.6, 0.5)), "squashed"});
  scene.instances.push_back({0, trs(V3d(0, 7, 0), 1.0, V3d(3.0)), "big"});
  const auto found = find_sphere_meshes(scene, {});
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].instance, 0u);
  expect_sphere(found[0], V3d(5, 0, 0), 0.5);
  EXPECT_EQ(found[1].instance, 2u);
  expect_sphere(found[1], V3d(0, 7, 0), 3.0);
}

TEST(SphereDetection, ReplacementKeepsTheMaterialAndTheOtherPlacements) {
  SceneDescription scene;
  MaterialDescription red, blue;
  red.name = "red";
  blue.name = "blue";
  blue.base_colour = C3f(0.1f, 0.2f, 0.9f);
  scene.materials = {red, blue};
  Mesh ball{"ball", {uv_sphere(V3d(0.0), 1.0, 24, 12, 1)}};
  Mesh floor{"floor", {cube()}};
  floor.primitives[0].material = 0;
  scene.meshes = {floor, ball};
  scene.instances.push_back({0, M44d(), "floor-node"});
  scene.instances.push_back({1, trs(V3d(0, 2, 0), 0.0, V3d(0.5)), "ball-node"});
  scene.instances.push_back({1, trs(V3d(3, 2, 0), 0.0, V3d(0.5, 1.0, 0.5)), "egg-node"});

  const auto found = find_sphere_meshes(scene, {});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].material, 1);
  const auto replaced = replace_sphere_meshes(&scene, found);
  ASSERT_EQ(replaced.size(), 1u);
  ASSERT_EQ(scene.spheres.size(), 1u);
  EXPECT_EQ(scene.spheres[0].material, 1);
  EXPECT_EQ(scene.spheres[0].node_name, "ball-node");
  EXPECT_NEAR(scene.spheres[0].radius, 0.5, kFitTolerance);
  EXPECT_NEAR((scene.spheres[0].centre - V3d(0, 2, 0)).length(), 0.0, kFitTolerance);
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.instances[0].node_name, "floor-node");
  EXPECT_EQ(scene.instances[1].node_name, "egg-node");
  EXPECT_EQ(scene.meshes.size(), 2u);  // the mesh stays for the egg
}

TEST(SphereDetection, LooksThatNeedTheMeshAreNotReplaced) {
  SceneDescription scene = scene_with(uv_sphere(V3d(0.0), 1.0, 24, 12, 0));
  scene.materials.resize(2);
  scene.materials[0].base_colour_texture = 0;
  auto found = find_sphere_meshes(scene, {});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].blocker, SphereReplaceBlocker::textured_material);
  EXPECT_TRUE(replace_sphere_meshes(&scene, found).empty());
  EXPECT_EQ(scene.instances.size(), 1u);
  EXPECT_TRUE(scene.spheres.empty());

  // Two primitives (the two halves) with different materials.
  Primitive whole = icosphere(2, 1);
  Primitive half = whole;
  const size_t split = whole.indices.size() / 2;
  half.indices.assign(whole.indices.begin() + static_cast<std::ptrdiff_t>(split),
                      whole.indices.end());
  whole.indices.resize(split);
  SceneDescription two = scene_with(whole);
  two.materials.resize(2);
  half.material = 0;
  two.meshes[0].primitives.push_back(half);
  found = find_sphere_meshes(two, {});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].blocker, SphereReplaceBlocker::several_materials);
}

}  // namespace
}  // namespace prism
