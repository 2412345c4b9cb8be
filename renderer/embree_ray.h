// Prism's Ray as Embree's single-ray structures, for everything that calls rtcIntersect1 and
// rtcOccluded1 (renderer/embree_scene.cpp, and the benchmarks that trace the same rays).
#pragma once

#include <embree3/rtcore.h>

#include "renderer/ray.h"

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

}  // namespace prism
