// What Embree's build quality and scene flags cost and buy (GeometryOptions::build_quality,
// compact, robust): for each scene, every combination of RTC_BUILD_QUALITY_LOW / MEDIUM /
// HIGH, RTC_SCENE_FLAG_COMPACT off / on and RTC_SCENE_FLAG_ROBUST off / on is built
// (RenderScene, as `prism render` builds it: rebased on the camera) and rendered with the
// `shadow` integrator at --spp (1), 480 pixels high at the camera's aspect ratio. The variants
// are interleaved (each repetition starting one variant later, so none always runs first),
// the whole set repeated --reps times, and medians printed with the range, so that a shared,
// loaded machine slows every variant alike. --spp traces more rays per build (a final
// render's share); --no-robust leaves out the ROBUST variants.
//
//   build/bench/build_flags_bench [--reps 5] [--threads N] [--spp 1] [--no-robust] SCENE...
//
// Columns: build = the RenderScene's construction (Prism's copy, bake and clean of every
// mesh, then Embree's BVH build; the materials and lights are negligible next to it),
// trace = the render's time, Mrays/s = its camera and shadow rays over that time. The BVH's
// memory comes from a separate raw Embree build (rtcSetDeviceMemoryMonitorFunction) of each
// distinct mesh once, in object space, with the same quality and flags: peak = the most Embree
// held during the build, kept = what it holds after. Prism's own copy of the meshes is not
// in it. "image" compares the variant's image (the last repetition's) with LOW's without flags:
// "same" when bit-identical, else how many pixels differ and the largest difference.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/global_control.h>

#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/image/colour.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"

namespace prism {
namespace {

struct Variant {
  BuildQuality quality;
  bool compact;
  bool robust;
};

struct Memory {
  std::atomic<long long> current{0};
  std::atomic<long long> peak{0};
};

bool monitor(void* user, ssize_t bytes, bool /*post*/) {
  auto* m = static_cast<Memory*>(user);
  const long long now = m->current += bytes;
  long long peak = m->peak.load();
  while (now > peak && !m->peak.compare_exchange_weak(peak, now)) {
  }
  return true;
}

// Embree's bytes for the BVH over every distinct mesh of `scene` (object space, once each).
void bvh_memory(const SceneDescription& scene, const Variant& v, double* peak_mib,
                double* kept_mib) {
  RTCDevice device = rtcNewDevice(nullptr);
  Memory memory;
  rtcSetDeviceMemoryMonitorFunction(device, monitor, &memory);
  RTCScene s = rtcNewScene(device);
  rtcSetSceneFlags(s, static_cast<RTCSceneFlags>((v.compact ? RTC_SCENE_FLAG_COMPACT : 0) |
                                                 (v.robust ? RTC_SCENE_FLAG_ROBUST : 0)));
  rtcSetSceneBuildQuality(s, embree_build_quality(v.quality));
  std::vector<std::vector<V3f>> padded;  // Embree reads 4 bytes past the last vertex
  for (const Mesh& mesh : scene.meshes)
    for (const Primitive& p : mesh.primitives) {
      if (p.indices.size() < 3 || p.positions.empty()) continue;
      padded.push_back(p.positions);
      padded.back().push_back(V3f(0.0f));
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                 padded.back().data(), 0, sizeof(V3f), p.positions.size());
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, p.indices.data(), 0,
                                 3 * sizeof(uint32_t), p.indices.size() / 3);
      rtcCommitGeometry(g);
      rtcAttachGeometry(s, g);
      rtcReleaseGeometry(g);
    }
  const long long before = memory.current.load();
  memory.peak = before;
  rtcCommitScene(s);
  *peak_mib = double(memory.peak.load() - before) / (1024.0 * 1024.0);
  *kept_mib = double(memory.current.load() - before) / (1024.0 * 1024.0);
  rtcReleaseScene(s);
  rtcReleaseDevice(device);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "same" when bit-identical, else how many pixels differ and by how much at most (RGB).
std::string image_difference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a == b) return "same";
  size_t pixels = 0;
  float largest = 0.0f;
  for (size_t p = 0; p + 3 < a.size(); p += 4) {
    float d = 0.0f;
    for (size_t c = 0; c < 3; ++c) d = std::max(d, std::fabs(a[p + c] - b[p + c]));
    pixels += d > 0.0f;
    largest = std::max(largest, d);
  }
  char text[96];
  std::snprintf(text, sizeof text, "%zu px differ, max %.3g", pixels, largest);
  return text;
}

