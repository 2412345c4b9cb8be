#include "renderer/geometry/sphere_geometry.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "renderer/geometry/sphere_intersect.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {

bool parse_sphere_options(const std::string& text, SphereOptions* options, std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  SphereOptions parsed;
  if (text == "analytic") {
    parsed.mode = SphereMode::analytic;
  } else if (text == "embree-points") {
    parsed.mode = SphereMode::embree_points;
  } else if (text == "mesh") {
    parsed.mode = SphereMode::mesh;
  } else if (text.rfind("mesh:", 0) == 0) {
    parsed.mode = SphereMode::mesh;
    const char* first = text.data() + 5;
    const char* last = text.data() + text.size();
    // from_chars, unlike stoi, takes no sign, space or trailing junk, so "mesh: 3" and
    // "mesh:3x" are errors rather than silently level 3.
    const auto [end, ec] = std::from_chars(first, last, parsed.mesh_level);
    if (first == last || ec == std::errc::invalid_argument || end != last) {
      return fail("sphere mode '" + text + "': the mesh level after 'mesh:' must be a number");
    }
    if (ec == std::errc::result_out_of_range || parsed.mesh_level < 0 ||
        parsed.mesh_level > kMaxSphereMeshLevel) {
      return fail("sphere mode '" + text + "': the mesh level must be 0 to " +
                  std::to_string(kMaxSphereMeshLevel));
    }
  } else {
    return fail("unknown sphere mode '" + text +
                "' (expected analytic, mesh, mesh:N or embree-points)");
  }
  *options = parsed;
  return true;
}

std::string to_string(const SphereOptions& options) {
  switch (options.mode) {
    case SphereMode::analytic:
      return "analytic";
    case SphereMode::mesh:
      return "mesh:" + std::to_string(options.mesh_level);
    case SphereMode::embree_points:
      return "embree-points";
  }
  return "unknown";
}

namespace {

struct FloatSphere {
  Imath::V3f centre;
  float radius;
};

// The user data of an analytic-sphere geometry; see attach_analytic_spheres for who frees it.
struct AnalyticSpheres {
  std::vector<FloatSphere> spheres;
};

FloatSphere to_float(const Sphere& s) {
  return {Imath::V3f(float(s.centre.x), float(s.centre.y), float(s.centre.z)), float(s.radius)};
}

void analytic_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* data = static_cast<const AnalyticSpheres*>(args->geometryUserPtr);
  const FloatSphere& s = data->spheres[args->primID];
  // intersect_sphere accepts near-tangent rays whose computed closest approach is a few ulps
  // inside r while the exact one is a few ulps outside; those rays must still reach the
  // callback, so the box is widened by 2^-18 of the sphere's largest coordinate
  // (about 30 ulps), far more than the test's rounding and far too little to cost time.
  const float extent =
      std::max({std::abs(s.centre.x), std::abs(s.centre.y), std::abs(s.centre.z)}) + s.radius;
  const float r = s.radius + extent * 0x1p-18f;
  RTCBounds* b = args->bounds_o;
  b->lower_x = s.centre.x - r;
  b->lower_y = s.centre.y - r;
  b->lower_z = s.centre.z - r;
  b->upper_x = s.centre.x + r;
  b->upper_y = s.centre.y + r;
  b->upper_z = s.centre.z + r;
}

constexpr unsigned kMaxPacket = 16;  // rtcIntersect16 is the widest packet

Imath::V3f ray_origin(RTCRayN* rays, unsigned n, unsigned i) {
  return {RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)};
}

Imath::V3f ray_direction(RTCRayN* rays, unsigned n, unsigned i) {
  return {RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i)};
}

void write_hit(RTCHitN* hits, unsigned n, unsigned i, const SphereRoot& root, unsigned prim_id,
               unsigned geom_id, const RTCIntersectContext& context) {
  RTCHitN_Ng_x(hits, n, i) = root.offset.x;
  RTCHitN_Ng_y(hits, n, i) = root.offset.y;
  RTCHitN_Ng_z(hits, n, i) = root.offset.z;
  RTCHitN_u(hits, n, i) = 0.0f;
  RTCHitN_v(hits, n, i) = 0.0f;
  RTCHitN_primID(hits, n, i) = prim_id;
  RTCHitN_geomID(hits, n, i) = geom_id;
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) {
    RTCHitN_instID(hits, n, i, l) = context.instID[l];
  }
}

