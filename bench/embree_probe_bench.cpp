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

#include "integrators/registry.h"
#include "renderer/camera.h"
#include "renderer/image/colour.h"
#include "renderer/geometry/embree_ray.h"
#include "renderer/shading/lights.h"
#include "renderer/math.h"
#include "renderer/render.h"
#include "renderer/render_scene.h"
#include "scene_passes/scene_defaults.h"
#include "scene_io/gltf_loader.h"

namespace prism {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------
// The plain Embree scene.

struct BakedMesh {
  std::vector<V3f> positions;  // world (shifted by the world origin), or object if instanced
  std::vector<V3f> normals;    // unit; empty = flat
  std::vector<uint32_t> indices;
};

// A mesh placed by several nodes: one BVH in object space, shared by its instances.
struct Prototype {
  RTCScene scene = nullptr;
  std::vector<BakedMesh> meshes;  // by geomID within scene
};

struct PlacedInstance {
  const Prototype* prototype = nullptr;
  Imath::M44f object_to_world;  // into the shifted frame
  Imath::M44f normal_to_world;
};

// The scene in the same two-level layout Prism uses (renderer/geometry/embree_scene.cpp: a mesh placed
// once is baked into world space, a mesh placed by several nodes becomes one BVH with an
// instance per node), or with `flat` every placement baked; spheres as Embree's points.
class RawScene {
 public:
  RawScene(const SceneDescription& scene, const V3d& origin, bool flat) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("rtcNewDevice failed");
    scene_ = rtcNewScene(device_);
    // Prism's default build quality (GeometryOptions), so both trace the same kind of tree.
    rtcSetSceneBuildQuality(scene_, embree_build_quality(GeometryOptions{}.build_quality));
    std::vector<int> uses(scene.meshes.size(), 0);
    for (const MeshInstance& instance : scene.instances) ++uses[size_t(instance.mesh)];
    std::vector<Prototype*> prototype_of(scene.meshes.size(), nullptr);
    M44d shift;
    shift.setTranslation(-origin);
    for (const MeshInstance& instance : scene.instances) {
      const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
      const M44d to_world = instance.object_to_world * shift;
      const M44d normal_matrix = instance.object_to_world.inverse().transposed();
      if (flat || uses[size_t(instance.mesh)] == 1) {
        for (const Primitive& p : mesh.primitives) {
          BakedMesh baked = copy(p, to_world, normal_matrix);
          const unsigned id = attach(scene_, &baked);
          if (id == RTC_INVALID_GEOMETRY_ID) continue;
          if (records_.size() <= id) records_.resize(id + 1);
          records_[id] = {meshes_.size(), false};
          meshes_.push_back(std::move(baked));
        }
        continue;
      }
      Prototype*& proto = prototype_of[size_t(instance.mesh)];
      if (!proto) {
        prototypes_.push_back(std::make_unique<Prototype>());
        proto = prototypes_.back().get();
        proto->scene = rtcNewScene(device_);
        rtcSetSceneBuildQuality(proto->scene,
                                embree_build_quality(GeometryOptions{}.build_quality));
        for (const Primitive& p : mesh.primitives) {
          BakedMesh baked = copy(p, M44d(), M44d());
          const unsigned id = attach(proto->scene, &baked);
          if (id == RTC_INVALID_GEOMETRY_ID) continue;
          if (proto->meshes.size() <= id) proto->meshes.resize(id + 1);
          proto->meshes[id] = std::move(baked);
        }
        rtcCommitScene(proto->scene);
      }
      PlacedInstance placed;
      placed.prototype = proto;
      placed.object_to_world = Imath::M44f(to_world);
      placed.normal_to_world = Imath::M44f(normal_matrix);
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, proto->scene);
      // Imath's row-vector matrix laid out row by row is Embree's column-major one.
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                              &placed.object_to_world[0][0]);
      rtcCommitGeometry(g);
      const unsigned id = rtcAttachGeometry(scene_, g);
      rtcReleaseGeometry(g);
      for (const Primitive& p : mesh.primitives) triangles_ += p.indices.size() / 3;
      ++instance_count_;
      if (records_.size() <= id) records_.resize(id + 1);
      records_[id] = {instances_.size(), true};
      instances_.push_back(placed);
    }
    if (!scene.spheres.empty()) {
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* points = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                  4 * sizeof(float), scene.spheres.size()));
      for (size_t i = 0; i < scene.spheres.size(); ++i) {
        const V3f c(scene.spheres[i].centre - origin);
        points[4 * i + 0] = c.x;
        points[4 * i + 1] = c.y;
        points[4 * i + 2] = c.z;
        points[4 * i + 3] = float(scene.spheres[i].radius);
        spheres_.push_back(Imath::V4f(c.x, c.y, c.z, points[4 * i + 3]));
      }
      rtcCommitGeometry(g);
      sphere_geom_ = rtcAttachGeometry(scene_, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
      throw std::runtime_error("Embree failed to build the probe scene");
  }
  ~RawScene() {
    rtcReleaseScene(scene_);
    for (const auto& p : prototypes_) rtcReleaseScene(p->scene);
    rtcReleaseDevice(device_);
  }
  RawScene(const RawScene&) = delete;
  RawScene& operator=(const RawScene&) = delete;

  RTCScene scene() const { return scene_; }
  size_t triangles() const { return triangles_; }
  size_t instances() const { return instance_count_; }

  // The hit point and the unit shading normal (flat when the mesh has none) of a hit, in
  // the shifted world frame.
  void surface(const RTCRayHit& rh, V3f* position, V3f* normal) const {
    if (rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID && rh.hit.geomID == sphere_geom_) {
      const Imath::V4f& s = spheres_[rh.hit.primID];
      const V3f n = normalize(V3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
      *position = V3f(s.x, s.y, s.z) + s.w * n;
      *normal = n;
      return;
    }
    const PlacedInstance* placed = nullptr;
    const BakedMesh* m = nullptr;
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
      placed = &instances_[records_[rh.hit.instID[0]].index];
      m = &placed->prototype->meshes[rh.hit.geomID];
    } else {
      m = &meshes_[records_[rh.hit.geomID].index];
    }
    const uint32_t* t = &m->indices[3 * size_t(rh.hit.primID)];
    const float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
    V3f p = w * m->positions[t[0]] + u * m->positions[t[1]] + v * m->positions[t[2]];
    V3f n = m->normals.empty() ? V3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)
                               : w * m->normals[t[0]] + u * m->normals[t[1]] + v * m->normals[t[2]];
    if (placed) {
      // Embree reports an instanced hit's Ng in object space, as the interpolated normal is.
      V3f q;
      placed->object_to_world.multVecMatrix(p, q);
      p = q;
      placed->normal_to_world.multDirMatrix(n, q);
      n = q;
    }
    *position = p;
    *normal = normalize(n);
  }

 private:
  struct Record {
    size_t index = 0;  // into meshes_ or instances_
    bool instance = false;
  };

  static BakedMesh copy(const Primitive& p, const M44d& to_world, const M44d& normal_matrix) {
    BakedMesh baked;
    baked.positions.reserve(p.positions.size());
    for (const V3f& v : p.positions) {
      V3d w;
      to_world.multVecMatrix(V3d(v), w);
      baked.positions.push_back(V3f(w));
    }
    if (p.normals.size() == p.positions.size()) {
      for (const V3f& n : p.normals) {
        V3d w;
        normal_matrix.multDirMatrix(V3d(n), w);
        baked.normals.push_back(V3f(w.normalized()));
      }
    }
    baked.indices = p.indices;
    return baked;
  }

  unsigned attach(RTCScene scene, BakedMesh* baked) {
    if (baked->indices.empty()) return RTC_INVALID_GEOMETRY_ID;
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // One float of padding: Embree reads 16 bytes per float3 vertex.
    auto* p = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          baked->positions.size() + 1));
    std::memcpy(p, baked->positions.data(), baked->positions.size() * sizeof(V3f));
    auto* i = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                             RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                                             baked->indices.size() / 3));
    std::memcpy(i, baked->indices.data(), baked->indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    if (scene == scene_) triangles_ += baked->indices.size() / 3;
    return id;
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<std::unique_ptr<Prototype>> prototypes_;
  std::vector<BakedMesh> meshes_;
  std::vector<PlacedInstance> instances_;
  std::vector<Record> records_;  // by top-level geomID
  std::vector<Imath::V4f> spheres_;
  unsigned sphere_geom_ = RTC_INVALID_GEOMETRY_ID;
  size_t triangles_ = 0, instance_count_ = 0;
};

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

