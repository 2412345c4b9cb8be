#include "session/checkpoint_fingerprint.h"

#include <xxhash.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "renderer/version.h"

namespace prism {
namespace {

// Hex floats: exact, so two values that differ in the last bit give different texts.
std::string exact(double v) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%a", v);
  return buffer;
}

}  // namespace

std::string checkpoint_fingerprint(const SceneRequest& request, const RenderJob& job) {
  // One field per line, named, so that no two jobs share a text.
  std::string text = "prism " + std::string(kVersion) + "\n";
  const auto field = [&](const char* name, const std::string& value) {
    text += name;
    text += '=';
    text += value;
    text += '\n';
  };
  field("scene.path", request.path);
  field("scene.scene", request.scene);
  field("scene.allow_external_paths", std::to_string(request.allow_external_paths));
  field("scene.add_defaults", std::to_string(request.add_defaults));
  field("scene.detect_spheres", std::to_string(request.detect_spheres));
  field("scene.sphere_tolerance", exact(request.sphere_detection.tolerance));
  field("scene.sphere_min_vertices", std::to_string(request.sphere_detection.min_vertices));
  field("scene.sphere_min_facet_distance", exact(request.sphere_detection.min_facet_distance));
  field("integrator", job.integrator);
  for (const auto& [name, value] : job.integrator_parameters)
    field(("parameter." + name).c_str(), exact(value));
  field("camera", job.camera);
  field("width", std::to_string(job.width));
  field("height", std::to_string(job.height));
  field("film.width", std::to_string(job.film.width));
  field("film.height", std::to_string(job.film.height));
  field("film.spp", std::to_string(job.film.spp));
  field("film.tile_size", std::to_string(job.film.tile_size));
  field("film.specialise", std::to_string(job.film.specialise));
  field("film.target_error", exact(job.film.target_error));
  field("film.time_limit_seconds", exact(job.film.time_limit_seconds));
  field("film.min_spp", std::to_string(job.film.min_spp));
  field("working_space", to_string(job.working_space));
  field("background", exact(job.background));
  field("brdf", to_string(job.brdf));
  field("spheres", to_string(job.spheres));
  field("robust", std::to_string(job.robust));
  field("build_quality", to_string(job.build_quality));
  field("reference", job.reference_path);

  XXH3_state_t* state = XXH3_createState();
  if (!state) throw std::bad_alloc();
  const std::unique_ptr<XXH3_state_t, XXH_errorcode (*)(XXH3_state_t*)> owner(state,
                                                                              &XXH3_freeState);
  XXH3_128bits_reset(state);
  XXH3_128bits_update(state, text.data(), text.size());
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(request.path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw std::runtime_error(request.path + ": cannot read it: " + std::strerror(errno));
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0)
    XXH3_128bits_update(state, buffer, n);
  if (std::ferror(file.get())) throw std::runtime_error(request.path + ": cannot read it");
  const XXH128_hash_t h = XXH3_128bits_digest(state);
  char hex[33];
  std::snprintf(hex, sizeof hex, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return hex;
}

}  // namespace prism
