// GeometryOptions::build_quality and compact, `prism render --build-quality`, and the
// parallel construction of EmbreeScene: a BVH's quality or layout changes how fast rays find
// their hit, never which hit, so the image must not change; nor may the thread count that
// copied and cleaned the meshes.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <tbb/global_control.h>

#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/geometry/embree_device.h"
#include "renderer/geometry/sphere_mesh.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"
#include "session/session.h"
#include "tests/scratch_dir.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

// Baked meshes (placed once) and instanced ones (several nodes share 14 of its meshes), 110k
// triangles: both paths of EmbreeScene's constructor.
const std::string kEngine =
    std::string(PRISM_ASSIMP_GLTF2_DIR) + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

SceneDescription engine() {
  SceneDescription scene = load_gltf(kEngine);
  add_scene_defaults(&scene);
  return scene;
}

testing::Rendered render_shadow(const SceneDescription& scene, const GeometryOptions& options) {
  testing::TestSettings settings;
  settings.width = 160;
  settings.height = 120;
  settings.spp = 1;
  return testing::render_scene(scene, "shadow", settings, options);
}

// The geometry as `prism render` places it: rebased on the camera.
GeometryOptions options_for(const SceneDescription& scene, BuildQuality quality, bool compact) {
  GeometryOptions options;
  options.world_origin = camera_position(scene.cameras.front());
  options.build_quality = quality;
  options.compact = compact;
  return options;
}

size_t hit_pixels(const Image& image) {
  size_t n = 0;
  for (size_t i = 0; i < image.rgba.size(); i += 4)
    n += image.rgba[i] > 0.0f || image.rgba[i + 1] > 0.0f || image.rgba[i + 2] > 0.0f;
  return n;
}

TEST(BuildQuality, ParsesItsFourNamesAndNothingElse) {
  for (BuildQuality q :
       {BuildQuality::low, BuildQuality::medium, BuildQuality::high, BuildQuality::automatic}) {
    BuildQuality parsed = q == BuildQuality::low ? BuildQuality::high : BuildQuality::low;
    EXPECT_TRUE(parse_enum(to_string(q), &parsed)) << to_string(q);
    EXPECT_EQ(parsed, q);
  }
  BuildQuality untouched = BuildQuality::medium;
  for (const char* bad : {"", "High", "best", "high ", "2", "automatic"}) {
    EXPECT_FALSE(parse_enum(bad, &untouched)) << '"' << bad << '"';
    EXPECT_EQ(untouched, BuildQuality::medium);
  }
}

// Every quality, with and without RTC_SCENE_FLAG_COMPACT, finds the same nearest hits at the
// pixel centres: bit-identical images (measured so on this scene and on the 1M-triangle
// terrain, docs/benchmarks.md, "BVH build quality and flags"). With 16 samples per pixel one
// engine pixel in 230 400 differed: two triangles at exactly the same distance, of which the
// traversal order picks one.
TEST(BuildQuality, EveryQualityAndLayoutGivesTheSameImage) {
  const SceneDescription scene = engine();
  const testing::Rendered reference =
      render_shadow(scene, options_for(scene, BuildQuality::high, false));
  // Not a black image that would match anything: the engine fills a good part of the frame.
  ASSERT_GT(hit_pixels(reference.image), size_t(160 * 120 / 10));
  for (BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high})
    for (bool compact : {false, true}) {
      const testing::Rendered r = render_shadow(scene, options_for(scene, q, compact));
      EXPECT_TRUE(r.image.rgba == reference.image.rgba)
          << to_string(q) << (compact ? " compact" : "");
      EXPECT_EQ(r.result.rays[RayKind::shadow], reference.result.rays[RayKind::shadow])
          << to_string(q);
    }
}

