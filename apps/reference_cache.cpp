#include "apps/reference_cache.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "renderer/image/exr_file.h"
#include "renderer/image/image_metrics.h"
#include "renderer/version.h"
#include "session/job_fingerprint.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

// The EXR attribute (prism:<name>) holding the settings a cached reference was made with.
constexpr const char* kKeyAttribute = "referenceKey";

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The glTF's JSON: the whole .gltf, or a .glb's first chunk (after the 12-byte header and the
// chunk's length and type). Empty when it is neither.
std::string gltf_json(const std::string& bytes) {
  if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {
    uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, sizeof length);
    return bytes.substr(20, length);
  }
  return bytes;
}

// The scene's bytes with those of the files it names (buffers, images): editing a texture
// or a .bin beside the .gltf must not bring back a stale reference.
std::string scene_fingerprint(const std::string& scene_path) {
  const std::string bytes = read_bytes(scene_path);
  std::string all = bytes;
  const nlohmann::json gltf = nlohmann::json::parse(gltf_json(bytes), nullptr, false);
  if (gltf.is_object()) {
    for (const char* list : {"buffers", "images"}) {
      if (!gltf.contains(list) || !gltf[list].is_array()) continue;
      for (const nlohmann::json& item : gltf[list]) {
        if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
        const std::string uri = item["uri"];
        if (uri.rfind("data:", 0) == 0) continue;  // embedded: already in the bytes
        all += uri;
        all += read_bytes(fs::path(scene_path).parent_path() / uri);
      }
    }
  }
  return hash_text(all);
}

}  // namespace

ReferenceKey reference_key(const std::string& scene_path, const RenderJob& job,
                           const RenderSettings& s, const ParameterValues& parameters,
                           const CameraDescription& camera, int camera_index) {
  std::vector<double> camera_to_world;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) camera_to_world.push_back(camera.camera_to_world[r][c]);
  ReferenceKey key;
  key.settings = {
      {"version", kVersion},
      {"scene", scene_fingerprint(scene_path)},
      {"integrator", job.integrator},
      {"parameters", parameters.values()},
      {"spp", s.spp},
      {"seed", s.seed},
      {"width", s.width},
      {"height", s.height},
      {"camera",
       {{"index", camera_index},
        {"name", camera.name},
        {"projection", static_cast<int>(camera.projection)},
        {"cameraToWorld", camera_to_world},
        {"yfov", camera.yfov},
        {"aspectRatio", camera.aspect_ratio},
        {"xmag", camera.xmag},
        {"ymag", camera.ymag},
        {"znear", camera.znear}}},
      {"workingSpace", to_string(job.working_space)},
      {"background", {job.background.x, job.background.y, job.background.z}},
      {"environment", environment_settings(job.environment)},
      {"brdf", to_string(job.brdf)},
      {"spheres", to_string(job.spheres)},
  };
  const std::string text = key.settings.dump();
  key.hash = hash_text(text);
  return key;
}

std::string reference_cache_dir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  // The XDG base directory spec says a relative XDG_CACHE_HOME is invalid and to be ignored.
  if (xdg && *xdg && fs::path(xdg).is_absolute())
    return (fs::path(xdg) / "prism" / "references").string();
  const char* home = std::getenv("HOME");
  if (home && *home) return (fs::path(home) / ".cache" / "prism" / "references").string();
  throw UsageError(
      "--reference-spp: no cache directory for references (set XDG_CACHE_HOME or HOME)");
}

std::string cached_reference_path(const std::string& dir, const ReferenceKey& key) {
  return (fs::path(dir) / (key.hash + ".exr")).string();
}

std::pair<std::string, std::string> reference_metadata_entry(const ReferenceKey& key) {
  return {kKeyAttribute, key.settings.dump()};
}

RecordedRender read_recorded_render(const std::string& path) {
  RecordedRender recorded;
  recorded.image = read_exr(path);
  const std::optional<ExrHeader> header = read_exr_header(path);
  if (!header) throw std::runtime_error(path + ": not a readable OpenEXR file");
  recorded.spp = header->int_value("prism:spp").value_or(0);
  recorded.seconds = header->float_value("prism:renderSeconds").value_or(0.0f);
  // write_exr stores the counts as strings (RenderMetadata::extra).
  auto count = [&](const char* name) {
    return std::strtoull(header->string_value(std::string("prism:") + name).value_or("").c_str(),
                         nullptr, 10);
  };
  for (const EnumName<RayKind>& kind : kRayKindNames) {
    std::string name = kind.name;
    name[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
    recorded.rays[kind.value] = count(("rays" + name).c_str());
  }
  recorded.rays.discarded_samples = count("discardedSamples");
  return recorded;
}

std::optional<RecordedRender> find_cached_reference(const std::string& dir,
                                                    const ReferenceKey& key) {
  const std::string path = cached_reference_path(dir, key);
  if (!fs::is_regular_file(path)) return std::nullopt;
  // Unreadable, or another key with the same hash: render it again.
  if (read_exr_string(path, std::string("prism:") + kKeyAttribute) != key.settings.dump())
    return std::nullopt;
  try {
    RecordedRender found = read_recorded_render(path);
    // A hit makes it the most recently used (bound_reference_cache evicts by this time).
    std::error_code ec;
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
    return found;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

namespace {

bool is_cache_entry(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  if (!entry.is_regular_file() || name.size() != 32 + 4 || !name.ends_with(".exr")) return false;
  for (size_t i = 0; i < 32; ++i)
    if (!std::isxdigit(static_cast<unsigned char>(name[i]))) return false;
  return true;
}

}  // namespace

CacheSweep bound_reference_cache(const std::string& dir, uint64_t max_bytes,
                                 const std::string& keep) {
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    uint64_t bytes;
  };
  std::vector<Entry> entries;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (!is_cache_entry(entry)) continue;
    std::error_code size_ec, time_ec;
    const uint64_t bytes = entry.file_size(size_ec);
    const fs::file_time_type time = entry.last_write_time(time_ec);
    if (!size_ec && !time_ec) entries.push_back({entry.path(), time, bytes});
  }
  // Newest first; the oldest go while the total is over the bound.
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.time != b.time ? a.time > b.time : a.path < b.path;
  });
  CacheSweep sweep;
  uint64_t total = 0;
  for (const Entry& e : entries) total += e.bytes;
  for (auto it = entries.rbegin(); it != entries.rend(); ++it) {
    const bool kept_anyway = !keep.empty() && fs::equivalent(it->path, keep, ec);
    if (total > max_bytes && !kept_anyway && fs::remove(it->path, ec)) {
      total -= it->bytes;
      ++sweep.removed;
      sweep.removed_bytes += it->bytes;
    } else {
      ++sweep.kept;
      sweep.kept_bytes += it->bytes;
    }
  }
  return sweep;
}

}  // namespace prism
