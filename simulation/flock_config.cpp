#include "simulation/flock_config.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/registry.h"
#include "scene_io/gltf_loader.h"
#include "simulation/obstacle_scene.h"

namespace prism {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& where, const std::string& field,
                       const std::string& what) {
  throw FlockConfigError((where.empty() ? "" : where + ": ") + field + ": " + what);
}

// One JSON object being read: every key it holds must be one the reader asks for, so a
// misspelt key is an error rather than a silently ignored setting.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string where, std::string prefix)
      : object_(object), where_(std::move(where)), prefix_(std::move(prefix)) {
    if (!object_.is_object()) fail(where_, prefix_.empty() ? "(top)" : prefix_, "is not an object");
  }

  std::string field(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }
  const std::string& where() const { return where_; }

  // Refuses keys no one asked for; call after reading.
  void finish(std::initializer_list<const char*> known) const {
    for (const auto& item : object_.items()) {
      bool found = false;
      for (const char* k : known) found = found || item.key() == k;
      if (!found) fail(where_, field(item.key()), "no such key");
    }
  }

  const json* get(const std::string& key) const {
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  void number(const std::string& key, float* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number()) fail(where_, field(key), "is not a number");
    const double d = v->get<double>();
    if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max())
      fail(where_, field(key), "is not a finite number");
    *out = static_cast<float>(d);
  }

  void integer(const std::string& key, int* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number_integer()) fail(where_, field(key), "is not an integer");
    const auto i = v->get<int64_t>();
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
      fail(where_, field(key), "is out of range");
    *out = static_cast<int>(i);
  }

  void unsigned_integer(const std::string& key, uint64_t* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number_unsigned()) fail(where_, field(key), "is not a non-negative integer");
    *out = v->get<uint64_t>();
  }

  void boolean(const std::string& key, bool* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_boolean()) fail(where_, field(key), "is not true or false");
    *out = v->get<bool>();
  }

  void text(const std::string& key, std::string* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_string()) fail(where_, field(key), "is not a string");
    *out = v->get<std::string>();
  }

  void vector(const std::string& key, Imath::V3f* out) const {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_array() || v->size() != 3) fail(where_, field(key), "is not an array of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const json& c = (*v)[static_cast<size_t>(i)];
      const std::string name = field(key) + "[" + std::to_string(i) + "]";
      if (!c.is_number()) fail(where_, name, "is not a number");
      const double d = c.get<double>();
      if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max())
        fail(where_, name, "is not a finite number");
      (*out)[i] = static_cast<float>(d);
    }
  }

  ObjectReader child(const std::string& key) const {
    static const json empty = json::object();
    const json* v = get(key);
    return ObjectReader(v ? *v : empty, where_, field(key));
  }

 private:
  const json& object_;
  std::string where_;
  std::string prefix_;
};