// Each quality reaches Embree's builder for the meshes themselves (rtcSetGeometryBuildQuality,
// not only the scene's): the BVHs Embree holds for the engine differ in size between every
// pair of qualities (low: Morton build; medium: binned SAH; high: SAH with spatial splits).
// (Scene-level quality still changes the BVHs over instances, so a lone mesh is the test.)
// With the scene's quality alone, low and medium built the meshes identically.
TEST(BuildQuality, EveryQualityReachesTheMeshBuilds) {
  // One mesh placed once (81 920 triangles): the only BVH is the one over its triangles.
  SceneDescription scene;
  Mesh ball;
  ball.primitives.push_back(tessellate_sphere(Sphere{V3d(0, 0, 0), 1.0, -1, ""}, 6));
  scene.meshes.push_back(ball);
  scene.instances.push_back(MeshInstance{0, M44d(), "ball"});
  scene.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.2));
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  long long bytes[3] = {0, 0, 0};
  int i = 0;
  for (BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high}) {
    auto device = std::make_shared<EmbreeDevice>();
    const long long before = device->bytes_in_use();
    const RenderScene built(device, scene, options_for(scene, q, false), colour);
    bytes[i++] = device->bytes_in_use() - before;
    std::printf("build quality %-6s: Embree holds %lld bytes\n", to_string(q), bytes[i - 1]);
  }
  EXPECT_GT(bytes[0], 0);
  EXPECT_NE(bytes[0], bytes[1]);
  EXPECT_NE(bytes[1], bytes[2]);
  EXPECT_NE(bytes[0], bytes[2]);
}

// LOW is for previews of big meshes, where writing the BVH is most of the build: it always
// takes the compact layout, so it holds what LOW with COMPACT asked for holds, and less than
// MEDIUM's default layout (Triangle4i leaves index the shared vertices instead of copying them).
TEST(BuildQuality, LowBuildsTheCompactLayout) {
  SceneDescription scene;
  Mesh ball;
  ball.primitives.push_back(tessellate_sphere(Sphere{V3d(0, 0, 0), 1.0, -1, ""}, 6));
  scene.meshes.push_back(ball);
  scene.instances.push_back(MeshInstance{0, M44d(), "ball"});
  scene.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.2));
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  auto held = [&](BuildQuality q, bool compact) {
    auto device = std::make_shared<EmbreeDevice>();
    const long long before = device->bytes_in_use();
    const RenderScene built(device, scene, options_for(scene, q, compact), colour);
    return device->bytes_in_use() - before;
  };
  const long long low = held(BuildQuality::low, false);
  EXPECT_EQ(low, held(BuildQuality::low, true));
  EXPECT_LT(low, held(BuildQuality::medium, false));
  EXPECT_GT(held(BuildQuality::medium, false), held(BuildQuality::medium, true));
}

// The meshes are copied, baked and cleaned in parallel, then attached in the scene's order:
// the same geomIDs, statistics and image with one thread as with two.
TEST(BuildQuality, ParallelConstructionIsIndependentOfTheThreadCount) {
  const SceneDescription scene = engine();
  const GeometryOptions options = options_for(scene, BuildQuality::medium, false);
  testing::Rendered one, two;
  GeometryStatistics stats_one, stats_two;
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render_shadow(scene, options);
    stats_one = RenderScene(scene, options, colour).geometry().statistics();
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render_shadow(scene, options);
    stats_two = RenderScene(scene, options, colour).geometry().statistics();
  }
  EXPECT_TRUE(one.image.rgba == two.image.rgba);
  EXPECT_EQ(stats_one.triangles, stats_two.triangles);
  EXPECT_EQ(stats_one.meshes_baked, stats_two.meshes_baked);
  EXPECT_EQ(stats_one.mesh_instances, stats_two.mesh_instances);
  EXPECT_EQ(stats_one.degenerate_triangles, stats_two.degenerate_triangles);
  EXPECT_EQ(stats_one.normals_repaired, stats_two.normals_repaired);
  EXPECT_GT(stats_one.meshes_baked, 0u);
  EXPECT_GT(stats_one.mesh_instances, 0u);
}

