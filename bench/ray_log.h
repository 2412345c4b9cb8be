// The rays a process handed to Embree, as bench/ray_recorder.cpp writes them and
// bench/bounce_ray_probe_bench.cpp reads them back.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace prism::probe {

inline constexpr char kRayLogMagic[8] = {'P', 'R', 'A', 'Y', 'L', 'O', 'G', '1'};

// Which Embree call the ray went to: 16-wide calls are Prism's coherent packets (camera rays,
// the shadow queue), 1-wide ones its incoherent rays (bounces, next-event shadow rays).
enum class TraceCall : uint32_t { intersect1, occluded1, intersect16, occluded16 };
inline constexpr int kTraceCallCount = 4;

struct RecordedRay {
  float origin[3];
  float direction[3];
  float tnear, tfar;
  TraceCall call;
};
static_assert(sizeof(RecordedRay) == 36, "the log's record layout");

inline std::vector<RecordedRay> read_ray_log(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open ray log " + path);
  char magic[8];
  uint64_t count = 0;
  std::vector<RecordedRay> rays;
  bool ok = std::fread(magic, 1, 8, f) == 8 && std::memcmp(magic, kRayLogMagic, 8) == 0 &&
            std::fread(&count, sizeof count, 1, f) == 1 && count < (uint64_t(1) << 32);
  if (ok) {
    rays.resize(count);
    ok = std::fread(rays.data(), sizeof(RecordedRay), count, f) == count;
  }
  std::fclose(f);
  if (!ok) throw std::runtime_error("not a complete ray log: " + path);
  for (const RecordedRay& r : rays)
    if (static_cast<uint32_t>(r.call) >= kTraceCallCount)
      throw std::runtime_error("unknown trace call in ray log " + path);
  return rays;
}

}  // namespace prism::probe
