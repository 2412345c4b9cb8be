// What a flock and its clip are made of, and the one reader of flock.json (docs/boids.md has
// the schema). Everything is checked here, before anything runs or is written, so a bad file
// costs the caller one line naming the field.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <Imath/ImathVec.h>

namespace prism {

struct SphereObstacle {
  Imath::V3f centre{0.0f};
  float radius = 1.0f;
};

struct AxisBox {
  Imath::V3f min{-10.0f};
  Imath::V3f max{10.0f};
};

// Reynolds' flock in metres and seconds. Forces are accelerations (boids have unit mass).
struct FlockParameters {
  uint64_t seed = 1;
  int boids = 100;
  float boid_radius = 0.1f;  // the body: no boid's centre may come this close to a surface
  float time_step = 1.0f / 120.0f;
  float max_speed = 4.0f;
  float cruise_speed = 3.0f;  // the speed a boid steers back to when nothing else pulls
  float max_force = 12.0f;    // the steering budget shared by every behaviour, per step
  float neighbour_radius = 1.5f;
  float separation_radius = 0.5f;
  float field_of_view_degrees = 270.0f;  // the full angle a boid sees neighbours in
  float separation_weight = 1.5f;
  float alignment_weight = 1.0f;
  float cohesion_weight = 1.0f;
  float cruise_weight = 4.0f;  // per second: the share of a speed deficit made up each second
  float migration_weight = 0.0f;
  Imath::V3f migration{0.0f};  // a velocity the flock is drawn to (Reynolds' migratory urge)
  AxisBox bounds;
  float bounds_margin = 1.0f;  // walls start pushing back this far inside the box
  float probe_radius = 0.3f;   // the avoidance cylinder's radius
  float look_ahead = 3.0f;     // the avoidance cylinder's length
  float avoidance_weight = 1.0f;
  std::vector<SphereObstacle> obstacles;
  AxisBox spawn;  // where boids start, outside every obstacle
  Imath::V3f spawn_velocity{1.0f, 0.0f, 0.0f};
};

struct ClipCamera {
  Imath::V3f eye{0.0f, 0.0f, 20.0f};
  Imath::V3f target{0.0f};
  float yfov_degrees = 40.0f;
};

// How the flock becomes frames and how `prism batch` renders them.
struct ClipSettings {
  int frames = 48;
  int steps_per_frame = 4;
  int warmup_steps = 0;  // stepped before the first frame, so the flock has formed
  int width = 320;
  int height = 240;
  int spp = 16;
  std::string integrator = "shadow";
  ClipCamera camera;
  bool ground = true;  // a floor under the box, for shadows
  float background = 0.0f;
};

struct FlockConfig {
  FlockParameters flock;
  ClipSettings clip;
};

// "FILE: FIELD: what is wrong", one line.
struct FlockConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads and checks a flock.json; throws FlockConfigError.
FlockConfig read_flock_config(const std::filesystem::path& path);

// The checks read_flock_config applies, for parameters built in code. `where` prefixes the
// message (a file name, or empty).
void check_flock_parameters(const FlockParameters& p, const std::string& where = "");
void check_clip_settings(const ClipSettings& c, const std::string& where = "");

}  // namespace prism
