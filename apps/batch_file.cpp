#include "apps/batch_file.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "apps/render_command.h"

namespace prism {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Set once for the whole batch, not per job.
const std::map<std::string, std::string> kBatchLevel = {
    {"threads", "give --threads to prism batch"},
    {"memory-limit", "give --memory-limit to prism batch"},
    {"quiet", "give --quiet to prism batch"},
    {"verbose", "it is not a job's setting"}};
// Keys whose values are paths, resolved against the job file's folder.
const std::set<std::string> kPathKeys = {"scene",     "output",     "preview", "sample-count-image",
                                         "reference", "environment"};
// Keys that may be lists, expanding into one render per value, in this order.
const char* const kMatrixKeys[] = {"camera", "integrator", "spp"};

struct Failure {
  std::string field, message;
};

std::string number_text(const json& v) {
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number_unsigned()) return std::to_string(v.get<unsigned long long>());
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v.get<double>());
  return buffer;
}

// A render option's value as command-line text; false for a type no option takes.
bool value_text(const json& v, std::string* text) {
  if (v.is_string())
    *text = v.get<std::string>();
  else if (v.is_number())
    *text = number_text(v);
  else
    return false;
  return true;
}

// `prism render`'s command line for one job: its keys as flags, in key order.
std::vector<std::string> job_arguments(const json& job, const std::string* only = nullptr) {
  std::vector<std::string> args = {"render"};
  for (const auto& [key, value] : job.items()) {
    if (key == "name") continue;
    if (only && key != *only && key != "scene" && key != "output") continue;
    if (key == "scene") {
      args.push_back(value.get<std::string>());
      continue;
    }
    const std::string flag = "--" + std::string(key == "resolution" ? "res" : key);
    if (value.is_boolean()) {
      if (value.get<bool>()) args.push_back(flag);
      continue;
    }
    std::string text;
    value_text(value, &text);
    args.push_back(flag);
    args.push_back(text);
  }
  return args;
}

// Parses `args` as `prism render` does; the CLI11 message on failure, "" on success.
std::string parse_render(const std::vector<std::string>& args, RenderOptions* options) {
  CLI::App app;
  add_render_command(app, options);
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

// Whether `key` is one of `prism render`'s flags (options that take no value).
bool is_render_flag(const std::string& key) {
  CLI::App app;
  RenderOptions options;
  CLI::App* render = add_render_command(app, &options);
  const CLI::Option* option = render->get_option_no_throw("--" + key);
  return option && option->get_expected_max() == 0;
}

// "--spp: Value 0 not in range" -> field "spp", message "Value 0 not in range".
Failure split_flag_message(const std::string& message, const std::string& fallback) {
  if (message.rfind("--", 0) == 0) {
    const size_t end = message.find_first_of(": ", 2);
    if (end != std::string::npos) {
      std::string rest = message.substr(end);
      while (!rest.empty() && (rest[0] == ':' || rest[0] == ' ')) rest.erase(0, 1);
      return {message.substr(2, end - 2), rest};
    }
  }
  return {fallback, message};
}

// One render of a job (every matrix key a single value) into a spec, or the failure.
std::optional<Failure> make_spec(const json& job, BatchJobSpec* spec) {
  for (const auto& [key, value] : job.items()) {
    if (kBatchLevel.count(key))
      return Failure{key, "is set for the whole batch: " + kBatchLevel.at(key)};
    if (key == "name") continue;
    if (value.is_array() || value.is_object() || value.is_null())
      return Failure{key, std::string("must be a ") +
                              (value.is_boolean() ? "flag" : "string, number or true/false")};
  }
  if (!job.contains("scene")) return Failure{"scene", "missing: every job needs a scene file"};
  if (!job.contains("output"))
    return Failure{"output", "missing: every job needs an output path (.exr)"};
  if (!job["scene"].is_string()) return Failure{"scene", "must be a path"};
  RenderOptions options;
  std::string message = parse_render(job_arguments(job), &options);
  if (!message.empty()) {
    // Which key: each alone, beside the scene and output every job has.
    for (const auto& [key, value] : job.items()) {
      if (key == "name" || key == "scene" || key == "output") continue;
      RenderOptions alone;
      const std::string m = parse_render(job_arguments(job, &key), &alone);
      if (m.find("not expected") != std::string::npos)
        return is_render_flag(key) ? Failure{key, "is a flag: give true or false"}
                                   : Failure{key, "no such key: prism render has no --" + key};
      if (!m.empty()) return split_flag_message(m, key);
    }
    return split_flag_message(message, "job");
  }
  RenderRequest request;
  try {
    request = render_request(options);
  } catch (const UsageError& e) {
    return split_flag_message(e.what(), "job");
  } catch (const RequestError& e) {
    return Failure{e.field, e.what()};
  }
  spec->scene = request.scene;
  spec->render = request.job;
  spec->outputs = {request.files.image, request.files.preview, request.files.sample_counts};
  spec->pixel_type = request.files.pixel_type;
  spec->checkpoint_interval = request.checkpoint_interval;
  for (const auto& [field, pattern] :
       {std::pair{"output", &spec->outputs.exr}, std::pair{"preview", &spec->outputs.preview},
        std::pair{"sample-count-image", &spec->outputs.sample_counts}})
    if (const std::string problem = placeholder_problem(*pattern); !problem.empty())
      return Failure{field, problem};
  if (spec->render.camera == "all") {
    spec->every_camera = true;
    spec->render.camera.clear();
  }
  return std::nullopt;
}

// Every combination of the matrix keys' values, as single-valued jobs.
std::vector<json> expand_matrix(const json& job) {
  std::vector<json> out = {job};
  for (const char* key : kMatrixKeys) {
    if (!job.contains(key) || !job[key].is_array()) continue;
    std::vector<json> next;
    for (const json& partial : out)
      for (const json& value : job[key]) {
        json copy = partial;
        copy[key] = value;
        next.push_back(std::move(copy));
      }
    out = std::move(next);
  }
  return out;
}

}  // namespace

