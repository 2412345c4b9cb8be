// What RTC_SCENE_FLAG_ROBUST (GeometryOptions::robust: Embree's watertight triangle test
// and robust traversal) costs: the same camera rays, traced with and without it, at
// assimp's 2CylinderEngine (~120k triangles) and at a set of tessellated spheres. Stress
// case 8 (tests/stress/08_watertight_test.cpp) shows what it buys.
//
//   build/bench/robust_flag_bench --benchmark_repetitions=3
//
// Rays per second are reported as the items_per_second counter.
#include <cstdio>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "renderer/camera.h"
#include "renderer/geometry/embree_scene.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

constexpr int kWidth = 320, kHeight = 240;
const char* const kEngine =
    "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

// A perspective camera on the +Z side of the scene's bounds, framing all of it.
std::vector<Ray> camera_rays(const Imath::Box3f& bounds) {
  const V3f centre = 0.5f * (bounds.min + bounds.max);
  const float extent = (bounds.max - bounds.min).length();
  CameraDescription c;
  c.yfov = 0.8;
  c.camera_to_world = M44d().setTranslation(V3d(centre.x, centre.y, centre.z + 1.2 * extent));
  const Camera camera(c, kWidth, kHeight, V3d(0.0));
  std::vector<Ray> rays;
  rays.reserve(size_t(kWidth) * kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) rays.push_back(camera.generate_ray(x + 0.5f, y + 0.5f));
  return rays;
}

SceneDescription sphere_set() {
  SceneDescription scene;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      scene.spheres.push_back(Sphere{V3d(2.5 * i, 2.5 * j, 0.0), 1.0, -1, "s"});
  return scene;
}

void trace(benchmark::State& state, const SceneDescription& scene, bool robust) {
  GeometryOptions options;
  options.robust = robust;
  options.spheres = {SphereMode::mesh, 4};
  const EmbreeScene geometry(scene, options);
  const std::vector<Ray> rays = camera_rays(geometry.bounds());
  size_t hits = 0;
  for (auto _ : state) {
    for (const Ray& ray : rays) {
      SurfaceHit hit;
      hits += geometry.intersect(ray, &hit);
    }
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
  state.counters["hit_fraction"] =
      double(hits) / (double(state.iterations()) * double(rays.size()));
}

void BM_Engine(benchmark::State& state) {
  static const SceneDescription scene = load_gltf(kEngine);
  trace(state, scene, state.range(0) != 0);
}

void BM_TessellatedSpheres(benchmark::State& state) {
  static const SceneDescription scene = sphere_set();
  trace(state, scene, state.range(0) != 0);
}

// Argument: 0 = default flags, 1 = RTC_SCENE_FLAG_ROBUST.
BENCHMARK(BM_Engine)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TessellatedSpheres)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace prism

BENCHMARK_MAIN();
