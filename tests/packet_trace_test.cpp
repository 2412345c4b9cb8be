// Camera rays traced as Embree packets (EmbreeScene::intersect_packet, what the tile loop
// uses) must find the hits that tracing them one at a time finds, with every filter in
// play: alpha BLEND (whose decision hashes the ray, found by its lane), alpha MASK,
// back-face culling of single-sided meshes (the second, culling trace), instancing and
// analytic spheres. Bit for bit, except where a ray meets a shared triangle edge within
// rounding: Embree's packet and single-ray triangle tests may then pick either triangle
// (same surface, t within a few ulps), which is why the tile loop fixes what shares a packet
// (integrators/tile_loop.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "renderer/geometry/embree_scene.h"
#include "renderer/geometry/ray.h"
#include "scene_io/gltf_loader.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

uint32_t bits(float f) {
  return std::bit_cast<uint32_t>(f);
}

bool same_bits(const SurfaceHit& a, const SurfaceHit& b) {
  bool same = bits(a.t) == bits(b.t) && a.material == b.material && a.back_face == b.back_face;
  for (int k = 0; k < 3; ++k) {
    same = same && bits(a.position[k]) == bits(b.position[k]) &&
           bits(a.geometric_normal[k]) == bits(b.geometric_normal[k]) &&
           bits(a.shading_normal[k]) == bits(b.shading_normal[k]);
  }
  return same;
}

struct Agreement {
  int rays = 0;
  int hits = 0;
  int differing = 0;            // hits not equal bit for bit
  double largest_t_change = 0;  // relative, over the differing hits
};

// Traces `rays` both ways. Every ray must hit or miss alike and find the same material;
// where the hits differ at all, the distance must agree to `t_tolerance` (relative).
Agreement compare_packet_and_single(const EmbreeScene& geometry, const std::vector<Ray>& rays,
                                    double t_tolerance) {
  Agreement a;
  constexpr int K = EmbreeScene::kPacketSize;
  for (size_t first = 0; first < rays.size(); first += K) {
    const int count = static_cast<int>(std::min<size_t>(K, rays.size() - first));
    SurfaceHit packet_hits[K];
    bool found[K];
    geometry.intersect_packet(&rays[first], count, packet_hits, found);
    for (int i = 0; i < count; ++i) {
      ++a.rays;
      SurfaceHit single;
      const bool single_found = geometry.intersect(rays[first + i], &single);
      EXPECT_EQ(found[i], single_found) << "ray " << first + i;
      if (!found[i] || !single_found) continue;
      ++a.hits;
      EXPECT_EQ(packet_hits[i].material, single.material) << "ray " << first + i;
      if (same_bits(packet_hits[i], single)) continue;
      ++a.differing;
      const double change = std::fabs(double(packet_hits[i].t) - single.t) / single.t;
      a.largest_t_change = std::max(a.largest_t_change, change);
      EXPECT_LE(change, t_tolerance) << "ray " << first + i;
    }
  }
  return a;
}

// Rays from a point above the scene, fanning down over [-extent, extent]^2 at y = 0, in
// the row order a tile loop would take them; every 7th ray is not a camera ray (culling
// off), and the count is not a multiple of the packet size, so the last packet is partial.
std::vector<Ray> fan_down(float height, float extent, int n) {
  std::vector<Ray> rays;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n + 3; ++i) {
      Ray r;
      r.origin = V3f(0.05f, height, -0.03f);
      const V3f target(extent * (2.0f * (i + 0.5f) / (n + 3) - 1.0f), 0.0f,
                       extent * (2.0f * (j + 0.5f) / n - 1.0f));
      r.direction = (target - r.origin).normalized();
      r.from_camera = (rays.size() % 7) != 0;
      rays.push_back(r);
    }
  }
  return rays;
}

