#include "session/batch_records.h"

namespace prism {

nlohmann::json record_json(const JobRecord& r) {
  nlohmann::json j = {{"index", r.index},
                      {"job", r.label},
                      {"name", r.name},
                      {"scene", r.scene},
                      {"camera", r.camera},
                      {"integrator", r.integrator},
                      {"spp", r.spp},
                      {"width", r.width},
                      {"height", r.height},
                      {"output", r.output},
                      {"status", to_string(r.status)},
                      {"error", r.error},
                      {"seconds", r.seconds},
                      {"render_seconds", r.render_seconds},
                      {"write_seconds", r.write_seconds},
                      {"load_seconds", r.load_seconds},
                      {"build_seconds", r.build_seconds},
                      {"resumed_samples", r.resumed_samples},
                      {"rank", r.rank},
                      {"side_by_side", r.side_by_side},
                      {"rays", r.rays},
                      {"rays_per_second", r.rays_per_second},
                      {"scene_bytes", r.scene_bytes}};
  if (r.reference_error)
    j["reference"] = {{"rmse", r.reference_error->rmse}, {"relmse", r.reference_error->relmse}};
  return j;
}

JobRecord record_from_json(const nlohmann::json& j) {
  JobRecord r;
  r.index = j.at("index").get<int>();
  r.label = j.at("job").get<std::string>();
  r.name = j.at("name").get<std::string>();
  r.scene = j.at("scene").get<std::string>();
  r.camera = j.at("camera").get<std::string>();
  r.integrator = j.at("integrator").get<std::string>();
  r.spp = j.at("spp").get<int>();
  r.width = j.at("width").get<int>();
  r.height = j.at("height").get<int>();
  r.output = j.at("output").get<std::string>();
  if (!parse_enum(j.at("status").get<std::string>(), &r.status))
    throw std::invalid_argument("unknown job status");
  r.error = j.at("error").get<std::string>();
  r.seconds = j.at("seconds").get<double>();
  r.render_seconds = j.at("render_seconds").get<double>();
  r.write_seconds = j.at("write_seconds").get<double>();
  r.load_seconds = j.at("load_seconds").get<double>();
  r.build_seconds = j.at("build_seconds").get<double>();
  r.resumed_samples = j.at("resumed_samples").get<int>();
  r.rank = j.at("rank").get<int>();
  r.side_by_side = j.at("side_by_side").get<bool>();
  r.rays = j.at("rays").get<uint64_t>();
  r.rays_per_second = j.at("rays_per_second").get<double>();
  r.scene_bytes = j.at("scene_bytes").get<uint64_t>();
  if (j.contains("reference"))
    r.reference_error = PassError{r.spp, j["reference"].at("rmse").get<double>(),
                                  j["reference"].at("relmse").get<double>()};
  return r;
}

}  // namespace prism