// Runs body(first, last) over [0, count): on this thread alone for threads == 1, else
// split by TBB in an arena of that many threads, as renderer/render.cpp does.
void run_parallel(size_t count, int threads, const std::function<void(size_t, size_t)>& body) {
  if (threads == 1) {
    body(0, count);
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 64),
                      [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
  });
}

// The camera and shadow rays laid out for one packet width, ready to be traced in place.
// Width 1 uses RTCRayHit/RTCRay; 8 and 16 the SoA packet types. Tracing overwrites tfar and
// the hit, so reset() copies the pristine rays back (outside the timed region).
template <int N>
struct PacketTypes;
template <>
struct PacketTypes<1> {
  using Hit = RTCRayHit;
  using Occ = RTCRay;
};
template <>
struct PacketTypes<8> {
  using Hit = RTCRayHit8;
  using Occ = RTCRay8;
};
template <>
struct PacketTypes<16> {
  using Hit = RTCRayHit16;
  using Occ = RTCRay16;
};

template <int N>
class RaySet {
 public:
  using Hit = typename PacketTypes<N>::Hit;
  using Occ = typename PacketTypes<N>::Occ;
  // Embree reads the valid mask with aligned vector loads: 32 bytes for 8-wide, 64 for 16.
  struct alignas(64) Valid {
    int lane[N];
  };