// "0.644 (0.610-0.702)"
std::string summary(const std::vector<double>& v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f (%.3f-%.3f)", median(v),
                *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()));
  return text;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

int run(int argc, char** argv) {
  int reps = 5, threads = 0, spp = 1;
  bool with_robust = true;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--spp") && i + 1 < argc)
      spp = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--no-robust"))
      with_robust = false;
    else
      paths.push_back(argv[i]);
  }
  if (paths.empty()) {
    std::fprintf(stderr,
                 "usage: build_flags_bench [--reps N] [--threads N] [--spp N] [--no-robust] "
                 "SCENE...\n");
    return 2;
  }
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<size_t>(threads));
  std::vector<Variant> variants;
  for (bool robust : {false, true}) {
    if (robust && !with_robust) continue;
    for (bool compact : {false, true})
      for (BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high})
        variants.push_back({q, compact, robust});
  }

  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const auto integrator = make_integrator("shadow");
  for (const std::string& path : paths) {
    SceneDescription scene = load_gltf(path);
    add_scene_defaults(&scene);
    const CameraDescription& description = scene.cameras.front();
    RenderSettings settings;
    settings.height = 480;
    if (description.aspect_ratio > 0.0)
      settings.width = std::max(1, static_cast<int>(std::lround(480.0 * description.aspect_ratio)));
    settings.spp = spp;
    const std::string load_before = load_average();
    std::vector<std::vector<double>> build(variants.size()), trace(variants.size()),
        rate(variants.size());
    std::vector<std::vector<float>> images(variants.size());
    size_t triangles = 0;
    for (int r = 0; r < reps; ++r) {
      for (size_t k = 0; k < variants.size(); ++k) {
        const size_t i = (k + static_cast<size_t>(r)) % variants.size();
        GeometryOptions options;
        options.build_quality = variants[i].quality;
        options.compact = variants[i].compact;
        options.robust = variants[i].robust;
        options.world_origin = camera_position(description);
        const auto start = std::chrono::steady_clock::now();
        const RenderScene render_scene(scene, options, colour);
        build[i].push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        triangles = render_scene.geometry().statistics().triangles;
        const Camera camera = render_scene.camera(description, settings.width, settings.height);
        Image image;
        const RenderResult result =
            render(*integrator, RenderContext{render_scene, camera, settings}, &image);
        trace[i].push_back(result.seconds);
        rate[i].push_back(double(result.rays.total()) / result.seconds * 1e-6);
        images[i] = std::move(image.rgba);
      }
    }
    std::printf("\n%s: %zu triangles, %dx%d, shadow %d spp, %d reps, load average %s -> %s\n\n",
                path.c_str(), triangles, settings.width, settings.height, spp, reps,
                load_before.c_str(), load_average().c_str());
    std::printf(
        "| quality | compact | robust | build s: median (range) | trace s: median (range) | "
        "Mrays/s (median) | BVH peak MiB | BVH kept MiB | image |\n");
    std::printf("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | --- |\n");
    for (size_t i = 0; i < variants.size(); ++i) {
      double peak = 0.0, kept = 0.0;
      bvh_memory(scene, variants[i], &peak, &kept);
      std::printf("| %s | %s | %s | %s | %s | %.2f | %.1f | %.1f | %s |\n",
                  to_string(variants[i].quality), variants[i].compact ? "on" : "off",
                  variants[i].robust ? "on" : "off", summary(build[i]).c_str(),
                  summary(trace[i]).c_str(), median(rate[i]), peak, kept,
                  image_difference(images[i], images[0]).c_str());
    }
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace prism

int main(int argc, char** argv) {
  return prism::run(argc, argv);
}