// A hit record as wide as the packet, for the filter functions, which index it by lane.
struct CandidateHit {
  alignas(64) unsigned words[(7 + RTC_MAX_INSTANCE_LEVEL_COUNT) * kMaxPacket];
  RTCHitN* get() { return reinterpret_cast<RTCHitN*>(words); }
};

// Embree 3 leaves it to user geometry to write the hit and to run the filter functions (the
// geometry's and the context's), which see the candidate distance in tfar and reject it by
// zeroing their valid flag. Only lane i is offered, so the other lanes' flags stay 0.
// `run_filter(filter_args)` calls the intersection or occlusion filters; `accept(i, root)`
// records a root they kept, with tfar already set to it.
template <typename Args, typename RunFilter, typename Accept>
void for_each_filtered_root(const Args* args, RTCRayN* rays, RunFilter&& run_filter,
                            Accept&& accept) {
  const auto* data = static_cast<const AnalyticSpheres*>(args->geometryUserPtr);
  const FloatSphere& s = data->spheres[args->primID];
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] == 0) continue;
    float& tfar = RTCRayN_tfar(rays, n, i);
    const auto root = intersect_sphere(ray_origin(rays, n, i), ray_direction(rays, n, i), s.centre,
                                       s.radius, RTCRayN_tnear(rays, n, i), tfar);
    if (!root) continue;
    CandidateHit candidate;
    write_hit(candidate.get(), n, i, *root, args->primID, args->geomID, *args->context);
    int valid[kMaxPacket] = {};
    valid[i] = -1;
    const RTCFilterFunctionNArguments filter{valid, args->geometryUserPtr, args->context,
                                             rays,  candidate.get(),       n};
    const float old_tfar = tfar;
    tfar = root->t;
    run_filter(&filter);
    if (valid[i] == 0) {
      tfar = old_tfar;
      continue;
    }
    accept(i, *root);
  }
}

void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  for_each_filtered_root(
      args, rays, [&](const RTCFilterFunctionNArguments* f) { rtcFilterIntersection(args, f); },
      [&](unsigned i, const SphereRoot& root) {
        write_hit(hits, args->N, i, root, args->primID, args->geomID, *args->context);
      });
}

void analytic_occluded(const RTCOccludedFunctionNArguments* args) {
  for_each_filtered_root(
      args, args->ray, [&](const RTCFilterFunctionNArguments* f) { rtcFilterOcclusion(args, f); },
      [&](unsigned i, const SphereRoot&) {
        // Embree 3's mark of an occluded ray.
        RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
      });
}

}  // namespace

unsigned attach_analytic_spheres(RTCDevice device, RTCScene scene,
                                 const std::vector<Sphere>& spheres) {
  auto* data = new AnalyticSpheres;
  data->spheres.reserve(spheres.size());
  for (const Sphere& s : spheres) data->spheres.push_back(to_float(s));

  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  if (!geometry) {
    delete data;
    throw std::runtime_error("Embree could not create a user geometry for the spheres");
  }
  rtcSetGeometryUserPrimitiveCount(geometry, unsigned(spheres.size()));
  rtcSetGeometryUserData(geometry, data);
  rtcSetGeometryBoundsFunction(geometry, analytic_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geometry, analytic_intersect);
  rtcSetGeometryOccludedFunction(geometry, analytic_occluded);
  rtcCommitGeometry(geometry);
  const unsigned geom_id = rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);  // the scene holds its own reference
  return geom_id;
}

void release_analytic_spheres(RTCScene scene, unsigned geom_id) {
  RTCGeometry geometry = rtcGetGeometry(scene, geom_id);
  if (!geometry) return;
  delete static_cast<AnalyticSpheres*>(rtcGetGeometryUserData(geometry));
  rtcSetGeometryUserData(geometry, nullptr);
}

unsigned attach_point_spheres(RTCDevice device, RTCScene scene,
                              const std::vector<Sphere>& spheres) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  if (!geometry) throw std::runtime_error("Embree could not create a sphere-point geometry");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
  if (!vertices && !spheres.empty()) {
    rtcReleaseGeometry(geometry);
    throw std::runtime_error("Embree could not allocate the sphere-point vertex buffer");
  }
  for (size_t i = 0; i < spheres.size(); ++i) {
    const FloatSphere s = to_float(spheres[i]);
    vertices[4 * i + 0] = s.centre.x;
    vertices[4 * i + 1] = s.centre.y;
    vertices[4 * i + 2] = s.centre.z;
    vertices[4 * i + 3] = s.radius;
  }
  rtcCommitGeometry(geometry);
  const unsigned geom_id = rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  return geom_id;
}

}  // namespace prism
