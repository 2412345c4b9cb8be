// A shared library to preload into any process that traces with Embree (`prism render`, the
// bounce-ray probe's recording child): it stands in front of Embree's rtcIntersect1,
// rtcOccluded1, rtcIntersect16 and rtcOccluded16, writes down every ray handed to them, and
// passes the call on unchanged. At exit the rays go to the file named by PRISM_RAY_LOG, so
// bench/bounce_ray_probe_bench.cpp can trace exactly the rays Prism traced, with nothing of
// Prism around them.
//
//   LD_PRELOAD=build/bench/libprism_ray_recorder.so PRISM_RAY_LOG=/tmp/rays.bin prism render ...
//
// File: the 8 bytes "PRAYLOG1", a uint64 count, then `count` RecordedRay (bench/ray_log.h).
// Without PRISM_RAY_LOG the calls are passed on and nothing is kept.
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include <embree3/rtcore.h>

#include "bench/ray_log.h"

namespace {

using prism::probe::RecordedRay;
using prism::probe::TraceCall;

// Each thread appends to its own buffer; the buffers live until exit (never freed with their
// thread: TBB's workers may end before the log is written).
struct Log {
  std::mutex mutex;
  std::vector<std::vector<RecordedRay>*> buffers;
  const char* path = std::getenv("PRISM_RAY_LOG");

  ~Log() {
    if (!path) return;
    uint64_t count = 0;
    for (const auto* b : buffers) count += b->size();
    FILE* f = std::fopen(path, "wb");
    if (!f) {
      std::fprintf(stderr, "ray_recorder: cannot write %s\n", path);
      return;
    }
    bool ok = std::fwrite(prism::probe::kRayLogMagic, 1, 8, f) == 8 &&
              std::fwrite(&count, sizeof count, 1, f) == 1;
    for (const auto* b : buffers)
      ok = ok && std::fwrite(b->data(), sizeof(RecordedRay), b->size(), f) == b->size();
    ok = std::fclose(f) == 0 && ok;
    std::fprintf(stderr, "ray_recorder: %llu rays %s %s\n", (unsigned long long)count,
                 ok ? "written to" : "FAILED to write", path);
  }
};

Log& log() {
  static Log instance;
  return instance;
}

std::vector<RecordedRay>& thread_buffer() {
  thread_local std::vector<RecordedRay>* buffer = [] {
    auto* b = new std::vector<RecordedRay>;
    std::lock_guard<std::mutex> lock(log().mutex);
    log().buffers.push_back(b);
    return b;
  }();
  return *buffer;
}

void record(TraceCall call, float ox, float oy, float oz, float dx, float dy, float dz, float tnear,
            float tfar) {
  if (!log().path) return;
  thread_buffer().push_back({{ox, oy, oz}, {dx, dy, dz}, tnear, tfar, call});
}

template <typename Ray>
void record_one(TraceCall call, const Ray& r) {
  record(call, r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tnear, r.tfar);
}

template <typename Packet>
void record_lanes(TraceCall call, const int* valid, const Packet& r) {
  for (int i = 0; i < 16; ++i)
    if (valid[i] != 0)
      record(call, r.org_x[i], r.org_y[i], r.org_z[i], r.dir_x[i], r.dir_y[i], r.dir_z[i],
             r.tnear[i], r.tfar[i]);
}

// Embree's own function of that name, found past this library.
template <typename Fn>
Fn next(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) {
    std::fprintf(stderr, "ray_recorder: %s not found after the preload\n", name);
    std::abort();
  }
  return reinterpret_cast<Fn>(f);
}

}  // namespace

extern "C" {

void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  static const auto real =
      next<void (*)(RTCScene, RTCIntersectContext*, RTCRayHit*)>("rtcIntersect1");
  record_one(TraceCall::intersect1, rayhit->ray);
  real(scene, context, rayhit);
}

void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  static const auto real = next<void (*)(RTCScene, RTCIntersectContext*, RTCRay*)>("rtcOccluded1");
  record_one(TraceCall::occluded1, *ray);
  real(scene, context, ray);
}

void rtcIntersect16(const int* valid, RTCScene scene, RTCIntersectContext* context,
                    RTCRayHit16* rayhit) {
  static const auto real =
      next<void (*)(const int*, RTCScene, RTCIntersectContext*, RTCRayHit16*)>("rtcIntersect16");
  record_lanes(TraceCall::intersect16, valid, rayhit->ray);
  real(valid, scene, context, rayhit);
}

void rtcOccluded16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16* ray) {
  static const auto real =
      next<void (*)(const int*, RTCScene, RTCIntersectContext*, RTCRay16*)>("rtcOccluded16");
  record_lanes(TraceCall::occluded16, valid, *ray);
  real(valid, scene, context, ray);
}

}  // extern "C"