  RaySet(const std::vector<Ray>& camera, const std::vector<Ray>& shadow)
      : camera_count_(camera.size()), shadow_count_(shadow.size()) {
    pack(camera, &camera_pristine_, &camera_valid_);
    pack(shadow, &shadow_pristine_, &shadow_valid_);
    camera_ = camera_pristine_;
    shadow_ = shadow_pristine_;
  }

  void reset() {
    camera_ = camera_pristine_;
    shadow_ = shadow_pristine_;
  }

  // Each returns how many camera rays hit / shadow rays were blocked, so the widths can be
  // checked against each other and the work cannot be optimised away.
  size_t trace_camera(RTCScene scene, int threads) {
    return run_counting(camera_.size(), threads,
                        [&](RTCIntersectContext* c, size_t i) { return intersect(scene, c, i); });
  }
  size_t trace_shadow(RTCScene scene, int threads) {
    return run_counting(shadow_.size(), threads,
                        [&](RTCIntersectContext* c, size_t i) { return occluded(scene, c, i); });
  }

  size_t camera_count() const { return camera_count_; }
  size_t shadow_count() const { return shadow_count_; }

 private:
  template <typename Packet>
  static void pack(const std::vector<Ray>& rays, std::vector<Packet>* packets,
                   std::vector<Valid>* valid) {
    const size_t count = (rays.size() + N - 1) / N;
    packets->assign(count, Packet{});
    valid->assign(count, Valid{});
    for (size_t i = 0; i < rays.size(); ++i) set(&(*packets)[i / N], i % N, rays[i]);
    for (size_t i = 0; i < rays.size(); ++i) (*valid)[i / N].lane[i % N] = -1;
  }

