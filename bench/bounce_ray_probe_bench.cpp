// How close Prism's path tracer gets to Embree's own speed on the rays it actually traces.
// Path-traced bounce and next-event rays are incoherent, so the shadow-integrator probe's
// rays (camera through pixel centres, shadow rays to point lights) say little about them.
// This probe records Prism's own rays and traces them again with nothing of Prism around:
//
//   1. it runs itself again with bench/ray_recorder.cpp preloaded, and that child renders
//      SCENE with the `path` integrator once (1 thread; the rays do not depend on it), the
//      recorder writing down every ray handed to Embree;
//   2. it builds the plain Embree scene of bench/raw_embree.h from the same file (same
//      frame, same build quality) and traces the recorded rays as Prism did: the 16-wide
//      camera packets with rtcIntersect16, bounce rays with rtcIntersect1, next-event
//      shadow rays with rtcOccluded1;
//   3. it renders the same image with Prism's `path` in this process, interleaved with (2),
//      and sets Prism's rays per second (all its rays over its whole render() call:
//      sampling, BSDFs, lights, accumulation) against Embree's on the same rays.
//
//   build-bench/bench/bounce_ray_probe_bench [--res WxH] [--spp N] [--reps N]
//       [--min-seconds S] [--threads 1,2] [--recorder LIB] SCENE
//
// --recorder defaults to libprism_ray_recorder.so beside this executable.
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include "bench/raw_embree.h"

#include "bench/ray_log.h"
#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/image/colour.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"

