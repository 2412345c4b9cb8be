// The flock (simulation/): the lecture's avoidance force and its five cases, the neighbour
// grid against brute force, no penetration in a dense field over 10 000 steps, the same
// positions for 1 and 2 threads, bad configs, and frames the loader reads back as written.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "renderer/geometry/sphere_mesh.h"
#include "scene_io/gltf_loader.h"
#include "simulation/clip_export.h"
#include "simulation/flock.h"
#include "simulation/flock_config.h"
#include "simulation/neighbour_grid.h"
#include "simulation/obstacle_avoidance.h"
#include "tests/gltf_test_builder.h"

namespace prism {
namespace {

using Imath::V3f;
namespace fs = std::filesystem;

const ProbeShape kProbe{0.5f, 6.0f};
constexpr float kMaxForce = 10.0f;
constexpr float kSpeed = 2.0f;
const V3f kOrigin(0.0f);
const V3f kForward(0.0f, 0.0f, 1.0f);

// A unit sphere 4 ahead, offset sideways by `offset` (along +x).
SphereObstacle sphere_ahead(float offset, float ahead = 4.0f) {
  return {V3f(offset, 0.0f, ahead), 1.0f};
}

ProbeResult probe(const SphereObstacle& s, const V3f& o = kOrigin, const V3f& d = kForward) {
  return probe_sphere(o, d, kSpeed, s, kProbe, kMaxForce);
}

TEST(BoidsAvoidance, TheLecturesFiveCases) {
  // Going to hit: the line of travel passes 0.4 from the centre of a unit sphere.
  EXPECT_EQ(probe(sphere_ahead(0.4f)).kind, ProbeCase::hit);
  // Going to skim: the line misses the sphere (1.2 > 1) but the 0.5 cylinder clips it.
  EXPECT_EQ(probe(sphere_ahead(1.2f)).kind, ProbeCase::skim);
  // Inside: the boid is within the grown sphere, here inside the sphere itself.
  EXPECT_EQ(probe(sphere_ahead(0.3f, 0.2f)).kind, ProbeCase::inside);
  // Going to miss: 1.6 > 1 + 0.5 from the centre.
  EXPECT_EQ(probe(sphere_ahead(1.6f)).kind, ProbeCase::miss);
  // Beyond the look-ahead counts as a miss too.
  EXPECT_EQ(probe(sphere_ahead(0.0f, 8.0f)).kind, ProbeCase::miss);
  // Behind: dead on the line, but behind the boid.
  EXPECT_EQ(probe(sphere_ahead(0.0f, -3.0f)).kind, ProbeCase::behind);
  // Only hit, skim and inside steer.
  EXPECT_EQ(probe(sphere_ahead(1.6f)).force, V3f(0.0f));
  EXPECT_EQ(probe(sphere_ahead(0.0f, -3.0f)).force, V3f(0.0f));
  EXPECT_GT(probe(sphere_ahead(1.2f)).force.length(), 0.0f);
}

TEST(BoidsAvoidance, ForceIsPerpendicularAwayFromTheCentreAndRisesAsTheMissShrinks) {
  const V3f d = V3f(0.3f, 0.2f, 1.0f).normalized();
  const V3f o(1.0f, -2.0f, 0.5f);
  float previous = 0.0f;
  // Spheres whose centres lie further and further from the line, all 3.5 ahead and off to
  // one side: the predicted miss distance grows from 0.05 to 1.45 (the grown radius is 1.5).
  const V3f side = d.cross(V3f(0.0f, 1.0f, 0.0f)).normalized();
  for (int k = 29; k >= 1; --k) {
    const float miss = 0.05f * static_cast<float>(k);
    const SphereObstacle s{o + 3.5f * d + miss * side, 1.0f};
    const ProbeResult r = probe_sphere(o, d, kSpeed, s, kProbe, kMaxForce);
    ASSERT_TRUE(r.kind == ProbeCase::hit || r.kind == ProbeCase::skim) << miss;
    EXPECT_NEAR(r.miss_distance, miss, 1e-5f);
    const float length = r.force.length();
    // Perpendicular to D, to float rounding of the force.
    EXPECT_LT(std::fabs(r.force.dot(d)), 1e-5f * length) << miss;
    // From C towards E (E on the line, C off it by `miss` along `side`).
    const V3f e = o + (s.centre - o).dot(d) * d;
    EXPECT_GT(r.force.dot(e - s.centre), 0.999f * length * (e - s.centre).length()) << miss;
    // Iterating from the largest miss to the smallest, the force must rise every time.
    EXPECT_GT(length, previous) << miss;
    previous = length;
  }
}

TEST(BoidsAvoidance, HeadingAtTheCentreTurnsAWellDefinedStableWay) {
  const SphereObstacle s = sphere_ahead(0.0f);
  const ProbeResult r = probe(s);
  ASSERT_EQ(r.kind, ProbeCase::hit);
  EXPECT_EQ(r.miss_distance, 0.0f);
  const float length = r.force.length();
  ASSERT_TRUE(std::isfinite(length));
  ASSERT_GT(length, 0.0f);
  EXPECT_LT(std::fabs(r.force.dot(kForward)), 1e-6f * length);
  // The same input gives the same turn, and a heading a thousandth of a radian off (still
  // dead at the centre of a sphere moved onto its line) turns nearly the same way, so a boid
  // does not flick between sides from one step to the next.
  EXPECT_EQ(probe(s).force, r.force);
  const V3f tilted = V3f(std::sin(1e-3f), 0.0f, std::cos(1e-3f));
  const ProbeResult t = probe({4.0f * tilted, 1.0f}, kOrigin, tilted);
  ASSERT_EQ(t.kind, ProbeCase::hit);
  EXPECT_GT(t.force.normalized().dot(r.force.normalized()), 0.999f);
  // Straight down (where the sideways turn is undefined) still gets a unit perpendicular.
  const V3f down(0.0f, -1.0f, 0.0f);
  const V3f turn = fallback_turn(down);
  EXPECT_NEAR(turn.length(), 1.0f, 1e-6f);
  EXPECT_EQ(turn.dot(down), 0.0f);
}

TEST(BoidsAvoidance, InsidePushesOutAlongTheRadius) {
  const SphereObstacle s{V3f(0.0f, 0.0f, 1.0f), 1.0f};
  // 0.6 from the centre: 0.9 below the grown surface (radius 1.5), 1.8 probe radii.
  const V3f o(0.0f, 0.6f, 1.0f);
  const ProbeResult r = probe(s, o);
  ASSERT_EQ(r.kind, ProbeCase::inside);
  EXPECT_NEAR(r.force.y, 1.8f * kMaxForce, 1e-4f);
  EXPECT_NEAR(r.force.x, 0.0f, 1e-6f);
  EXPECT_NEAR(r.force.z, 0.0f, 1e-6f);
  // Deeper pushes harder; at the grown surface it fades to nothing.
  EXPECT_GT(probe(s, V3f(0.0f, 0.3f, 1.0f)).force.y, r.force.y);
  EXPECT_LT(probe(s, V3f(0.0f, 1.49f, 1.0f)).force.length(), 0.03f * kMaxForce);
}

TEST(BoidsGrid, FindsEveryPointWithinTheRadius) {
  AxisBox box{V3f(-5.0f), V3f(5.0f)};
  std::vector<V3f> points;
  uint32_t state = 12345;
  const auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) * 0x1p-24f * 10.0f - 5.0f;
  };
  for (int i = 0; i < 2000; ++i) points.push_back(V3f(next(), next(), next()));
  const float radius = 1.3f;
  NeighbourGrid grid(box, radius);
  grid.build(points);
  EXPECT_GT(grid.cells(0), 1);
  size_t total = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    std::set<uint32_t> found;
    grid.for_each_candidate(points[i], [&](uint32_t j) { found.insert(j); });
    for (size_t j = 0; j < points.size(); ++j)
      if ((points[j] - points[i]).length2() <= radius * radius) {
        EXPECT_TRUE(found.count(static_cast<uint32_t>(j))) << i << " " << j;
        ++total;
      }
  }
  EXPECT_GT(total, points.size());  // the radius does hold neighbours
}

