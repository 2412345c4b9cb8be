// Micro-benchmarks of Prism's hot paths, each on fixed inputs so runs compare:
//   - ray/sphere: the robust analytic test alone (intersect_sphere), the same test as Embree
//     user geometry, Embree's native sphere points, and icospheres of triangles, all on the
//     same rays; then the three modes through EmbreeScene::intersect, which adds Prism's hit
//     reconstruction;
//   - offset_ray_origin, the self-intersection offset every secondary ray pays;
//   - the pixel sample position: Owen-scrambled Sobol against independent hashing;
//   - shade_local on prepared hits of scenes/spheres.gltf, without and with shadow rays;
//   - one 16x16 tile of scenes/spheres.gltf (at the centre, and where whitted casts the most
//     rays) through each integrator's render_tile.
//
//   build-bench/bench/micro_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only
//
// items_per_second is rays (or hits shaded, or offsets) per second; for the tile loop it is
// pixels per second, with rays per second as the rays_per_second counter.
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include "integrators/local_shading.h"
#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/geometry/embree_ray.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/geometry/sphere_geometry.h"
#include "renderer/geometry/sphere_intersect.h"
#include "renderer/geometry/sphere_mesh.h"
#include "renderer/image/colour.h"
#include "renderer/math.h"
#include "renderer/render_scene.h"
#include "renderer/sampling/sampler.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"

namespace prism {
namespace {

// ---------------------------------------------------------------------------------------
// Ray/sphere.

// A square grid of spheres of radius 0.4 and spacing 1 in the z = 0 plane, centred on the
// origin; 1 sphere is the unit sphere at the origin.
std::vector<Sphere> sphere_field(int count) {
  if (count == 1) return {Sphere{V3d(0.0), 1.0, -1, "unit"}};
  const int side = int(std::lround(std::sqrt(double(count))));
  std::vector<Sphere> spheres;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      spheres.push_back(Sphere{V3d(i - 0.5 * (side - 1), j - 0.5 * (side - 1), 0.0), 0.4, -1, ""});
  return spheres;
}

// 128 x 128 rays from a point on +z through a square just wider than the spheres' extent,
// so some rays miss and rims are grazed, as in an image.
std::vector<Ray> sphere_rays(int count) {
  const float half = count == 1 ? 1.1f : 0.55f * std::sqrt(float(count));
  const V3f eye(0.0f, 0.0f, 4.0f * half);
  constexpr int kSide = 128;
  std::vector<Ray> rays;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const V3f target(half * (2.0f * (x + 0.5f) / kSide - 1.0f),
                       half * (2.0f * (y + 0.5f) / kSide - 1.0f), 0.0f);
      Ray r;
      r.origin = eye;
      r.direction = normalize(target - eye);
      rays.push_back(r);
    }
  return rays;
}

void finish(benchmark::State& state, size_t rays, size_t hits) {
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays));
  state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * double(rays));
}

void BM_SphereAnalyticAlone(benchmark::State& state) {
  const Sphere s = sphere_field(1).front();
  const V3f centre(s.centre);
  const float radius = float(s.radius);
  const std::vector<Ray> rays = sphere_rays(1);
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays)
      hits += intersect_sphere(r.origin, r.direction, centre, radius, r.tnear, r.tfar).has_value();
  finish(state, rays.size(), hits);
}
BENCHMARK(BM_SphereAnalyticAlone);

// A bare Embree scene (no EmbreeScene around it) holding the spheres in one of the three
// forms, traced with rtcIntersect1: what each form costs Embree itself.
class RawSphereScene {
 public:
  RawSphereScene(const std::vector<Sphere>& spheres, SphereMode mode, int level) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, embree_build_quality(GeometryOptions{}.build_quality));
    if (mode == SphereMode::analytic) {
      analytic_ = attach_analytic_spheres(device_, scene_, spheres);
    } else if (mode == SphereMode::embree_points) {
      attach_point_spheres(device_, scene_, spheres);
    } else {
      for (const Sphere& s : spheres) {
        const Primitive p = tessellate_sphere(s, level);
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
            p.positions.size() + 1));  // Embree reads 16 bytes per vertex: one float spare
        for (size_t i = 0; i < p.positions.size(); ++i)
          for (int k = 0; k < 3; ++k) v[3 * i + k] = p.positions[i][k];
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), p.indices.size() / 3));
        std::copy(p.indices.begin(), p.indices.end(), idx);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
      }
    }
    rtcCommitScene(scene_);
  }
  ~RawSphereScene() {
    if (analytic_ != RTC_INVALID_GEOMETRY_ID) release_analytic_spheres(scene_, analytic_);
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  RawSphereScene(const RawSphereScene&) = delete;
  RawSphereScene& operator=(const RawSphereScene&) = delete;

  bool intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = to_rtc_rayhit(ray);
    rtcIntersect1(scene_, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  unsigned analytic_ = RTC_INVALID_GEOMETRY_ID;
};

// Arguments: sphere mode (0 analytic user geometry, 1 Embree points, 2 mesh), mesh level,
// number of spheres.
void BM_SphereRawEmbree(benchmark::State& state) {
  const SphereMode mode = state.range(0) == 0   ? SphereMode::analytic
                          : state.range(0) == 1 ? SphereMode::embree_points
                                                : SphereMode::mesh;
  const int count = int(state.range(2));
  const RawSphereScene scene(sphere_field(count), mode, int(state.range(1)));
  const std::vector<Ray> rays = sphere_rays(count);
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays) hits += scene.intersect(r);
  finish(state, rays.size(), hits);
}
BENCHMARK(BM_SphereRawEmbree)
    ->ArgNames({"mode", "level", "spheres"})
    ->Args({0, 0, 1})
    ->Args({1, 0, 1})
    ->Args({2, 3, 1})
    ->Args({2, 5, 1})
    ->Args({0, 0, 1024})
    ->Args({1, 0, 1024})
    ->Args({2, 3, 1024})
    ->Args({2, 5, 1024});

