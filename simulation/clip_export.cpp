#include "simulation/clip_export.h"

#include <cmath>
#include <cstdio>
#include <cstring>


#include "simulation/atomic_write.h"
#include "simulation/flock.h"

namespace prism {

using Imath::V3f;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kFloatComponent = 5126;
constexpr int kArrayBufferTarget = 34962;

// glTF's column-major node matrix from three axis columns and a translation.
json node_matrix(const V3f& x, const V3f& y, const V3f& z, const V3f& t) {
  return json::array(
      {x.x, x.y, x.z, 0.0f, y.x, y.y, y.z, 0.0f, z.x, z.y, z.z, 0.0f, t.x, t.y, t.z, 1.0f});
}

// A right-handed frame whose third axis is `forward`, its second as near world up as the
// heading allows.
void frame_around(const V3f& forward, V3f* right, V3f* up) {
  V3f r = V3f(0.0f, 1.0f, 0.0f).cross(forward);
  if (r.length2() < 1e-8f) r = V3f(1.0f, 0.0f, 0.0f).cross(forward);
  *right = r.normalized();
  *up = forward.cross(*right);
}

json material(const char* name, float r, float g, float b, float roughness) {
  return {{"name", name},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {r, g, b, 1.0f}},
            {"metallicFactor", 0.0f},
            {"roughnessFactor", roughness}}}};
}

// Flat-shaded triangles with their normals, appended to one buffer.
struct GeometryBuffer {
  std::vector<unsigned char> bytes;
  json views = json::array();
  json accessors = json::array();

  // Returns the POSITION and NORMAL accessors of a triangle list.
  std::pair<int, int> add_triangles(const std::vector<V3f>& triangles) {
    std::vector<V3f> normals;
    for (size_t i = 0; i + 2 < triangles.size(); i += 3) {
      const V3f n =
          (triangles[i + 1] - triangles[i]).cross(triangles[i + 2] - triangles[i]).normalized();
      normals.insert(normals.end(), {n, n, n});
    }
    V3f lo(INFINITY), hi(-INFINITY);
    for (const V3f& p : triangles)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
    const int positions =
        add(triangles, json::array({lo.x, lo.y, lo.z}), json::array({hi.x, hi.y, hi.z}));
    const int normal = add(normals, json(), json());
    return {positions, normal};
  }

  std::string data_uri() const {
    // RFC 4648 base64, three bytes to four characters, '=' padding the last group.
    static constexpr char kDigits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out = "data:application/octet-stream;base64,";
    for (size_t i = 0; i < bytes.size(); i += 3) {
      const size_t n = std::min<size_t>(3, bytes.size() - i);
      uint32_t group = uint32_t(uint8_t(bytes[i])) << 16;
      if (n > 1) group |= uint32_t(uint8_t(bytes[i + 1])) << 8;
      if (n > 2) group |= uint32_t(uint8_t(bytes[i + 2]));
      for (size_t k = 0; k < 4; ++k)
        out += k <= n ? kDigits[(group >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
  }

 private:
  int add(const std::vector<V3f>& values, const json& min, const json& max) {
    const size_t offset = bytes.size();
    const size_t length = values.size() * sizeof(float) * 3;
    bytes.resize(offset + length);
    for (size_t i = 0; i < values.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        const float c = values[i][a];
        std::memcpy(bytes.data() + offset + (3 * i + static_cast<size_t>(a)) * sizeof(float), &c,
                    sizeof c);
      }
    views.push_back({{"buffer", 0},
                     {"byteOffset", offset},
                     {"byteLength", length},
                     {"target", kArrayBufferTarget}});
    json accessor = {{"bufferView", views.size() - 1},
                     {"componentType", kFloatComponent},
                     {"count", values.size()},
                     {"type", "VEC3"}};
    if (!min.is_null()) {
      accessor["min"] = min;
      accessor["max"] = max;
    }
    accessors.push_back(accessor);
    return static_cast<int>(accessors.size() - 1);
  }
};

// A sphere palette that reads apart from the warm boids.
constexpr float kSphereColours[][3] = {
    {0.20f, 0.35f, 0.70f}, {0.25f, 0.55f, 0.45f}, {0.55f, 0.55f, 0.60f}, {0.45f, 0.30f, 0.60f}};

}  // namespace

std::string ClipLayout::frame_name(int frame) const {
  const int digits = std::max(4, static_cast<int>(std::to_string(std::max(frames - 1, 0)).size()));
  char name[32];
  std::snprintf(name, sizeof name, "frame_%0*d", digits, frame);
  return name;
}
fs::path ClipLayout::scene(int frame) const {
  return dir / "scenes" / (frame_name(frame) + ".gltf");
}
fs::path ClipLayout::exr(int frame) const {
  return dir / "exr" / (frame_name(frame) + ".exr");
}
fs::path ClipLayout::preview(int frame) const {
  return dir / "png" / (frame_name(frame) + ".png");
}

std::vector<V3f> dart_triangles() {
  // A narrow four-sided pyramid: the nose ahead, a flat diamond tail, wider than tall so
  // the flock's headings read from above and from the side.
  const V3f nose(0.0f, 0.0f, 1.0f);
  const V3f left(-0.45f, 0.0f, -0.7f), right(0.45f, 0.0f, -0.7f);
  const V3f top(0.0f, 0.3f, -0.7f), bottom(0.0f, -0.2f, -0.7f);
  // Counter-clockwise seen from outside, so the normals point out.
  return {nose, right,  top,   nose, top, left,  nose, left,  bottom,
          nose, bottom, right, left, top, right, left, right, bottom};
}

json frame_scene(const FlockParameters& flock, const ClipSettings& clip,
                 const std::vector<V3f>& positions, const std::vector<V3f>& velocities) {
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "prism boids"}};
  doc["extensionsUsed"] = {"PRISM_sphere", "KHR_lights_punctual"};
  doc["scene"] = 0;