// A small flock in a box crowded with spheres, nothing pulling it any one way.
FlockParameters dense_field() {
  FlockParameters p;
  p.seed = 3;
  p.boids = 40;
  p.boid_radius = 0.1f;
  p.bounds = {V3f(-6.0f, -3.0f, -6.0f), V3f(6.0f, 3.0f, 6.0f)};
  p.spawn = p.bounds;
  p.spawn_velocity = V3f(2.0f, 0.0f, 1.0f);
  p.max_speed = 3.0f;
  p.cruise_speed = 2.5f;
  p.max_force = 15.0f;
  p.probe_radius = 0.35f;
  p.look_ahead = 2.5f;
  // A 4 x 2 x 4 lattice of spheres 0.9 to 1.3 in radius, 3 apart: gaps of 0.4 to 1.2 between
  // neighbours, so the flock is always threading between them.
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 4; ++z) {
        const float r = 0.9f + 0.1f * static_cast<float>((x + 2 * y + 3 * z) % 5);
        p.obstacles.push_back({V3f(-4.5f + 3.0f * x, -1.5f + 3.0f * y, -4.5f + 3.0f * z), r});
      }
  return p;
}

TEST(BoidsFlock, DenseFieldNoPenetrationAndKeepsMovingOver10000Steps) {
  const FlockParameters p = dense_field();
  Flock flock(p, 1);
  constexpr int kSteps = 10000;
  // A stuck boid is one slower than a tenth of the cruise speed for a whole second.
  const int stuck_steps = static_cast<int>(1.0f / p.time_step);
  std::vector<int> slow_for(static_cast<size_t>(p.boids), 0);
  float closest = INFINITY;
  float slowest_mean = INFINITY;
  int longest_slow = 0;
  for (int step = 0; step < kSteps; ++step) {
    flock.step();
    float speed_sum = 0.0f;
    for (size_t i = 0; i < flock.positions().size(); ++i) {
      for (const SphereObstacle& s : p.obstacles)
        closest = std::min(closest, (flock.positions()[i] - s.centre).length() - s.radius);
      const float speed = flock.velocities()[i].length();
      speed_sum += speed;
      slow_for[i] = speed < 0.1f * p.cruise_speed ? slow_for[i] + 1 : 0;
      longest_slow = std::max(longest_slow, slow_for[i]);
    }
    slowest_mean = std::min(slowest_mean, speed_sum / static_cast<float>(p.boids));
  }
  // No centre within its own radius of a surface, at any of the 10 000 steps.
  EXPECT_GE(closest, p.boid_radius);
  // Moving: the mean speed never below half the cruise speed, and no boid stuck.
  EXPECT_GT(slowest_mean, 0.5f * p.cruise_speed);
  EXPECT_LT(longest_slow, stuck_steps);
  // And inside the box.
  for (const V3f& x : flock.positions())
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(x[a], p.bounds.min[a]);
      EXPECT_LE(x[a], p.bounds.max[a]);
    }
  std::printf("closest approach to a surface %.4f (boid radius %.2f), slowest mean speed %.3f\n",
              closest, p.boid_radius, slowest_mean);
}