// The same through Prism's EmbreeScene::intersect, which also rebuilds the hit (position,
// normals, material) for shading.
void BM_SphereEmbreeScene(benchmark::State& state) {
  GeometryOptions options;
  options.spheres.mode = state.range(0) == 0   ? SphereMode::analytic
                         : state.range(0) == 1 ? SphereMode::embree_points
                                               : SphereMode::mesh;
  options.spheres.mesh_level = int(state.range(1));
  const int count = int(state.range(2));
  SceneDescription description;
  description.spheres = sphere_field(count);
  const EmbreeScene scene(description, options);
  const std::vector<Ray> rays = sphere_rays(count);
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays) {
      SurfaceHit hit;
      hits += scene.intersect(r, &hit);
    }
  finish(state, rays.size(), hits);
}
BENCHMARK(BM_SphereEmbreeScene)
    ->ArgNames({"mode", "level", "spheres"})
    ->Args({0, 0, 1})
    ->Args({1, 0, 1})
    ->Args({2, 3, 1})
    ->Args({0, 0, 1024})
    ->Args({1, 0, 1024})
    ->Args({2, 3, 1024});

// ---------------------------------------------------------------------------------------
// The ray offset.

void BM_OffsetRayOrigin(benchmark::State& state) {
  // Points spread over magnitudes 1e-3 .. 1e3 (both branches of the offset: near the origin
  // a fixed step, elsewhere a number of ulps) with random unit normals.
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), exponent(-3.0f, 3.0f);
  std::vector<V3f> points, normals;
  for (int i = 0; i < 4096; ++i) {
    const float scale = std::pow(10.0f, exponent(rng));
    points.push_back(scale * V3f(unit(rng), unit(rng), unit(rng)));
    normals.push_back(normalize(V3f(unit(rng), unit(rng), unit(rng)) + V3f(1e-3f)));
  }
  for (auto _ : state) {
    V3f sum(0.0f);
    for (size_t i = 0; i < points.size(); ++i) sum += offset_ray_origin(points[i], normals[i]);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(points.size()));
}
BENCHMARK(BM_OffsetRayOrigin);