  json materials = json::array();
  materials.push_back(material("boid", 0.95f, 0.55f, 0.12f, 0.5f));
  for (const auto& c : kSphereColours)
    materials.push_back(material("sphere", c[0], c[1], c[2], 0.4f));
  const int ground_material = static_cast<int>(materials.size());
  materials.push_back(material("ground", 0.55f, 0.55f, 0.52f, 0.9f));
  doc["materials"] = materials;

  GeometryBuffer buffer;
  const auto dart = buffer.add_triangles(dart_triangles());
  json meshes = json::array();
  meshes.push_back(
      {{"name", "boid"},
       {"primitives",
        {{{"attributes", {{"POSITION", dart.first}, {"NORMAL", dart.second}}}, {"material", 0}}}}});
  json nodes = json::array();
  if (clip.ground) {
    // A floor just under the box, three times its width so the camera never sees its edge.
    const AxisBox& b = flock.bounds;
    const V3f size = b.max - b.min;
    const float y = b.min.y - 0.01f * size.y;
    const float x0 = b.min.x - size.x, x1 = b.max.x + size.x;
    const float z0 = b.min.z - size.z, z1 = b.max.z + size.z;
    const auto floor = buffer.add_triangles({V3f(x0, y, z0), V3f(x0, y, z1), V3f(x1, y, z1),
                                             V3f(x0, y, z0), V3f(x1, y, z1), V3f(x1, y, z0)});
    meshes.push_back({{"name", "ground"},
                      {"primitives",
                       {{{"attributes", {{"POSITION", floor.first}, {"NORMAL", floor.second}}},
                         {"material", ground_material}}}}});
    nodes.push_back({{"name", "ground"}, {"mesh", 1}});
  }
  doc["meshes"] = meshes;
  doc["buffers"] = {{{"byteLength", buffer.bytes.size()}, {"uri", buffer.data_uri()}}};
  doc["bufferViews"] = buffer.views;
  doc["accessors"] = buffer.accessors;

  // The camera looks down its -z with +y up.
  V3f right, up;
  const V3f forward = (clip.camera.target - clip.camera.eye).normalized();
  frame_around(-forward, &right, &up);
  doc["cameras"] = {{{"type", "perspective"},
                     {"perspective",
                      {{"yfov", clip.camera.yfov_degrees * kPi / 180.0f},
                       {"aspectRatio", static_cast<float>(clip.width) / clip.height},
                       {"znear", 0.05f}}}}};
  nodes.push_back({{"name", "camera"},
                   {"camera", 0},
                   {"matrix", node_matrix(right, up, -forward, clip.camera.eye)}});