TEST(BoidsFlock, SamePositionsBitForBitForOneAndTwoThreads) {
  FlockParameters p = dense_field();
  p.boids = 2000;  // several of the step's 256-boid chunks, so two threads do split the work
  p.bounds = {V3f(-12.0f, -3.0f, -12.0f), V3f(12.0f, 3.0f, 12.0f)};
  p.spawn = p.bounds;
  Flock one(p, 1), two(p, 2);
  one.run(60);
  two.run(60);
  ASSERT_EQ(one.positions().size(), two.positions().size());
  EXPECT_EQ(0, std::memcmp(one.positions().data(), two.positions().data(),
                           one.positions().size() * sizeof(V3f)));
  EXPECT_EQ(0, std::memcmp(one.velocities().data(), two.velocities().data(),
                           one.velocities().size() * sizeof(V3f)));
  // The flock did move: the comparison is not of two copies of the start.
  Flock start(p, 1);
  EXPECT_NE(0, std::memcmp(one.positions().data(), start.positions().data(),
                           one.positions().size() * sizeof(V3f)));
}

class BoidsConfig : public ::testing::Test {
 protected:
  fs::path write(const std::string& text) {
    const fs::path path =
        fs::temp_directory_path() / ("prism_boids_test_" + std::to_string(::getpid()) + ".json");
    std::ofstream(path) << text;
    paths_.push_back(path);
    return path;
  }
  // The error for a config of version 1 holding `body`, or "" when it is accepted.
  std::string error(const std::string& body) {
    try {
      read_flock_config(
          write("{\"version\": 1" + std::string(body.empty() ? "" : ", ") + body + "}"));
    } catch (const FlockConfigError& e) {
      return e.what();
    }
    return "";
  }
  void TearDown() override {
    for (const fs::path& p : paths_) fs::remove(p);
  }
  std::vector<fs::path> paths_;
};