// nlohmann's DOM parser reports where a syntax error is but not in which field, and a number
// too large for a double not even where. This builds the same document through the SAX
// interface while keeping the path to the value being read, so both name the field.
class FieldTrackingParser : public nlohmann::json_sax<json> {
 public:
  bool null() override { return add(json()); }
  bool boolean(bool v) override { return add(json(v)); }
  bool number_integer(number_integer_t v) override { return add(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return add(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return add(json(v)); }
  bool string(string_t& v) override { return add(json(v)); }
  bool binary(binary_t& v) override { return add(json::binary(v)); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    keys_.back() = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    // 406 is nlohmann's "number overflow": 1e999 and the like.
    if (e.id == 406) {
      error_ = "is not a finite number";
    } else {
      error_ = e.what();
      const size_t close = error_.find("] ");
      if (close != std::string::npos) error_ = error_.substr(close + 2);
      for (char& ch : error_)
        if (ch == '\n' || ch == '\r') ch = ' ';
      error_ = "not valid JSON (it has no NaN or infinity): " + error_;
    }
    return false;
  }

  // "boids.radius", "obstacles[2].centre[1]": the value being read when parsing stopped.
  std::string field() const {
    std::string path;
    for (size_t i = 0; i < stack_.size(); ++i) {
      // An array below the top already holds the container being read; the top one has not
      // stored the value that failed.
      if (stack_[i]->is_array())
        path += "[" + std::to_string(stack_[i]->size() - (i + 1 < stack_.size() ? 1 : 0)) + "]";
      else if (!keys_[i].empty())
        path += (path.empty() ? "" : ".") + keys_[i];
    }
    return path;
  }
  const std::string& error() const { return error_; }
  json take() { return std::move(root_); }

 private:
  json* place(json&& v) {
    if (stack_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& top = *stack_.back();
    if (top.is_array()) {
      top.push_back(std::move(v));
      return &top.back();
    }
    json& slot = top[keys_.back()];
    slot = std::move(v);
    return &slot;
  }
  bool add(json v) {
    place(std::move(v));
    return true;
  }
  bool open(json container) {
    stack_.push_back(place(std::move(container)));
    keys_.emplace_back();
    return true;
  }
  bool close() {
    stack_.pop_back();
    keys_.pop_back();
    return true;
  }

  json root_;
  std::vector<json*> stack_;
  std::vector<std::string> keys_;
  std::string error_;
};

void read_box(const ObjectReader& r, AxisBox* box) {
  r.vector("min", &box->min);
  r.vector("max", &box->max);
}

void read_resolution(const ObjectReader& r, ClipSettings* c) {
  std::string text;
  r.text("resolution", &text);
  if (text.empty()) return;
  int w = 0, h = 0;
  char x = 0, rest = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || (in >> rest))
    fail(r.where(), r.field("resolution"), "is not WIDTHxHEIGHT");
  c->width = w;
  c->height = h;
}

void check_positive(const std::string& where, const std::string& field, float v) {
  if (!(v > 0.0f)) fail(where, field, "must be positive");
}
void check_non_negative(const std::string& where, const std::string& field, float v) {
  if (!(v >= 0.0f)) fail(where, field, "must not be negative");
}
void check_finite(const std::string& where, const std::string& field, const Imath::V3f& v) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i])) fail(where, field, "must be finite");
}
void check_box(const std::string& where, const std::string& field, const AxisBox& b) {
  check_finite(where, field + ".min", b.min);
  check_finite(where, field + ".max", b.max);
  for (int i = 0; i < 3; ++i)
    if (!(b.max[i] > b.min[i])) fail(where, field, "max must exceed min on every axis");
}

}  // namespace

void check_flock_parameters(const FlockParameters& p, const std::string& where) {
  if (p.boids < 1) fail(where, "boids.count", "must be at least 1");
  if (p.boids > 1000000) fail(where, "boids.count", "must be at most 1000000");
  check_positive(where, "boids.radius", p.boid_radius);
  check_positive(where, "simulation.time_step", p.time_step);
  check_positive(where, "boids.max_speed", p.max_speed);
  check_non_negative(where, "boids.cruise_speed", p.cruise_speed);
  if (p.cruise_speed > p.max_speed) fail(where, "boids.cruise_speed", "must not exceed max_speed");
  check_positive(where, "boids.max_force", p.max_force);
  check_positive(where, "boids.neighbour_radius", p.neighbour_radius);
  check_positive(where, "boids.separation_radius", p.separation_radius);
  if (!(p.field_of_view_degrees > 0.0f && p.field_of_view_degrees <= 360.0f))
    fail(where, "boids.field_of_view", "must be above 0 and at most 360 degrees");
  check_non_negative(where, "boids.weights.separation", p.separation_weight);
  check_non_negative(where, "boids.weights.alignment", p.alignment_weight);
  check_non_negative(where, "boids.weights.cohesion", p.cohesion_weight);
  check_non_negative(where, "boids.weights.cruise", p.cruise_weight);
  check_non_negative(where, "migration.weight", p.migration_weight);
  check_finite(where, "migration.velocity", p.migration);
  check_box(where, "bounds", p.bounds);
  check_non_negative(where, "bounds.margin", p.bounds_margin);
  check_positive(where, "avoidance.probe_radius", p.probe_radius);
  check_positive(where, "avoidance.look_ahead", p.look_ahead);
  check_non_negative(where, "avoidance.weight", p.avoidance_weight);
  for (size_t i = 0; i < p.obstacles.size(); ++i) {
    const std::string name = "obstacles[" + std::to_string(i) + "]";
    check_finite(where, name + ".centre", p.obstacles[i].centre);
    check_positive(where, name + ".radius", p.obstacles[i].radius);
  }
  check_box(where, "spawn", p.spawn);
  for (int i = 0; i < 3; ++i)
    if (p.spawn.min[i] < p.bounds.min[i] || p.spawn.max[i] > p.bounds.max[i])
      fail(where, "spawn", "must lie inside bounds");
  check_finite(where, "spawn.velocity", p.spawn_velocity);
}

