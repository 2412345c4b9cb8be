// Prism's Ray as Embree's ray structures, for everything that calls rtcIntersect and
// rtcOccluded (renderer/geometry/embree_scene.cpp, and the benchmarks that trace the same rays).
#pragma once

#include <embree3/rtcore.h>

#include "renderer/geometry/ray.h"

namespace prism {

inline RTCRay to_rtc_ray(const Ray& ray) {
  RTCRay r{};
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.mask = 0xffffffffu;
  return r;
}

// With no hit recorded yet: Embree reads geomID and instID to know whether it found one.
inline RTCRayHit to_rtc_rayhit(const Ray& ray) {
  RTCRayHit rh{};
  rh.ray = to_rtc_ray(ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

// Lane `i` of an Embree ray packet (RTCRay4/8/16, or the .ray of an RTCRayHitN) set to
// `ray`; its id is the lane.
template <typename RayPacket>
void set_packet_lane(RayPacket* packet, int i, const Ray& ray) {
  packet->org_x[i] = ray.origin.x;
  packet->org_y[i] = ray.origin.y;
  packet->org_z[i] = ray.origin.z;
  packet->dir_x[i] = ray.direction.x;
  packet->dir_y[i] = ray.direction.y;
  packet->dir_z[i] = ray.direction.z;
  packet->tnear[i] = ray.tnear;
  packet->tfar[i] = ray.tfar;
  packet->time[i] = 0.0f;
  packet->mask[i] = 0xffffffffu;
  packet->id[i] = static_cast<unsigned>(i);
  packet->flags[i] = 0;
}

}  // namespace prism
