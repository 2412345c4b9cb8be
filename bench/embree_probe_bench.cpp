// How close Prism gets to Embree's own speed: a plain Embree scene built straight from the
// SceneDescription (no EmbreeScene code; meshes baked or instanced by Prism's rule, or all
// baked with --flat; spheres as Embree's native sphere points; Prism's default build
// quality; no degenerate-triangle cleaning), traced with exactly the rays Prism's `shadow`
// integrator casts at 1 spp, with no shading, one ray at a time and as 8- and 16-wide
// packets. The same image is then rendered by Prism's `phong` and `shadow` integrators in
// this process and the rays per second compared.
//
//   build-bench/bench/embree_probe_bench [--res WxH] [--reps N] [--min-seconds S]
//                                        [--threads 1,2] [--flat] SCENE...
//
// Rays, as Prism casts them (integrators/local_shading.h):
//   - camera rays: Prism's Camera through every pixel centre, in the frame rebased on the
//     camera (GeometryOptions::world_origin), in the order of the tile loop's packets;
//   - shadow rays: for each hit, one per light that light_arrival() reaches and that faces
//     the shading normal turned towards the viewer, from the hit point moved by
//     offset_ray_origin() along that normal, ending at the light.
// The probe does not apply Hanika's terminator offset (Prism does, on smooth triangles), so
// a few origins differ by a fraction of a triangle; the table prints both shadow-ray counts
// to show the ray sets agree in size.
//
// Every measurement is repeated until it has run for --min-seconds, and the whole set
// --reps times, interleaved (probe, then Prism, then probe again...), so that load from
// other jobs hits all of them alike; the median is printed. Times exclude building the BVH
// and preparing the ray arrays: the probe times rtcIntersect/rtcOccluded calls alone, Prism
// its render() call (ray generation, traversal, hit reconstruction, shading, image writes).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bench/raw_embree.h"
#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/geometry/embree_ray.h"
#include "renderer/image/colour.h"
#include "renderer/math.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "renderer/shading/lights.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"