void check_clip_settings(const ClipSettings& c, const std::string& where) {
  if (c.frames < 1) fail(where, "simulation.frames", "must be at least 1");
  if (c.frames > 100000) fail(where, "simulation.frames", "must be at most 100000");
  if (c.steps_per_frame < 1) fail(where, "simulation.steps_per_frame", "must be at least 1");
  if (c.warmup_steps < 0) fail(where, "simulation.warmup_steps", "must not be negative");
  if (c.width < 1 || c.height < 1 || c.width > 32768 || c.height > 32768)
    fail(where, "render.resolution", "must be 1 to 32768 pixels each way");
  if (c.spp < 1 || c.spp > 65536) fail(where, "render.spp", "must be 1 to 65536");
  if (!find_integrator(c.integrator)) {
    std::string names;
    for (const IntegratorInfo* info : integrator_registry())
      names += std::string(names.empty() ? "" : ", ") + info->name;
    fail(where, "render.integrator", "'" + c.integrator + "' is not one of " + names);
  }
  check_finite(where, "render.camera.eye", c.camera.eye);
  check_finite(where, "render.camera.target", c.camera.target);
  if ((c.camera.target - c.camera.eye).length2() == 0.0f)
    fail(where, "render.camera.target", "must differ from the eye");
  if (!(c.camera.yfov_degrees > 0.0f && c.camera.yfov_degrees < 180.0f))
    fail(where, "render.camera.yfov", "must be above 0 and below 180 degrees");
  check_non_negative(where, "render.background", c.background);
}