TEST_F(BoidsConfig, BadValuesNameTheirField) {
  EXPECT_EQ(error(""), "");
  EXPECT_NE(error(R"("boids": {"radius": -0.1})").find(": boids.radius: must be positive"),
            std::string::npos);
  EXPECT_NE(error(R"("boids": {"count": 0})").find(": boids.count: must be at least 1"),
            std::string::npos);
  EXPECT_NE(error(R"("simulation": {"frames": 0})").find(": simulation.frames: must be at least 1"),
            std::string::npos);
  EXPECT_NE(error(R"("obstacles": [{"centre": [0, 0, 0], "radius": -1}])")
                .find(": obstacles[0].radius: must be positive"),
            std::string::npos);
  // JSON has no NaN: a NaN literal is a syntax error, and a number too large for a double
  // overflows; both still name the field they are in.
  const std::string nan = error(R"("boids": {"count": 3, "radius": NaN})");
  EXPECT_NE(nan.find(": boids.radius: not valid JSON"), std::string::npos) << nan;
  const std::string inside_list = error(R"("obstacles": [{"centre": [0, 0, 0], "radius": 1},
                                                         {"centre": [0, NaN, 0], "radius": 1}])");
  EXPECT_NE(inside_list.find(": obstacles[1].centre[1]: not valid JSON"), std::string::npos)
      << inside_list;
  EXPECT_NE(error(R"("avoidance": {"look_ahead": 1e999})")
                .find(": avoidance.look_ahead: is not a finite number"),
            std::string::npos);
  EXPECT_NE(error(R"("render": {"integrator": "direct"})")
                .find(": render.integrator: 'direct' is not one of phong, shadow, whitted"),
            std::string::npos);
  EXPECT_NE(error(R"("boids": {"raduis": 1})").find(": boids.raduis: no such key"),
            std::string::npos);
  EXPECT_NE(error(R"("boids": {"count": 2.5})").find(": boids.count: is not an integer"),
            std::string::npos);
  for (const std::string& e :
       {error(R"("boids": {"radius": -0.1})"), error(R"("boids": {"radius": NaN})")})
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  try {
    read_flock_config("/nonexistent/flock.json");
    ADD_FAILURE() << "a missing file was read";
  } catch (const FlockConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/flock.json: cannot be read");
  }
}