namespace prism {
namespace {

struct Options {
  int width = 320, height = 240;
  int spp = 4;
  int reps = 5;
  double min_seconds = 0.5;
  std::vector<int> threads{1, 2};
  std::string recorder;
  std::string record_to;  // set in the recording child only
  std::string scene;
};

Options parse(int argc, char** argv) {
  Options o;
  CLI::App app{"Prism's path tracer against raw Embree on the rays it traces",
               "bounce_ray_probe_bench"};
  std::string resolution = "320x240";
  app.add_option("--res", resolution, "resolution, WxH")->capture_default_str();
  app.add_option("--spp", o.spp, "samples per pixel")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--reps", o.reps, "interleaved rounds, probe::median")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--min-seconds", o.min_seconds, "least time per measurement")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--threads", o.threads, "thread counts to measure")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  app.add_option("--recorder", o.recorder, "the ray recorder library to preload");
  app.add_option("--record-to", o.record_to)->group("");  // the recording child's
  app.add_option("scene", o.scene, "glTF scene")->required();
  try {
    app.parse(argc, argv);
    if (std::sscanf(resolution.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 ||
        o.height < 1)
      throw CLI::ValidationError("--res", "expects WxH");
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  return o;
}

// The scene as `prism render` sees it, in the frame rebased on the camera.
struct Setup {
  SceneDescription scene;
  V3d origin;
  std::unique_ptr<RenderScene> prism;
  std::unique_ptr<Camera> camera;
  RenderSettings settings;

  explicit Setup(const Options& o) {
    scene = load_gltf(o.scene);
    add_scene_defaults(&scene);
    origin = camera_position(scene.cameras.front());
    GeometryOptions g;
    g.world_origin = origin;
    prism = std::make_unique<RenderScene>(scene, g, ColourPipeline(WorkingSpace::linear_rec709));
    camera = std::make_unique<Camera>(prism->camera(scene.cameras.front(), o.width, o.height));
    settings.width = o.width;
    settings.height = o.height;
    settings.spp = o.spp;
  }

  // One whole `path` render in an arena of `threads`.
  RenderResult render_path(int threads) const {
    tbb::task_arena arena(threads);
    const RenderContext context{*prism, *camera, settings};
    const std::unique_ptr<Integrator> integrator = make_integrator("path");
    Image image;
    RenderResult r;
    arena.execute([&] { r = render(*integrator, context, &image); });
    return r;
  }
};

// Step 1: this program again, with the recorder preloaded and --record-to.
std::vector<probe::RecordedRay> record_rays(const Options& o, char** argv) {
  std::string recorder = o.recorder;
  if (recorder.empty())
    recorder =
        (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "libprism_ray_recorder.so")
            .string();
  if (!std::filesystem::exists(recorder))
    throw std::runtime_error("no ray recorder at " + recorder + " (build it, or --recorder)");
  char log_template[] = "/tmp/prism-rays-XXXXXX";
  const int fd = mkstemp(log_template);
  if (fd < 0) throw std::runtime_error("cannot make a temporary ray log");
  close(fd);
  const std::string log = log_template;
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("fork failed");
  if (child == 0) {
    setenv("LD_PRELOAD", recorder.c_str(), 1);
    setenv("PRISM_RAY_LOG", log.c_str(), 1);
    const std::string res = std::to_string(o.width) + "x" + std::to_string(o.height);
    const std::string spp = std::to_string(o.spp);
    execl("/proc/self/exe", argv[0], "--res", res.c_str(), "--spp", spp.c_str(), "--record-to",
          log.c_str(), o.scene.c_str(), static_cast<char*>(nullptr));
    std::perror("exec");
    _exit(127);
  }
  int status = 0;
  waitpid(child, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("the recording run failed");
  std::vector<probe::RecordedRay> rays = probe::read_ray_log(log);
  std::filesystem::remove(log);
  return rays;
}

Ray to_ray(const probe::RecordedRay& r) {
  Ray ray;
  ray.origin = V3f(r.origin[0], r.origin[1], r.origin[2]);
  ray.direction = V3f(r.direction[0], r.direction[1], r.direction[2]);
  ray.tnear = r.tnear;
  ray.tfar = r.tfar;
  return ray;
}

// The 1-wide rays again, through Prism's own trace layer: EmbreeScene::intersect (Embree's
// rtcIntersect1 and the hit Prism makes of it: position, normals, texture coordinates, error
// bound, and the retrace past a culled back face) and EmbreeScene::occluded, split over
// threads as the raw replay is. Against the raw replay it is what Prism's wrapping of the two
// calls costs, apart from everything else a path vertex does.
struct LayerRate {
  double intersect_per_second = 0.0, occluded_per_second = 0.0, per_second = 0.0;
  size_t hits = 0, blocked = 0;
};
LayerRate measure_trace_layer(const EmbreeScene& geometry, const std::vector<Ray>& bounce,
                              const std::vector<Ray>& shadow, int threads, double min_seconds) {
  LayerRate rate;
  double intersect_time = 0.0, occluded_time = 0.0;
  size_t repeats = 0;
  do {  // at least once
    std::atomic<size_t> hits{0}, blocked{0};
    auto start = probe::Clock::now();
    probe::run_parallel(bounce.size(), threads, [&](size_t first, size_t last) {
      size_t n = 0;
      SurfaceHit hit;
      for (size_t i = first; i < last; ++i) n += geometry.intersect(bounce[i], &hit) ? 1 : 0;
      hits += n;
    });
    intersect_time += probe::seconds_since(start);
    start = probe::Clock::now();
    probe::run_parallel(shadow.size(), threads, [&](size_t first, size_t last) {
      size_t n = 0;
      for (size_t i = first; i < last; ++i) n += geometry.occluded(shadow[i]) ? 1 : 0;
      blocked += n;
    });
    occluded_time += probe::seconds_since(start);
    rate.hits = hits;
    rate.blocked = blocked;
    ++repeats;
  } while (intersect_time + occluded_time < min_seconds);
  const double r = double(repeats);
  rate.intersect_per_second = r * double(bounce.size()) / intersect_time;
  rate.occluded_per_second = r * double(shadow.size()) / occluded_time;
  rate.per_second = r * double(bounce.size() + shadow.size()) / (intersect_time + occluded_time);
  return rate;
}

int run(const Options& o, char** argv) {
  const Setup setup(o);
  if (!o.record_to.empty()) {
    const RenderResult r = setup.render_path(1);
    std::fprintf(stderr, "recording run: %llu rays counted by Prism\n",
                 (unsigned long long)r.rays.total());
    return 0;  // the recorder writes the log as this process exits
  }
  const std::vector<probe::RecordedRay> recorded = record_rays(o, argv);
  std::vector<Ray> by_call[probe::kTraceCallCount];
  for (const probe::RecordedRay& r : recorded)
    by_call[static_cast<int>(r.call)].push_back(to_ray(r));
  const auto& intersect1 = by_call[int(probe::TraceCall::intersect1)];
  const auto& occluded1 = by_call[int(probe::TraceCall::occluded1)];
  const auto& intersect16 = by_call[int(probe::TraceCall::intersect16)];
  const auto& occluded16 = by_call[int(probe::TraceCall::occluded16)];
  // As Prism traced them: packets as packets, single rays one at a time.
  probe::RaySet<16> coherent(intersect16, occluded16);
  probe::RaySet<1> incoherent(intersect1, occluded1);
  const probe::RawScene raw(setup.scene, setup.origin, false);

  const RenderResult counted = setup.render_path(1);
  std::printf(
      "%s: %dx%d, %d spp, path; %zu triangles (%zu instances), %zu spheres\n"
      "  recorded: %zu rtcIntersect16 lanes, %zu rtcOccluded16 lanes, %zu rtcIntersect1, "
      "%zu rtcOccluded1 (%zu in all); Prism counts %llu camera, %llu bounce, %llu shadow "
      "(%llu in all)\n",
      o.scene.c_str(), o.width, o.height, o.spp, raw.triangles(), raw.instances(),
      setup.scene.spheres.size(), intersect16.size(), occluded16.size(), intersect1.size(),
      occluded1.size(), recorded.size(), (unsigned long long)counted.rays[RayKind::camera],
      (unsigned long long)counted.rays[RayKind::bounce],
      (unsigned long long)counted.rays[RayKind::shadow], (unsigned long long)counted.rays.total());
  std::printf(
      "| threads | Embree 1-wide bounce Mrays/s | 1-wide shadow | all rays as Prism traced "
      "them | Prism path Mrays/s | Prism / Embree, all rays | Prism / Embree 1-wide rays | "
      "Prism render s | Embree s | Prism trace layer 1-wide Mrays/s | trace layer / Embree "
      "1-wide |\n"
      "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  const double all_rays = double(recorded.size());
  for (int threads : o.threads) {
    std::vector<double> bounce, shadow, single, all, prism_rate, prism_s, embree_s, layer;
    for (int rep = 0; rep < o.reps; ++rep) {
      const probe::TraceRate c =
          probe::measure_rays(&coherent, raw.scene(), threads, o.min_seconds);
      const probe::TraceRate s =
          probe::measure_rays(&incoherent, raw.scene(), threads, o.min_seconds);
      layer.push_back(measure_trace_layer(setup.prism->geometry(), intersect1, occluded1, threads,
                                          o.min_seconds)
                          .per_second);
      bounce.push_back(s.intersect_per_second);
      shadow.push_back(s.occluded_per_second);
      single.push_back(s.per_second);
      const double embree_seconds = c.seconds_per_repeat + s.seconds_per_repeat;
      all.push_back(all_rays / embree_seconds);
      embree_s.push_back(embree_seconds);
      double seconds = 0.0, rays = 0.0;
      do {  // at least once
        const RenderResult r = setup.render_path(threads);
        seconds += r.seconds;
        rays += double(r.rays.total());
        prism_s.push_back(r.seconds);
      } while (seconds < o.min_seconds);
      prism_rate.push_back(rays / seconds);
    }
    const double p = probe::median(prism_rate);
    std::printf("| %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.4f | %.4f | %.3f | %.3f |\n",
                threads, probe::median(bounce) / 1e6, probe::median(shadow) / 1e6,
                probe::median(all) / 1e6, p / 1e6, p / probe::median(all),
                p / probe::median(single), probe::median(prism_s), probe::median(embree_s),
                probe::median(layer) / 1e6, probe::median(layer) / probe::median(single));
  }
  return 0;
}

}  // namespace
}  // namespace prism

int main(int argc, char** argv) {
  const prism::Options o = prism::parse(argc, argv);
  try {
    return prism::run(o, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bounce_ray_probe_bench: %s\n", e.what());
    return 1;
  }
}