FlockConfig read_flock_config(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FlockConfigError(where + ": cannot be read");
  std::stringstream bytes;
  bytes << in.rdbuf();
  json root;
  FieldTrackingParser parser;
  if (!json::sax_parse(bytes.str(), &parser)) {
    const std::string field = parser.field();
    throw FlockConfigError(where + ": " + (field.empty() ? "" : field + ": ") + parser.error());
  }
  root = parser.take();

  FlockConfig config;
  FlockParameters& p = config.flock;
  ClipSettings& c = config.clip;
  const ObjectReader top(root, where, "");
  int version = 0;
  top.integer("version", &version);
  if (version != 1) fail(where, "version", "must be 1");
  top.unsigned_integer("seed", &p.seed);

  const ObjectReader boids = top.child("boids");
  boids.integer("count", &p.boids);
  boids.number("radius", &p.boid_radius);
  boids.number("max_speed", &p.max_speed);
  boids.number("cruise_speed", &p.cruise_speed);
  boids.number("max_force", &p.max_force);
  boids.number("neighbour_radius", &p.neighbour_radius);
  boids.number("separation_radius", &p.separation_radius);
  boids.number("field_of_view", &p.field_of_view_degrees);
  const ObjectReader weights = boids.child("weights");
  weights.number("separation", &p.separation_weight);
  weights.number("alignment", &p.alignment_weight);
  weights.number("cohesion", &p.cohesion_weight);
  weights.number("cruise", &p.cruise_weight);
  weights.finish({"separation", "alignment", "cohesion", "cruise"});
  boids.finish({"count", "radius", "max_speed", "cruise_speed", "max_force", "neighbour_radius",
                "separation_radius", "field_of_view", "weights"});

  const ObjectReader migration = top.child("migration");
  migration.vector("velocity", &p.migration);
  migration.number("weight", &p.migration_weight);
  migration.finish({"velocity", "weight"});

  const ObjectReader bounds = top.child("bounds");
  read_box(bounds, &p.bounds);
  bounds.number("margin", &p.bounds_margin);
  bounds.finish({"min", "max", "margin"});

  // Boids start anywhere in the bounds unless told otherwise.
  p.spawn = p.bounds;
  const ObjectReader spawn = top.child("spawn");
  read_box(spawn, &p.spawn);
  spawn.vector("velocity", &p.spawn_velocity);
  spawn.finish({"min", "max", "velocity"});

  const ObjectReader avoidance = top.child("avoidance");
  avoidance.number("probe_radius", &p.probe_radius);
  avoidance.number("look_ahead", &p.look_ahead);
  avoidance.number("weight", &p.avoidance_weight);
  avoidance.finish({"probe_radius", "look_ahead", "weight"});

  if (const json* obstacles = top.get("obstacles")) {
    if (!obstacles->is_array()) fail(where, "obstacles", "is not an array");
    for (size_t i = 0; i < obstacles->size(); ++i) {
      const ObjectReader o((*obstacles)[i], where, "obstacles[" + std::to_string(i) + "]");
      SphereObstacle sphere;
      if (!o.get("centre")) fail(where, o.field("centre"), "is missing");
      if (!o.get("radius")) fail(where, o.field("radius"), "is missing");
      o.vector("centre", &sphere.centre);
      o.number("radius", &sphere.radius);
      o.finish({"centre", "radius"});
      p.obstacles.push_back(sphere);
    }
  }

  // Spheres of a glTF file join the listed ones, read now so that a file that cannot be
  // loaded is a config error like any other.
  const ObjectReader scene = top.child("obstacle_scene");
  std::string scene_file;
  bool detect_spheres = false;
  scene.text("file", &scene_file);
  scene.boolean("detect_spheres", &detect_spheres);
  scene.finish({"file", "detect_spheres"});
  if (!scene_file.empty()) {
    const std::filesystem::path file = path.parent_path() / scene_file;
    try {
      for (const SphereObstacle& s : scene_spheres(file, detect_spheres)) p.obstacles.push_back(s);
    } catch (const LoadError& e) {
      fail(where, "obstacle_scene.file", e.what());
    }
  }

  const ObjectReader simulation = top.child("simulation");
  simulation.number("time_step", &p.time_step);
  simulation.integer("steps_per_frame", &c.steps_per_frame);
  simulation.integer("warmup_steps", &c.warmup_steps);
  simulation.integer("frames", &c.frames);
  simulation.finish({"time_step", "steps_per_frame", "warmup_steps", "frames"});

  const ObjectReader render = top.child("render");
  read_resolution(render, &c);
  render.integer("spp", &c.spp);
  render.text("integrator", &c.integrator);
  render.boolean("ground", &c.ground);
  render.number("background", &c.background);
  const ObjectReader camera = render.child("camera");
  camera.vector("eye", &c.camera.eye);
  camera.vector("target", &c.camera.target);
  camera.number("yfov", &c.camera.yfov_degrees);
  camera.finish({"eye", "target", "yfov"});
  render.finish({"resolution", "spp", "integrator", "ground", "background", "camera"});

  top.finish({"version", "seed", "boids", "migration", "bounds", "spawn", "avoidance", "obstacles",
              "obstacle_scene", "simulation", "render"});
  check_flock_parameters(p, where);
  check_clip_settings(c, where);
  return config;
}

}  // namespace prism