// A value the option does not know: exit code 2, one line naming the option and the choices,
// no image written.
TEST(BuildQuality, CommandLineRefusesAnUnknownQualityInOneLine) {
  const std::filesystem::path dir = test::scratch_dir("build_quality");
  const std::filesystem::path image = dir / "bad.exr";
  std::filesystem::remove(image);
  const std::string command = std::string(PRISM_BINARY) + " render " + PRISM_SOURCE_DIR +
                              "/scenes/spheres.gltf -o " + image.string() +
                              " --res 32x18 --build-quality best 2>&1 >/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string err;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe)) err += buffer;
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_EQ(err, "prism: error: --build-quality best: expected low, medium, high or auto\n");
  EXPECT_FALSE(std::filesystem::exists(image));
}

// The rule at its two crossovers: LOW below kLowBuildRaysPerPrimitive rays per primitive,
// HIGH above kHighBuildRaysPerPrimitive, MEDIUM between and at both.
TEST(BuildQuality, AutomaticChoosesByRaysPerPrimitive) {
  const double n = 4e6;
  EXPECT_EQ(automatic_build_quality(640.0 * 480.0, n), BuildQuality::low);  // a 1-spp preview
  EXPECT_EQ(automatic_build_quality(kLowBuildRaysPerPrimitive * n * 0.99, n), BuildQuality::low);
  EXPECT_EQ(automatic_build_quality(kLowBuildRaysPerPrimitive * n, n), BuildQuality::medium);
  EXPECT_EQ(automatic_build_quality(kHighBuildRaysPerPrimitive * n, n), BuildQuality::medium);
  EXPECT_EQ(automatic_build_quality(kHighBuildRaysPerPrimitive * n * 1.01, n), BuildQuality::high);
  EXPECT_EQ(automatic_build_quality(1e9, 0.0), BuildQuality::medium);  // nothing to build
}

// A session settles `auto` from the job (resolution x spp x (1 + max-depth)) against the
// engine's triangles, and builds exactly what the named quality builds: Embree holds the
// same bytes as for that quality, and other bytes than for the others.
TEST(BuildQuality, AutomaticReachesEmbreeAsTheQualityItChose) {
  SceneRequest request;
  request.path = kEngine;
  SessionOptions options;
  options.threads = 1;  // Embree's per-thread allocation blocks make its bytes vary otherwise
  struct Case {
    int width, height, spp;
    const char* integrator;
    BuildQuality expected;
  };
  // 110k triangles: 64 x 48 at 1 spp is 0.03 rays each, 320 x 240 at 16 spp about 11,
  // 640 x 480 at 1024 spp with Whitted's 5 bounces about 17 000.
  const Case cases[] = {{64, 48, 1, "shadow", BuildQuality::low},
                        {320, 240, 16, "shadow", BuildQuality::medium},
                        {640, 480, 1024, "whitted", BuildQuality::high}};
  uint64_t bytes[3] = {0, 0, 0};
  for (BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high}) {
    Session session(request, options);
    RenderJob job;
    job.width = 64;
    job.height = 48;
    job.build_quality = q;
    EXPECT_EQ(session.build_quality(job), q);
    session.render_scene(job);
    bytes[static_cast<int>(q)] = session.memory_bytes();
  }
  EXPECT_NE(bytes[0], bytes[1]);
  EXPECT_NE(bytes[1], bytes[2]);
  for (const Case& c : cases) {
    Session session(request, options);
    RenderJob job;
    job.width = c.width;
    job.height = c.height;
    job.film.spp = c.spp;
    job.integrator = c.integrator;
    ASSERT_EQ(job.build_quality, BuildQuality::automatic);  // the default
    EXPECT_EQ(session.build_quality(job), c.expected) << c.width << "x" << c.height << " " << c.spp;
    session.render_scene(job);
    EXPECT_EQ(session.memory_bytes(), bytes[static_cast<int>(c.expected)]) << to_string(c.expected);
  }
}

}  // namespace
}  // namespace prism