  // Ray lane k of a packet (or the single ray for N = 1).
  template <typename Packet>
  static void set(Packet* p, size_t k, const Ray& ray) {
    if constexpr (N == 1) {
      if constexpr (std::is_same_v<Packet, RTCRayHit>) {
        *p = to_rtc_rayhit(ray);
      } else {
        *p = to_rtc_ray(ray);
      }
    } else {
      auto& r = [&]() -> auto& {
        if constexpr (std::is_same_v<Packet, Hit>) {
          return p->ray;
        } else {
          return *p;
        }
      }
      ();
      set_packet_lane(&r, static_cast<int>(k), ray);
      if constexpr (std::is_same_v<Packet, Hit>) {
        p->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        p->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
    }
  }

  size_t intersect(RTCScene scene, RTCIntersectContext* context, size_t i) {
    Hit& h = camera_[i];
    size_t n = 0;
    if constexpr (N == 1) {
      rtcIntersect1(scene, context, &h);
      n = h.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    } else {
      if constexpr (N == 8) {
        rtcIntersect8(camera_valid_[i].lane, scene, context, &h);
      } else {
        rtcIntersect16(camera_valid_[i].lane, scene, context, &h);
      }
      for (int k = 0; k < N; ++k)
        n += camera_valid_[i].lane[k] != 0 && h.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
    }
    return n;
  }

  size_t occluded(RTCScene scene, RTCIntersectContext* context, size_t i) {
    Occ& r = shadow_[i];
    size_t n = 0;
    if constexpr (N == 1) {
      rtcOccluded1(scene, context, &r);
      n = r.tfar < 0.0f;
    } else {
      if constexpr (N == 8) {
        rtcOccluded8(shadow_valid_[i].lane, scene, context, &r);
      } else {
        rtcOccluded16(shadow_valid_[i].lane, scene, context, &r);
      }
      for (int k = 0; k < N; ++k) n += shadow_valid_[i].lane[k] != 0 && r.tfar[k] < 0.0f;
    }
    return n;
  }

  template <typename Fn>
  static size_t run_counting(size_t count, int threads, Fn&& fn) {
    std::atomic<size_t> total{0};
    run_parallel(count, threads, [&](size_t first, size_t last) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      size_t n = 0;
      for (size_t i = first; i < last; ++i) n += fn(&context, i);
      total += n;
    });
    return total;
  }

  size_t camera_count_, shadow_count_;
  std::vector<Hit> camera_pristine_, camera_;
  std::vector<Occ> shadow_pristine_, shadow_;
  std::vector<Valid> camera_valid_, shadow_valid_;
};

// ---------------------------------------------------------------------------------------
// Measuring.

struct Rate {
  double rays_per_second = 0.0;
  double camera_per_second = 0.0;  // camera rays alone (the probe's intersect phase)
  size_t hits = 0, blocked = 0;
};

// Traces the camera rays, then the shadow rays, repeating both until min_seconds have
// passed in total; each phase is timed on its own so the camera rays alone can be set
// against the phong integrator, which casts no shadow rays.
template <int N>
Rate measure_probe(RaySet<N>* set, RTCScene scene, int threads, double min_seconds) {
  Rate rate;
  double camera_time = 0.0, shadow_time = 0.0;
  size_t repeats = 0;
  while (camera_time + shadow_time < min_seconds) {
    set->reset();
    auto start = Clock::now();
    rate.hits = set->trace_camera(scene, threads);
    camera_time += seconds_since(start);
    start = Clock::now();
    rate.blocked = set->trace_shadow(scene, threads);
    shadow_time += seconds_since(start);
    ++repeats;
  }
  const double r = double(repeats);
  rate.camera_per_second = r * double(set->camera_count()) / camera_time;
  rate.rays_per_second =
      r * double(set->camera_count() + set->shadow_count()) / (camera_time + shadow_time);
  return rate;
}

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

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
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

const char* yes_no(RTCDevice device, RTCDeviceProperty p) {
  return rtcGetDeviceProperty(device, p) ? "yes" : "no";
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
      const Rate r1 = measure_probe(&set1, raw.scene(), threads, o.min_seconds);
      const Rate r8 = measure_probe(&set8, raw.scene(), threads, o.min_seconds);
      const Rate r16 = measure_probe(&set16, raw.scene(), threads, o.min_seconds);
      p1.push_back(r1.rays_per_second);
      p8.push_back(r8.rays_per_second);
      p16.push_back(r16.rays_per_second);
      c1.push_back(r1.camera_per_second);
      c8.push_back(r8.camera_per_second);
      c16.push_back(r16.camera_per_second);
      blocked1 = r1.blocked;
      blocked8 = r8.blocked;
      blocked16 = r16.blocked;
      hits8 = r8.hits;
      hits16 = r16.hits;
      if (r1.hits != hits) std::fprintf(stderr, "probe: 1-wide hits differ from setup\n");
      for (size_t v = 0; v < variants.size(); ++v) {
        last_shadow[v] = measure_prism(*prism_scenes[v], camera, width, height,
                                       "shadow", threads, o.min_seconds);
        last_phong[v] = measure_prism(*prism_scenes[v], camera, width, height,
                                      "phong", threads, o.min_seconds);
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
        RTC_VERSION_STRING, prism::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED),
        prism::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
        prism::yes_no(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED),
        prism::yes_no(device, RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED), o.reps, o.min_seconds);
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