TEST_F(BoidsConfig, ObstaclesFromAGltfFilesSpheres) {
  // scenes/spheres.gltf has four PRISM_sphere nodes: radius 1 scaled by 1, 0.8, 0.55, 0.35.
  const std::string scene = PRISM_SOURCE_DIR "/scenes/spheres.gltf";
  const FlockConfig c = read_flock_config(write(
      R"({"version": 1, "obstacles": [{"centre": [9, 9, 9], "radius": 0.5}],
          "obstacle_scene": {"file": ")" +
      scene + R"("}})"));
  ASSERT_EQ(c.flock.obstacles.size(), 5u);
  EXPECT_EQ(c.flock.obstacles[0].radius, 0.5f);  // the listed ones first
  EXPECT_NEAR(c.flock.obstacles[1].radius, 1.0f, 1e-6f);
  EXPECT_NEAR(c.flock.obstacles[1].centre.x, -1.25f, 1e-6f);  // "mirror sphere"
  EXPECT_NEAR(c.flock.obstacles[4].radius, 0.35f, 1e-6f);

  // A tessellated sphere (an icosphere of radius 2 at (1, 2, 3)) counts with detect_spheres.
  test::Builder b;
  const UnitIcosphere ico = make_unit_icosphere(3);
  std::vector<float> xyz;
  for (const Imath::V3d& v : ico.vertices)
    for (int a = 0; a < 3; ++a) xyz.push_back(static_cast<float>(v[a] * 2.0));
  const int positions = b.positions(xyz);
  const int indices = b.accessor(b.view(ico.indices), 5125, ico.indices.size(), "SCALAR");
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", positions}}}, {"indices", indices}})},
          {"translation", {1.0, 2.0, 3.0}}});
  const std::string ball = b.write("boids_ball.gltf");
  const auto with = [&](bool detect) {
    return read_flock_config(write(R"({"version": 1, "obstacle_scene": {"file": ")" + ball +
                                   R"(", "detect_spheres": )" + (detect ? "true" : "false") + "}}"))
        .flock.obstacles;
  };
  EXPECT_TRUE(with(false).empty());
  const auto detected = with(true);
  ASSERT_EQ(detected.size(), 1u);
  EXPECT_NEAR(detected[0].radius, 2.0f, 1e-5f);  // its vertices lie on radius 2, to float rounding
  EXPECT_NEAR(detected[0].centre.z, 3.0f, 1e-5f);
  fs::remove(ball);

  const std::string missing = error(R"("obstacle_scene": {"file": "/nonexistent/field.gltf"})");
  EXPECT_NE(missing.find(": obstacle_scene.file: "), std::string::npos) << missing;
  EXPECT_EQ(missing.find('\n'), std::string::npos) << missing;
}

TEST(BoidsClip, FramesLoadBackWithEveryBoidOrientedAlongItsVelocity) {
  FlockParameters p = dense_field();
  p.boids = 5;
  ClipSettings clip;
  Flock flock(p, 1);
  flock.run(10);
  const fs::path path =
      fs::temp_directory_path() / ("prism_boids_frame_" + std::to_string(::getpid()) + ".gltf");
  std::ofstream(path) << frame_scene(p, clip, flock.positions(), flock.velocities()).dump();
  const SceneDescription scene = load_gltf(path.string());
  fs::remove(path);
  ASSERT_EQ(scene.spheres.size(), p.obstacles.size());
  for (size_t i = 0; i < p.obstacles.size(); ++i) {
    EXPECT_NEAR(scene.spheres[i].radius, p.obstacles[i].radius, 1e-6);
    EXPECT_NEAR(scene.spheres[i].centre.x, p.obstacles[i].centre.x, 1e-6);
  }
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.lights.size(), 2u);
  std::vector<const MeshInstance*> boids;
  for (const MeshInstance& m : scene.instances)
    if (m.node_name.rfind("boid", 0) == 0) boids.push_back(&m);
  ASSERT_EQ(boids.size(), 5u);
  for (size_t i = 0; i < boids.size(); ++i) {
    // The dart's nose (0, 0, 1) lands one body radius ahead along the velocity.
    const Imath::V3d nose = Imath::V3d(0.0, 0.0, 1.0) * boids[i]->object_to_world;
    const V3f expected = flock.positions()[i] + p.boid_radius * flock.velocities()[i].normalized();
    EXPECT_NEAR(nose.x, expected.x, 1e-5);
    EXPECT_NEAR(nose.y, expected.y, 1e-5);
    EXPECT_NEAR(nose.z, expected.z, 1e-5);
  }
  // The drawn body fits in the simulated one.
  for (const V3f& v : dart_triangles()) EXPECT_LE(v.length(), 1.0f);
}

}  // namespace
}  // namespace prism