TEST(PacketTrace, SameHitsAsSingleRaysThroughFiltersCullingAndInstances) {
  SceneDescription scene;
  MaterialDescription blend = testing::lambert_like(0.5f);
  blend.alpha_mode = AlphaMode::blend;
  blend.alpha = 0.5f;
  blend.double_sided = true;
  MaterialDescription mask = testing::lambert_like(0.5f);
  mask.alpha_mode = AlphaMode::mask;
  mask.alpha = 0.2f;  // below the cutoff: never there
  mask.double_sided = true;
  MaterialDescription single_sided = testing::lambert_like(0.5f);
  single_sided.double_sided = false;
  MaterialDescription floor = testing::lambert_like(0.5f);
  floor.double_sided = true;
  scene.materials = {blend, mask, single_sided, floor};

  // A BLEND sheet placed twice (an instanced mesh), a MASK sheet, a single-sided sheet
  // facing down (the camera sees its back: culled), a single-sided sheet facing up, and the
  // floor. Quads are 2 triangles each.
  scene.meshes.push_back(testing::quad_mesh(1.0f, 0.0f, 0));
  scene.meshes.push_back(testing::quad_mesh(0.6f, 1.5f, 1));
  Mesh down = testing::quad_mesh(0.8f, 1.2f, 2);
  for (Primitive& p : down.primitives) {
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3)
      std::swap(p.indices[t + 1], p.indices[t + 2]);
    for (V3f& n : p.normals) n = -n;
  }
  scene.meshes.push_back(down);
  scene.meshes.push_back(testing::quad_mesh(0.4f, 0.9f, 2));
  scene.meshes.push_back(testing::quad_mesh(3.0f, 0.0f, 3));
  M44d up1, up2;
  up1.setTranslation(V3d(0.1, 1.8, 0.0));
  up2.setTranslation(V3d(-0.2, 0.6, 0.1));
  scene.instances = {{0, up1, "blend a"}, {0, up2, "blend b"}, {1, M44d(), "mask"},
                     {2, M44d(), "down"}, {3, M44d(), "up"},   {4, M44d(), "floor"}};
  Sphere ball;
  ball.centre = V3d(1.2, 0.5, 1.2);
  ball.radius = 0.4;
  ball.material = 3;
  scene.spheres.push_back(ball);

  const EmbreeScene geometry(scene, GeometryOptions{});
  const std::vector<Ray> rays = fan_down(4.0f, 2.5f, 45);
  const Agreement a = compare_packet_and_single(geometry, rays, 0.0);
  EXPECT_GT(a.hits, a.rays * 9 / 10);  // the floor is under them all
  // None of these rays passes within rounding of a shared edge: bit for bit, filters and
  // the culling trace included.
  EXPECT_EQ(a.differing, 0);
}

TEST(PacketTrace, SameHitsOnTheShippedSphereScene) {
  const SceneDescription scene = load_gltf(std::string(PRISM_SOURCE_DIR) + "/scenes/spheres.gltf");
  for (SphereMode mode : {SphereMode::analytic, SphereMode::embree_points, SphereMode::mesh}) {
    SCOPED_TRACE(::testing::Message() << "sphere mode " << static_cast<int>(mode));
    GeometryOptions options;
    options.spheres.mode = mode;
    const EmbreeScene geometry(scene, options);
    const Imath::Box3f b = geometry.bounds();
    std::vector<Ray> rays;
    const V3f eye = b.center() + V3f(0.0f, 0.3f, 2.0f) * (b.max - b.min).length();
    for (int j = 0; j < 40; ++j) {
      for (int i = 0; i < 40; ++i) {
        const V3f target(b.min.x + (b.max.x - b.min.x) * (i + 0.5f) / 40.0f,
                         b.min.y + (b.max.y - b.min.y) * (j + 0.5f) / 40.0f, b.center().z);
        Ray r;
        r.origin = eye;
        r.direction = (target - eye).normalized();
        r.from_camera = true;
        rays.push_back(r);
      }
    }
    // At a shared edge of the tessellated spheres the packet traversal may take the other
    // triangle: the same surface, t within a few ulps.
    const Agreement a = compare_packet_and_single(geometry, rays, 4e-7);
    EXPECT_GT(a.hits, 400);
    EXPECT_LE(a.differing, a.hits / 50);
    std::printf(
        "sphere mode %d: %d rays, %d hits, %d not bit-identical, largest relative t change %.3g\n",
        static_cast<int>(mode), a.rays, a.hits, a.differing, a.largest_t_change);
  }
}

}  // namespace
}  // namespace prism
