// The plain Embree side of the probes (bench/embree_probe_bench.cpp,
// bench/bounce_ray_probe_bench.cpp): Embree's own scene built straight from a
// SceneDescription, with no EmbreeScene code, and ray sets laid out for 1-, 8- and 16-wide
// tracing, so that what Prism does on top of Embree can be timed against Embree alone.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "renderer/geometry/embree_ray.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/math.h"
#include "renderer/scene_description.h"

namespace prism::probe {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline const char* yes_no(RTCDevice device, RTCDeviceProperty p) {
  return rtcGetDeviceProperty(device, p) ? "yes" : "no";
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

// The scene in the same two-level layout Prism uses (renderer/geometry/embree_scene.cpp: a mesh
// placed once is baked into world space, a mesh placed by several nodes becomes one BVH with an
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

// Runs body(first, last) over [0, count): on this thread alone for threads == 1, else
// split by TBB in an arena of that many threads, as renderer/render.cpp does.
inline void run_parallel(size_t count, int threads,
                         const std::function<void(size_t, size_t)>& body) {
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

// Raw Embree's rays per second on one ray set (intersect and occluded parts together, the
// set traced again until min_seconds have passed), and on its two parts, with how many hit or were
// blocked so the work cannot be skipped.
struct TraceRate {
  double per_second = 0.0, intersect_per_second = 0.0, occluded_per_second = 0.0;
  double seconds_per_repeat = 0.0;
  size_t hits = 0, blocked = 0;
};

template <int N>
TraceRate measure_rays(RaySet<N>* set, RTCScene scene, int threads, double min_seconds) {
  TraceRate rate;
  double intersect_time = 0.0, occluded_time = 0.0;
  size_t repeats = 0;
  do {  // at least once
    set->reset();
    auto start = Clock::now();
    rate.hits = set->trace_camera(scene, threads);
    intersect_time += seconds_since(start);
    start = Clock::now();
    rate.blocked = set->trace_shadow(scene, threads);
    occluded_time += seconds_since(start);
    ++repeats;
  } while (intersect_time + occluded_time < min_seconds);
  const double r = double(repeats);
  rate.intersect_per_second = r * double(set->camera_count()) / intersect_time;
  rate.occluded_per_second = r * double(set->shadow_count()) / occluded_time;
  rate.per_second =
      r * double(set->camera_count() + set->shadow_count()) / (intersect_time + occluded_time);
  rate.seconds_per_repeat = (intersect_time + occluded_time) / r;
  return rate;
}

}  // namespace prism::probe