// The pixel sample every camera ray pays for when spp > 1: the Owen-scrambled Sobol point
// (renderer/sampling/sampler.h) against the independent hash it replaced (two sample_uniform
// calls). items_per_second is 2D samples per second. Instruction counts per call:
// bench/sampler_cost_bench.cpp.
void BM_PixelSample(benchmark::State& state) {
  const bool sobol = state.range(0) != 0;
  for (auto _ : state) {
    float sum = 0.0f;
    for (uint64_t pixel = 0; pixel < 64; ++pixel) {
      for (uint32_t k = 0; k < 64; ++k) {
        if (sobol) {
          const PixelSample2D p = sobol_owen_pixel_sample(pixel, k);
          sum += p.x + p.y;
        } else {
          sum += sample_uniform(pixel, k, 0) + sample_uniform(pixel, k, 1);
        }
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * 64 * 64);
  state.SetLabel(sobol ? "sobol-owen" : "independent");
}
BENCHMARK(BM_PixelSample)->Arg(0)->Arg(1);

// ---------------------------------------------------------------------------------------
// Shading and the tile loop on the shipped default scene.

const char* const kSpheresScene = PRISM_SOURCE_DIR "/scenes/spheres.gltf";

// scenes/spheres.gltf set up as `prism render` does (camera-rebased, default resolution
// 853x480), built once for every benchmark below.
struct ShippedScene {
  SceneDescription description;
  ColourPipeline colour{WorkingSpace::linear_rec709};
  std::unique_ptr<RenderScene> scene;
  std::unique_ptr<Camera> camera;
  RenderSettings settings;

  ShippedScene() {
    description = load_gltf(kSpheresScene);
    add_scene_defaults(&description);
    const CameraDescription& c = description.cameras.front();
    settings.height = 480;
    settings.width = int(std::lround(480.0 * c.aspect_ratio));
    settings.spp = 1;
    GeometryOptions options;
    options.world_origin = camera_position(c);
    scene = std::make_unique<RenderScene>(description, options, colour);
    camera = std::make_unique<Camera>(scene->camera(c, settings.width, settings.height));
  }
};

const ShippedScene& shipped() {
  static const ShippedScene s;
  return s;
}

// Every camera-ray hit of every 4th pixel in both directions, with the ray that made it.
struct PreparedHit {
  SurfaceHit hit;
  V3f to_viewer;
};

std::vector<PreparedHit> prepared_hits() {
  const ShippedScene& s = shipped();
  std::vector<PreparedHit> out;
  for (int y = 0; y < s.settings.height; y += 4)
    for (int x = 0; x < s.settings.width; x += 4) {
      const Ray ray = s.camera->generate_ray(x + 0.5f, y + 0.5f);
      PreparedHit p;
      if (s.scene->geometry().intersect(ray, &p.hit)) {
        p.to_viewer = -ray.direction;
        out.push_back(p);
      }
    }
  return out;
}

// Material evaluation (texture lookup included: the floor is textured) and the local
// shading equation for both lights; with Shadows, one rtcOccluded1 per light facing the hit.
template <bool Shadows>
void BM_ShadeLocal(benchmark::State& state) {
  const ShippedScene& s = shipped();
  const std::vector<PreparedHit> hits = prepared_hits();
  const RenderContext context{*s.scene, *s.camera, s.settings};
  RayCounters counters;
  for (auto _ : state) {
    V3f sum(0.0f);
    for (const PreparedHit& p : hits) {
      const SurfaceResponse surface = evaluate(s.scene->material(p.hit.material), p.hit);
      sum +=
          shade_local<Shadows>(context, AmbientLight{}, p.hit, surface, p.to_viewer, {}, &counters);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(hits.size()));
  state.counters["shadow_rays_per_hit"] =
      double(counters[RayKind::shadow]) / (double(state.iterations()) * double(hits.size()));
}
BENCHMARK(BM_ShadeLocal<false>)->Name("BM_ShadeLocal/phong");
BENCHMARK(BM_ShadeLocal<true>)->Name("BM_ShadeLocal/shadows");

// The tile where the whitted integrator casts the most rays (on the glass and mirror
// spheres), found once by rendering every tile: the tile loop's cost where secondary rays
// dominate. Tile 0 is the one at the image centre, for a floor-and-wall mix.
TileRect bench_tile(bool busiest) {
  const ShippedScene& s = shipped();
  const int w = s.settings.width, h = s.settings.height;
  if (!busiest) {
    const int x0 = (w / 2) & ~15, y0 = (h / 2) & ~15;
    return {x0, y0, x0 + 16, y0 + 16};
  }
  const std::unique_ptr<Integrator> whitted = make_integrator("whitted");
  const RenderContext context{*s.scene, *s.camera, s.settings};
  Image image(w, h);
  TileRect best{0, 0, 16, 16};
  uint64_t most = 0;
  for (int y0 = 0; y0 + 16 <= h; y0 += 16)
    for (int x0 = 0; x0 + 16 <= w; x0 += 16) {
      RayCounters counters;
      const TileRect tile{x0, y0, x0 + 16, y0 + 16};
      whitted->render_tile(context, tile, &image, &counters);
      if (counters.total() > most) {
        most = counters.total();
        best = tile;
      }
    }
  return best;
}

// One 16x16 tile through an integrator's render_tile: ray generation, tracing, shading and
// the image write. Arguments: integrator (index in the registry), tile (0 centre, 1 busiest).
void BM_TileLoop(benchmark::State& state) {
  const ShippedScene& s = shipped();
  const IntegratorInfo& info = *integrator_registry()[static_cast<size_t>(state.range(0))];
  const std::unique_ptr<Integrator> integrator = configure_integrator(info).integrator;
  const RenderContext context{*s.scene, *s.camera, s.settings};
  Image image(s.settings.width, s.settings.height);
  static const TileRect centre = bench_tile(false), busiest = bench_tile(true);
  const TileRect tile = state.range(1) ? busiest : centre;
  RayCounters counters;
  for (auto _ : state) integrator->render_tile(context, tile, &image, &counters);
  state.SetLabel(std::string(info.name) + " tile (" + std::to_string(tile.x0) + "," +
                 std::to_string(tile.y0) + ")");
  state.SetItemsProcessed(int64_t(state.iterations()) * 256);
  state.counters["rays_per_second"] =
      benchmark::Counter(double(counters.total()), benchmark::Counter::kIsRate);
  state.counters["rays_per_pixel"] =
      double(counters.total()) / (double(state.iterations()) * 256.0);
}
BENCHMARK(BM_TileLoop)
    ->ArgNames({"integrator", "busiest"})
    ->ArgsProduct(
        {benchmark::CreateDenseRange(0, static_cast<int>(integrator_registry().size()) - 1, 1),
         {0, 1}});

}  // namespace
}  // namespace prism

BENCHMARK_MAIN();