std::string JobFileError::describe() const {
  std::string text;
  if (job >= 0) text = "jobs[" + std::to_string(job) + "] '" + name + "': ";
  if (!field.empty()) text += field + ": ";
  return text + message;
}

JobFile read_job_file(const std::string& path) {
  JobFile file;
  auto fail = [&](const std::string& field, const std::string& message) {
    file.errors.push_back({-1, "", field, message});
    return file;
  };
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return fail("", "no such job file");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  json root;
  try {
    root = json::parse(text.str());
  } catch (const json::parse_error& e) {
    return fail("", std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object())
    return fail("", "a job file is a JSON object with \"version\" and \"jobs\"");
  for (const auto& [key, value] : root.items())
    if (key != "version" && key != "defaults" && key != "jobs")
      return fail(key, "unknown key (a job file has \"version\", \"defaults\" and \"jobs\")");
  if (!root.contains("version") || !root["version"].is_number_integer())
    return fail("version", "missing: say \"version\": " + std::to_string(kJobFileVersion));
  if (root["version"].get<long long>() != kJobFileVersion)
    return fail("version", std::to_string(root["version"].get<long long>()) +
                               ": this Prism reads version " + std::to_string(kJobFileVersion));
  json defaults = root.value("defaults", json::object());
  if (!defaults.is_object()) return fail("defaults", "must be an object of job keys");
  if (!root.contains("jobs") || !root["jobs"].is_array() || root["jobs"].empty())
    return fail("jobs", "must be a list of at least one job");
  const fs::path folder = fs::path(path).parent_path();
  file.jobs = static_cast<int>(root["jobs"].size());
  for (int i = 0; i < file.jobs; ++i) {
    const json& given = root["jobs"][static_cast<size_t>(i)];
    JobFileError problem{i, "job" + std::to_string(i), "", ""};
    if (!given.is_object()) {
      problem.message = "a job is an object of render options";
      file.errors.push_back(problem);
      continue;
    }
    json job = defaults;
    for (const auto& [key, value] : given.items()) job[key] = value;
    if (job.contains("name")) {
      if (!job["name"].is_string() || job["name"].get<std::string>().empty()) {
        problem.field = "name";
        problem.message = "must be a non-empty string";
        file.errors.push_back(problem);
        continue;
      }
      problem.name = job["name"].get<std::string>();
    }
    // Paths are the job file's, wherever prism runs.
    for (const std::string& key : kPathKeys) {
      if (!job.contains(key) || !job[key].is_string()) continue;
      const fs::path p = job[key].get<std::string>();
      if (!p.empty() && p.is_relative()) job[key] = (folder / p).lexically_normal().string();
    }
    for (const char* key : kMatrixKeys)
      if (job.contains(key) && job[key].is_array() && job[key].empty()) {
        problem.field = key;
        problem.message = "an empty list renders nothing";
      }
    if (!problem.message.empty()) {
      file.errors.push_back(problem);
      continue;
    }
    std::vector<BatchJobSpec> specs;
    for (const json& single : expand_matrix(job)) {
      BatchJobSpec spec;
      spec.file_index = i;
      spec.name = problem.name;
      for (const char* key : kMatrixKeys)
        if (job.contains(key) && job[key].is_array()) {
          std::string value;
          value_text(single[key], &value);
          spec.variant += (spec.variant.empty() ? "" : ", ") + std::string(key) + " " + value;
        }
      if (auto failure = make_spec(single, &spec)) {
        problem.field = failure->field;
        problem.message = failure->message;
        break;
      }
      specs.push_back(std::move(spec));
    }
    if (!problem.message.empty()) {
      file.errors.push_back(problem);
      continue;
    }
    file.specs.insert(file.specs.end(), specs.begin(), specs.end());
  }
  return file;
}

}  // namespace prism
