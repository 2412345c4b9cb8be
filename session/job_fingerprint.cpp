#include "session/job_fingerprint.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <xxhash.h>

#include "renderer/version.h"

namespace prism {
namespace {

std::string hex(const XXH128_hash_t& h) {
  char buffer[33];
  std::snprintf(buffer, sizeof buffer, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return buffer;
}

struct StateDeleter {
  void operator()(XXH3_state_t* s) const { XXH3_freeState(s); }
};
using HashState = std::unique_ptr<XXH3_state_t, StateDeleter>;

HashState new_state() {
  HashState state(XXH3_createState());
  if (!state || XXH3_128bits_reset(state.get()) != XXH_OK)
    throw std::runtime_error("cannot create a hash state");
  return state;
}

// Each piece is preceded by its length, so that ("ab", "c") and ("a", "bc") differ.
void update(XXH3_state_t* state, const std::string& piece) {
  const unsigned long long length = piece.size();
  XXH3_128bits_update(state, &length, sizeof length);
  XXH3_128bits_update(state, piece.data(), piece.size());
}

std::string number(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

}  // namespace

std::string environment_settings(const EnvironmentRequest& e) {
  std::string map = "none";
  if (!e.path.empty()) {
    std::error_code error;
    const std::filesystem::path absolute = std::filesystem::absolute(e.path, error);
    std::string hash;
    try {
      hash = content_hash(e.path);
    } catch (const std::runtime_error&) {
      hash = "unreadable";
    }
    map = (error ? e.path : absolute.lexically_normal().string()) + " " + hash;
  }
  return map + " rotation " + number(e.rotation_degrees) + " intensity " + number(e.intensity) +
         (e.hidden ? " hidden" : " seen");
}

std::string canonical_settings(const SceneRequest& scene, const RenderJob& job,
                               ExrPixelType pixel_type) {
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(scene.path, error);
  std::string text;
  auto line = [&](const char* key, const std::string& value) {
    text += std::string(key) + "=" + value + "\n";
  };
  line("scene", error ? scene.path : absolute.lexically_normal().string());
  line("scene-select", scene.scene);
  line("allow-external-paths", scene.allow_external_paths ? "1" : "0");
  line("detect-spheres", scene.detect_spheres ? "1" : "0");
  line("sphere-tolerance", number(scene.sphere_detection.tolerance));
  line("integrator", job.integrator);
  for (const auto& [name, value] : job.integrator_parameters) line(name.c_str(), number(value));
  line("camera", job.camera);
  // Only when given, so that the fingerprints of jobs without them stay as they were.
  if (job.frame_scene) line("camera-auto", "1");
  if (job.placement) {
    const auto vector = [&](const char* key, const std::optional<V3d>& v) {
      if (v) line(key, number(v->x) + "," + number(v->y) + "," + number(v->z));
    };
    vector("look-from", job.placement->look_from);
    vector("look-at", job.placement->look_at);
    vector("up", job.placement->up);
    if (job.placement->yfov_degrees) line("fov", number(*job.placement->yfov_degrees));
  }
  line("res", std::to_string(job.width) + "x" + std::to_string(job.height));
  line("spp", std::to_string(job.film.spp));
  line("target-error", number(job.film.target_error));
  line("time-limit", number(job.film.time_limit_seconds));
  line("min-spp", std::to_string(job.film.min_spp));
  // Only when not the default: jobs keep the fingerprints they had before the goal existed.
  if (job.film.error_goal != ErrorGoal::pixel) line("error-goal", to_string(job.film.error_goal));
  // Only when set: seed 0's jobs keep the fingerprints they had before seeds existed.
  if (job.film.seed != 0) line("seed", std::to_string(job.film.seed));
  if (job.film.has_region()) {
    const TileRect& r = job.film.region;
    line("region", std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) +
                       "," + std::to_string(r.y1));
  }
  line("working-space", to_string(job.working_space));
  line("background",
       number(job.background.x) + "," + number(job.background.y) + "," + number(job.background.z));
  line("environment", environment_settings(job.environment));
  line("brdf", to_string(job.brdf));
  line("spheres", to_string(job.spheres));
  line("robust", job.robust ? "1" : "0");
  line("build-quality", to_string(job.build_quality));
  line("reference", job.reference_path);
  line("half", pixel_type == ExrPixelType::half ? "1" : "0");
  return text;
}

std::string hash_text(const std::string& bytes) {
  return hex(XXH3_128bits(bytes.data(), bytes.size()));
}

std::string content_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read to hash it");
  HashState state = new_state();
  std::vector<char> block(size_t{1} << 20);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const std::streamsize got = in.gcount();
    if (got > 0) XXH3_128bits_update(state.get(), block.data(), static_cast<size_t>(got));
  }
  if (in.bad()) throw std::runtime_error(path + ": read error while hashing it");
  return hex(XXH3_128bits_digest(state.get()));
}

std::vector<InputFile> hash_inputs(const std::vector<std::string>& files) {
  std::vector<InputFile> inputs;
  for (const std::string& file : files) inputs.push_back({file, content_hash(file)});
  return inputs;
}

std::string job_fingerprint(const std::string& settings, const std::vector<InputFile>& inputs) {
  HashState state = new_state();
  update(state.get(), std::string("prism ") + kVersion + " " + kBuildCommit);
  update(state.get(), settings);
  for (const InputFile& input : inputs) {
    update(state.get(), input.path);
    update(state.get(), input.content_hash);
  }
  return hex(XXH3_128bits_digest(state.get()));
}

std::string format_inputs(const std::vector<InputFile>& inputs) {
  std::string text;
  for (const InputFile& input : inputs)
    text += (text.empty() ? "" : "\n") + input.content_hash + " " + input.path;
  return text;
}

bool parse_inputs(const std::string& text, std::vector<InputFile>* inputs) {
  inputs->clear();
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    if (line.size() < 34 || line[32] != ' ') return false;
    const std::string hash = line.substr(0, 32);
    if (hash.find_first_not_of("0123456789abcdef") != std::string::npos) return false;
    inputs->push_back({line.substr(33), hash});
    start = end + 1;
  }
  return true;
}

}  // namespace prism