namespace prism {
namespace {

using probe::measure_rays;
using probe::median;
using probe::RawScene;
using probe::RaySet;
using probe::TraceRate;
using probe::yes_no;

// ---------------------------------------------------------------------------------------
// The rays.

// Pixel centres in the order the tile loop visits them (16x16 tiles, 4x4 blocks within a
// tile, rows within a block: integrators/tile_loop.h), so that packets of 16 consecutive
// rays are exactly Prism's camera-ray packets.
std::vector<Ray> camera_rays(const Camera& camera, int width, int height) {
  std::vector<Ray> rays;
  rays.reserve(size_t(width) * height);
  constexpr int kTile = 16, kBlock = 4;
  for (int ty = 0; ty < height; ty += kTile)
    for (int tx = 0; tx < width; tx += kTile)
      for (int by = ty; by < std::min(ty + kTile, height); by += kBlock)
        for (int bx = tx; bx < std::min(tx + kTile, width); bx += kBlock)
          for (int y = by; y < std::min(by + kBlock, height); ++y)
            for (int x = bx; x < std::min(bx + kBlock, width); ++x)
              rays.push_back(camera.generate_ray(float(x) + 0.5f, float(y) + 0.5f));
  return rays;
}

// The shadow rays Prism's shade_local<true> casts from these camera hits.
std::vector<Ray> shadow_rays(const RawScene& raw, const std::vector<Ray>& camera,
                             const std::vector<LightSource>& lights, size_t* hits) {
  std::vector<Ray> out;
  *hits = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (const Ray& ray : camera) {
    RTCRayHit rh = to_rtc_rayhit(ray);
    rtcIntersect1(raw.scene(), &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    ++*hits;
    V3f position, normal;
    raw.surface(rh, &position, &normal);
    const V3f n = face_forward(normal, -ray.direction);
    for (const LightSource& light : lights) {
      LightSample arrival;
      if (!light.sample(position, Imath::V2f(0.0f), &arrival)) continue;
      if (dot(n, arrival.wi) <= 0.0f) continue;
      Ray shadow;
      shadow.origin = offset_ray_origin(position, n);
      shadow.direction = arrival.wi;
      shadow.tfar = arrival.distance;
      out.push_back(shadow);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Measuring.

// The camera rays are the ray set's intersect part, the shadow rays its occluded part; the
// two are timed apart so the camera rays alone can be set against the phong integrator,
// which casts no shadow rays.

// Prism's own render of the same image, 1 spp through pixel centres.
struct PrismRate {
  double rays_per_second = 0.0;
  RayCounters rays;
};

PrismRate measure_prism(const RenderScene& scene, const Camera& camera, int width, int height,
                        const char* kind, int threads, double min_seconds) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = 1;
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  const RenderContext context{scene, camera, settings};
  const std::unique_ptr<Integrator> integrator = make_integrator(kind);
  PrismRate rate;
  double seconds = 0.0, rays = 0.0;
  while (seconds < min_seconds) {
    Image image;
    RenderResult r;
    arena.execute([&] { r = render(*integrator, context, &image); });
    seconds += r.seconds;
    rays += double(r.rays.total());
    rate.rays = r.rays;
  }
  rate.rays_per_second = rays / seconds;
  return rate;
}

struct Options {
  int width = 640, height = 480;
  bool explicit_resolution = false;
  bool flat = false;  // bake every mesh placement instead of instancing shared meshes
  int reps = 5;
  double min_seconds = 0.3;
  std::vector<int> threads{1, 2};
  std::vector<std::string> scenes;
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "embree_probe_bench: %s\nusage: embree_probe_bench [--res WxH] [--reps N] "
               "[--min-seconds S] [--threads 1,2] [--flat] SCENE...\n",
               why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--res") {
      if (std::sscanf(value().c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 ||
          o.height < 1)
        usage("--res expects WxH");
      o.explicit_resolution = true;
    } else if (a == "--reps") {
      o.reps = std::max(1, std::atoi(value().c_str()));
    } else if (a == "--min-seconds") {
      o.min_seconds = std::atof(value().c_str());
    } else if (a == "--threads") {
      o.threads.clear();
      const std::string list = value();
      for (size_t p = 0; p < list.size();) {
        const size_t comma = std::min(list.find(',', p), list.size());
        o.threads.push_back(std::max(1, std::atoi(list.substr(p, comma - p).c_str())));
        p = comma + 1;
      }
    } else if (a == "--flat") {
      o.flat = true;
    } else if (!a.empty() && a[0] == '-') {
      usage(("unknown option " + a).c_str());
    } else {
      o.scenes.push_back(a);
    }
  }
  if (o.scenes.empty()) usage("no scene given");
  return o;
}

// One scene: prints its rows of the table.
void probe_scene(const Options& o, const std::string& path) {
  SceneDescription scene = load_gltf(path);
  add_scene_defaults(&scene);  // as `prism render` does: a camera and a light if missing
  const CameraDescription& description = scene.cameras.front();
  int width = o.width, height = o.height;
  // Without --res, the resolution `prism render` picks: 480 rows, the camera's aspect.
  if (!o.explicit_resolution && description.aspect_ratio > 0.0) {
    height = 480;
    width = std::max(1, int(std::lround(480.0 * description.aspect_ratio)));
  }
  const V3d origin = camera_position(description);
  const ColourPipeline colour(WorkingSpace::linear_rec709);

  // Prism with its default spheres (analytic user geometry) and with Embree's sphere points,
  // the probe's own sphere primitive; for a scene without spheres the two are the same.
  struct Variant {
    const char* name;
    SphereMode mode;
  };
  std::vector<Variant> variants{{"analytic", SphereMode::analytic}};
  if (!scene.spheres.empty()) variants.push_back({"embree-points", SphereMode::embree_points});
  std::vector<std::unique_ptr<RenderScene>> prism_scenes;
  for (const Variant& v : variants) {
    GeometryOptions g;
    g.world_origin = origin;
    g.spheres.mode = v.mode;
    prism_scenes.push_back(std::make_unique<RenderScene>(scene, g, colour));
  }
  const Camera camera = prism_scenes.front()->camera(description, width, height);

  const RawScene raw(scene, origin, o.flat);
  const std::vector<Ray> camera_set = camera_rays(camera, width, height);
  size_t hits = 0;
  const std::vector<Ray> shadow_set =
      shadow_rays(raw, camera_set, prism_scenes.front()->lights(), &hits);
  RaySet<1> set1(camera_set, shadow_set);
  RaySet<8> set8(camera_set, shadow_set);
  RaySet<16> set16(camera_set, shadow_set);

  std::printf(
      "\n%s: %dx%d, %zu triangles (%zu instances%s), %zu spheres, %zu lights; %zu camera "
      "rays (%zu hit), %zu shadow rays\n",
      path.c_str(), width, height, raw.triangles(), raw.instances(), o.flat ? ", --flat" : "",
      scene.spheres.size(), scene.lights.size(), camera_set.size(), hits, shadow_set.size());

  for (int threads : o.threads) {
    // Medians over o.reps interleaved rounds.
    std::vector<double> p1, p8, p16, c1, c8, c16;
    std::vector<std::vector<double>> shadow(variants.size()), phong(variants.size());
    std::vector<PrismRate> last_shadow(variants.size()), last_phong(variants.size());
    size_t blocked1 = 0, blocked8 = 0, blocked16 = 0, hits8 = 0, hits16 = 0;
    for (int rep = 0; rep < o.reps; ++rep) {
      const TraceRate r1 = measure_rays(&set1, raw.scene(), threads, o.min_seconds);
      const TraceRate r8 = measure_rays(&set8, raw.scene(), threads, o.min_seconds);
      const TraceRate r16 = measure_rays(&set16, raw.scene(), threads, o.min_seconds);
      p1.push_back(r1.per_second);
      p8.push_back(r8.per_second);
      p16.push_back(r16.per_second);
      c1.push_back(r1.intersect_per_second);
      c8.push_back(r8.intersect_per_second);
      c16.push_back(r16.intersect_per_second);
      blocked1 = r1.blocked;
      blocked8 = r8.blocked;
      blocked16 = r16.blocked;
      hits8 = r8.hits;
      hits16 = r16.hits;
      if (r1.hits != hits) std::fprintf(stderr, "probe: 1-wide hits differ from setup\n");
      for (size_t v = 0; v < variants.size(); ++v) {
        last_shadow[v] = measure_prism(*prism_scenes[v], camera, width, height, "shadow", threads,
                                       o.min_seconds);
        last_phong[v] =
            measure_prism(*prism_scenes[v], camera, width, height, "phong", threads, o.min_seconds);
        shadow[v].push_back(last_shadow[v].rays_per_second);
        phong[v].push_back(last_phong[v].rays_per_second);
      }
    }
    std::printf(
        "  threads %d: probe blocked shadow rays 1/8/16-wide %zu/%zu/%zu, hits 8/16-wide "
        "%zu/%zu\n",
        threads, blocked1, blocked8, blocked16, hits8, hits16);
    const double m1 = median(p1), m8 = median(p8), m16 = median(p16);
    const double mc1 = median(c1), mc8 = median(c8), mc16 = median(c16);
    std::printf(
        "| scene | threads | rays | probe 1-wide Mrays/s | probe 8-wide | probe 16-wide | "
        "Prism | Prism Mrays/s | Prism / probe 1-wide | Prism / probe 16-wide |\n");
    std::printf("| --- | ---: | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: |\n");
    const std::string name = path.substr(path.find_last_of('/') + 1);
    for (size_t v = 0; v < variants.size(); ++v) {
      const double ms = median(shadow[v]);
      std::printf(
          "| %s | %d | camera + shadow (%zu + %zu; Prism %llu + %llu) | %.3f | %.3f | "
          "%.3f | shadow, spheres %s | %.3f | %.3f | %.3f |\n",
          name.c_str(), threads, camera_set.size(), shadow_set.size(),
          (unsigned long long)last_shadow[v].rays[RayKind::camera],
          (unsigned long long)last_shadow[v].rays[RayKind::shadow], m1 / 1e6, m8 / 1e6, m16 / 1e6,
          variants[v].name, ms / 1e6, ms / m1, ms / m16);
    }
    for (size_t v = 0; v < variants.size(); ++v) {
      const double mp = median(phong[v]);
      std::printf(
          "| %s | %d | camera only (%zu) | %.3f | %.3f | %.3f | phong, spheres %s | %.3f "
          "| %.3f | %.3f |\n",
          name.c_str(), threads, camera_set.size(), mc1 / 1e6, mc8 / 1e6, mc16 / 1e6,
          variants[v].name, mp / 1e6, mp / mc1, mp / mc16);
    }
  }
}

}  // namespace
}  // namespace prism

int main(int argc, char** argv) {
  const prism::Options o = prism::parse(argc, argv);
  {
    RTCDevice device = rtcNewDevice(nullptr);
    std::printf(
        "Embree %s; native packets: 4-wide %s, 8-wide %s, 16-wide %s; ray stream %s; "
        "%d reps, median, >= %.2f s each\n",
        RTC_VERSION_STRING, prism::probe::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED),
        prism::probe::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
        prism::probe::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED),
        prism::probe::yes_no(device, RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED), o.reps,
        o.min_seconds);
    rtcReleaseDevice(device);
  }
  try {
    for (const std::string& path : o.scenes) prism::probe_scene(o, path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embree_probe_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