  // A warm sun from above one side and a cool, weak fill from behind the camera (its shadows fall
  // behind what casts them); a light shines down its -z.
  const V3f sun = V3f(-0.4f, -1.0f, -0.5f).normalized();
  const V3f fill = V3f(0.3f, -0.7f, -0.65f).normalized();
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"name", "sun"},
                                                         {"type", "directional"},
                                                         {"color", {1.0f, 0.95f, 0.85f}},
                                                         {"intensity", 2.6f}},
                                                        {{"name", "fill"},
                                                         {"type", "directional"},
                                                         {"color", {0.7f, 0.8f, 1.0f}},
                                                         {"intensity", 0.5f}}};
  int light = 0;
  for (const V3f& direction : {sun, fill}) {
    V3f x, y;
    frame_around(-direction, &x, &y);
    nodes.push_back({{"name", light == 0 ? "sun" : "fill"},
                     {"matrix", node_matrix(x, y, -direction, V3f(0.0f))},
                     {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
    ++light;
  }

  for (size_t i = 0; i < flock.obstacles.size(); ++i) {
    const SphereObstacle& s = flock.obstacles[i];
    nodes.push_back(
        {{"name", "sphere " + std::to_string(i)},
         {"translation", {s.centre.x, s.centre.y, s.centre.z}},
         {"extensions",
          {{"PRISM_sphere",
            {{"radius", s.radius}, {"material", 1 + i % std::size(kSphereColours)}}}}}});
  }
  const float r = flock.boid_radius;
  for (size_t i = 0; i < positions.size(); ++i) {
    const float speed = velocities[i].length();
    const V3f f = speed > 0.0f ? velocities[i] / speed : V3f(1.0f, 0.0f, 0.0f);
    V3f x, y;
    frame_around(f, &x, &y);
    nodes.push_back({{"name", "boid " + std::to_string(i)},
                     {"mesh", 0},
                     {"matrix", node_matrix(x * r, y * r, f * r, positions[i])}});
  }
  json roots = json::array();
  for (size_t i = 0; i < nodes.size(); ++i) roots.push_back(i);
  doc["nodes"] = nodes;
  doc["scenes"] = {{{"nodes", roots}}};
  return doc;
}

json clip_jobs(const ClipSettings& clip, const ClipLayout& layout) {
  json jobs = json::array();
  const auto relative = [&](const fs::path& p) {
    return p.lexically_relative(layout.dir).string();
  };
  for (int frame = 0; frame < layout.frames; ++frame)
    jobs.push_back({{"name", layout.frame_name(frame)},
                    {"scene", relative(layout.scene(frame))},
                    {"output", relative(layout.exr(frame))},
                    {"preview", relative(layout.preview(frame))}});
  return {{"version", 1},
          {"defaults",
           {{"resolution", std::to_string(clip.width) + "x" + std::to_string(clip.height)},
            {"spp", clip.spp},
            {"integrator", clip.integrator},
            {"background", clip.background}}},
          {"jobs", jobs}};
}

ClipLayout write_clip(const FlockConfig& config, const fs::path& dir, int threads,
                      const std::function<void(int)>& frame_written) {
  check_clip_settings(config.clip);
  Flock flock(config.flock, threads);
  const ClipLayout layout{dir, config.clip.frames};
  for (const char* sub : {"scenes", "exr", "png"}) fs::create_directories(layout.dir / sub);
  flock.run(config.clip.warmup_steps);
  for (int frame = 0; frame < layout.frames; ++frame) {
    if (frame > 0) flock.run(config.clip.steps_per_frame);
    write_text_atomically(
        layout.scene(frame),
        frame_scene(config.flock, config.clip, flock.positions(), flock.velocities()).dump());
    if (frame_written) frame_written(frame);
  }
  write_text_atomically(layout.job_file(), clip_jobs(config.clip, layout).dump(1) + "\n");
  return layout;
}

}  // namespace prism
