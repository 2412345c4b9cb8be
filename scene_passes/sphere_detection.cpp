#include "scene_passes/sphere_detection.h"

#include <cstdio>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <vector>

#include <Imath/ImathBox.h>
#include <Imath/ImathMatrix.h>

namespace prism {
namespace {

constexpr double kFourPi = 4.0 * 3.14159265358979323846;
// The solid angles of a closed surface around a point add up to exactly 4 pi times its
// winding number; this only absorbs the rounding of a sum of double atan2's.
constexpr double kSolidAngleTolerance = 1e-6;
constexpr int kGaussNewtonSteps = 4;

// A mesh's triangles over distinct positions. Exporters split vertices at UV and normal
// seams, and generators leave the copies of a pole a few ulps apart (sin(pi) is not 0), so
// positions closer than kWeldDistance of the mesh's size are one; a real crack is wider.
constexpr double kWeldDistance = 1e-6;

struct WeldedMesh {
  std::vector<V3d> positions;
  std::vector<std::array<uint32_t, 3>> triangles;  // without degenerate (repeated-vertex) ones
  bool closed = false;  // every edge in exactly two triangles, in opposite directions
  int material = -1;
  SphereReplaceBlocker blocker = SphereReplaceBlocker::none;
};

using Cell = std::array<int64_t, 3>;

// One index per cell, the first position seen in it, by open addressing in a table sized
// once for every position the mesh can add: the lookups a std::unordered_map gave, without a
// node allocation per cell and a pointer chase per probe (27 probes a position).
class CellTable {
 public:
  explicit CellTable(size_t most) {
    size_t n = 16;
    while (n < 2 * most) n <<= 1;
    slots_.resize(n);
    mask_ = n - 1;
  }
  const uint32_t* find(const Cell& c) const {
    for (size_t i = slot(c);; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.index == kEmpty) return nullptr;
      if (s.cell == c) return &s.index;
    }
  }
  void insert(const Cell& c, uint32_t index) {  // for a cell not in the table
    size_t i = slot(c);
    while (slots_[i].index != kEmpty) i = (i + 1) & mask_;
    slots_[i] = Slot{c, index};
  }

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;
  struct Slot {
    Cell cell{};
    uint32_t index = kEmpty;
  };
  size_t slot(const Cell& c) const {
    uint64_t h = 1469598103934665603ull;
    for (int64_t v : c) h = (h ^ static_cast<uint64_t>(v)) * 1099511628211ull;
    h ^= h >> 29;  // the multiplications carry upwards only: bring the high bits down
    h *= 0xbf58476d1ce4e5b9ull;
    h ^= h >> 32;
    return static_cast<size_t>(h) & mask_;
  }
  std::vector<Slot> slots_;
  size_t mask_ = 0;
};

// Positions on a grid of cells kWeldDistance x size wide; a position joins one already seen
// in its own or a neighbouring cell within a cell's width (so two copies straddling a cell
// border are still found).
class Welder {
 public:
  Welder(double cell, size_t most_positions) : cell_(cell), cells_(most_positions) {}
  uint32_t index(const V3d& p, std::vector<V3d>* positions) {
    const Cell c{std::llround(p.x / cell_), std::llround(p.y / cell_), std::llround(p.z / cell_)};
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const uint32_t* found = cells_.find(Cell{c[0] + dx, c[1] + dy, c[2] + dz});
          if (!found) continue;
          const V3d d = (*positions)[*found] - p;
          if (std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) <= cell_) return *found;
        }
    const uint32_t i = static_cast<uint32_t>(positions->size());
    positions->push_back(p);
    cells_.insert(c, i);
    return i;
  }

 private:
  double cell_;
  CellTable cells_;
};

bool has_texture(const MaterialDescription& m) {
  return m.base_colour_texture >= 0 || m.metallic_roughness_texture >= 0 ||
         m.emissive_texture >= 0 || m.normal_texture >= 0 || m.occlusion_texture >= 0 ||
         m.clearcoat_texture >= 0 || m.clearcoat_roughness_texture >= 0 ||
         m.clearcoat_normal_texture >= 0 || m.sheen_colour_texture >= 0 ||
         m.sheen_roughness_texture >= 0;
}

WeldedMesh weld(const SceneDescription& scene, const Mesh& mesh) {
  WeldedMesh w;
  Imath::Box3d bounds;
  for (const Primitive& p : mesh.primitives)
    for (uint32_t i : p.indices) bounds.extendBy(V3d(p.positions[i]));
  const double size = bounds.isEmpty() ? 0.0 : (bounds.max - bounds.min).length();
  if (!(size > 0.0) || !std::isfinite(size)) return w;  // not closed
  size_t vertices = 0;                                  // each vertex adds at most one position
  for (const Primitive& p : mesh.primitives) vertices += p.positions.size();
  Welder welder(kWeldDistance * size, vertices);
  std::set<int> materials;
  bool colours = false;
  for (const Primitive& p : mesh.primitives) {
    materials.insert(p.material);
    colours = colours || !p.colours.empty();
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
      std::array<uint32_t, 3> tri;
      for (size_t k = 0; k < 3; ++k)
        tri[k] = welder.index(V3d(p.positions[p.indices[t + k]]), &w.positions);
      // Collapsed quads at the poles of latitude/longitude spheres are expected.
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
      w.triangles.push_back(tri);
    }
  }
  // Closed: every directed edge once, and its reverse once. Sorted keys say both in
  // O(n log n) with no map: a repeated key is an edge used twice the same way.
  std::vector<uint64_t> directed;
  directed.reserve(w.triangles.size() * 3);
  const auto key = [](uint32_t a, uint32_t b) { return (uint64_t{a} << 32) | b; };
  for (const auto& t : w.triangles)
    for (size_t k = 0; k < 3; ++k) directed.push_back(key(t[k], t[(k + 1) % 3]));
  std::sort(directed.begin(), directed.end());
  w.closed = !w.triangles.empty() &&
             std::adjacent_find(directed.begin(), directed.end()) == directed.end();
  for (size_t i = 0; w.closed && i < directed.size(); ++i) {
    const uint64_t edge = directed[i];
    w.closed = std::binary_search(directed.begin(), directed.end(),
                                  key(static_cast<uint32_t>(edge), edge >> 32));
  }
  w.material = materials.empty() ? -1 : *materials.begin();
  if (materials.size() > 1) {
    w.blocker = SphereReplaceBlocker::several_materials;
  } else if (w.material >= 0 && static_cast<size_t>(w.material) < scene.materials.size() &&
             has_texture(scene.materials[static_cast<size_t>(w.material)])) {
    w.blocker = SphereReplaceBlocker::textured_material;
  } else if (colours) {
    w.blocker = SphereReplaceBlocker::vertex_colours;
  }
  return w;
}

// Solves the symmetric 4x4 system a x = b; nothing when a is (nearly) singular, as for
// points on a plane or a line. a is scaled to O(1) entries by the callers.
std::optional<std::array<double, 4>> solve4(const Imath::M44d& a, const std::array<double, 4>& b) {
  if (!(std::abs(a.determinant()) > 1e-14)) return std::nullopt;
  const Imath::M44d inverse = a.gjInverse();
  std::array<double, 4> x{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      x[static_cast<size_t>(i)] += inverse[i][j] * b[static_cast<size_t>(j)];
  for (double v : x)
    if (!std::isfinite(v)) return std::nullopt;
  return x;
}

struct FittedSphere {
  V3d centre;
  double radius;
};

// Least-squares sphere: the algebraic fit |q|^2 = 2 c.q + k (linear, exact for points on a
// sphere) as the start, then Gauss-Newton on the geometric residuals |q - c| - r. Points are
// moved to their mean and scaled to the unit ball first, so the normal equations stay well
// conditioned wherever and however large the sphere is.
std::optional<FittedSphere> fit_sphere(const std::vector<V3d>& points) {
  const double n = static_cast<double>(points.size());
  V3d mean(0.0);
  for (const V3d& p : points) mean += p;
  mean /= n;
  double scale = 0.0;
  for (const V3d& p : points) scale = std::max(scale, (p - mean).length());
  if (!(scale > 0.0) || !std::isfinite(scale)) return std::nullopt;
  std::vector<V3d> q;
  q.reserve(points.size());
  for (const V3d& p : points) q.push_back((p - mean) / scale);

  Imath::M44d a(0.0);
  std::array<double, 4> b{};
  for (const V3d& p : q) {
    const double row[4] = {p.x, p.y, p.z, 1.0};
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) a[i][j] += row[i] * row[j] / n;
      b[static_cast<size_t>(i)] += row[i] * p.length2() / n;
    }
  }
  const auto algebraic = solve4(a, b);
  if (!algebraic) return std::nullopt;
  V3d c((*algebraic)[0] / 2.0, (*algebraic)[1] / 2.0, (*algebraic)[2] / 2.0);
  const double r2 = (*algebraic)[3] + c.length2();
  if (!(r2 > 0.0)) return std::nullopt;
  double r = std::sqrt(r2);

  for (int step = 0; step < kGaussNewtonSteps; ++step) {
    Imath::M44d jtj(0.0);
    std::array<double, 4> jtr{};
    for (const V3d& p : q) {
      const V3d d = p - c;
      const double length = d.length();
      if (!(length > 0.0)) return std::nullopt;
      const V3d u = d / length;
      const double jac[4] = {-u.x, -u.y, -u.z, -1.0};
      const double residual = length - r;
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) jtj[i][j] += jac[i] * jac[j] / n;
        jtr[static_cast<size_t>(i)] -= jac[i] * residual / n;
      }
    }
    const auto delta = solve4(jtj, jtr);
    if (!delta) return std::nullopt;
    c += V3d((*delta)[0], (*delta)[1], (*delta)[2]);
    r += (*delta)[3];
    if (!(r > 0.0)) return std::nullopt;
  }
  return FittedSphere{mean + c * scale, r * scale};
}

// The solid angle of triangle (a, b, c) seen from the origin, signed by its orientation
// (Van Oosterom and Strackee 1983).
double solid_angle(const V3d& a, const V3d& b, const V3d& c) {
  const double la = a.length(), lb = b.length(), lc = c.length();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(numerator, denominator);
}

// The world-space tests of one placement; the candidate, or nothing.
std::optional<SphereCandidate> check_placement(const WeldedMesh& w, const M44d& object_to_world,
                                               const SphereDetectionOptions& options) {
  std::vector<V3d> world(w.positions.size());
  for (size_t i = 0; i < w.positions.size(); ++i) {
    object_to_world.multVecMatrix(w.positions[i], world[i]);
    if (!std::isfinite(world[i].x) || !std::isfinite(world[i].y) || !std::isfinite(world[i].z))
      return std::nullopt;
  }
  const auto fit = fit_sphere(world);
  if (!fit) return std::nullopt;
  double deviation = 0.0;
  for (const V3d& p : world)
    deviation = std::max(deviation, std::abs((p - fit->centre).length() - fit->radius));
  deviation /= fit->radius;
  if (!(deviation <= options.tolerance)) return std::nullopt;

  double total_solid_angle = 0.0;
  int orientation = 0;
  for (const auto& t : w.triangles) {
    const V3d a = world[t[0]] - fit->centre, b = world[t[1]] - fit->centre,
              c = world[t[2]] - fit->centre;
    const V3d normal = (b - a).cross(c - a);
    const double length = normal.length();
    if (!(length > 0.0)) return std::nullopt;
    const double distance = normal.dot(a) / length;  // of the facet's plane from the centre
    const int side = distance > 0.0 ? 1 : -1;
    if (orientation == 0) orientation = side;
    if (side != orientation || std::abs(distance) < options.min_facet_distance * fit->radius)
      return std::nullopt;
    total_solid_angle += solid_angle(a, b, c);
  }
  if (!(std::abs(std::abs(total_solid_angle) - kFourPi) <= kSolidAngleTolerance * kFourPi))
    return std::nullopt;

  SphereCandidate candidate;
  candidate.centre = fit->centre;
  candidate.radius = fit->radius;
  candidate.deviation = deviation;
  candidate.material = w.material;
  candidate.blocker = w.blocker;
  return candidate;
}

}  // namespace

std::vector<SphereCandidate> find_sphere_meshes(const SceneDescription& scene,
                                                const SphereDetectionOptions& options) {
  std::vector<SphereCandidate> found;
  // Welded once per mesh, on first use: the topology does not depend on the placement.
  std::vector<std::optional<WeldedMesh>> welded(scene.meshes.size());
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& instance = scene.instances[i];
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= scene.meshes.size()) continue;
    auto& w = welded[static_cast<size_t>(instance.mesh)];
    if (!w) w = weld(scene, scene.meshes[static_cast<size_t>(instance.mesh)]);
    if (!w->closed || w->positions.size() < options.min_vertices) continue;
    auto candidate = check_placement(*w, instance.object_to_world, options);
    if (!candidate) continue;
    candidate->instance = i;
    candidate->mesh = instance.mesh;
    found.push_back(*candidate);
  }
  return found;
}

std::vector<SphereCandidate> replace_sphere_meshes(SceneDescription* scene,
                                                   const std::vector<SphereCandidate>& candidates) {
  std::vector<SphereCandidate> replaced;
  for (const SphereCandidate& c : candidates) {
    if (c.blocker != SphereReplaceBlocker::none) continue;
    const MeshInstance& instance = scene->instances[c.instance];
    Sphere sphere;
    sphere.centre = c.centre;
    sphere.radius = c.radius;
    sphere.material = c.material;
    sphere.node_name = instance.node_name.empty() ? scene->meshes[static_cast<size_t>(c.mesh)].name
                                                  : instance.node_name;
    scene->spheres.push_back(sphere);
    replaced.push_back(c);
  }
  // From the back, so the indices still to erase stay valid.
  for (auto it = replaced.rbegin(); it != replaced.rend(); ++it)
    scene->instances.erase(scene->instances.begin() + static_cast<std::ptrdiff_t>(it->instance));
  return replaced;
}

std::string describe_sphere_candidate(const SceneDescription& scene, const SphereCandidate& c) {
  const std::string& mesh = scene.meshes[static_cast<size_t>(c.mesh)].name;
  const std::string& node = scene.instances[c.instance].node_name;
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, ": centre (%.6g, %.6g, %.6g), radius %.6g, deviation %.3g",
                c.centre.x, c.centre.y, c.centre.z, c.radius, c.deviation);
  return "mesh [" + std::to_string(c.mesh) + "] '" + mesh + "' (node '" + node + "')" + numbers;
}

const char* to_string(SphereReplaceBlocker blocker) {
  switch (blocker) {
    case SphereReplaceBlocker::none:
      return "";
    case SphereReplaceBlocker::several_materials:
      return "its primitives have different materials";
    case SphereReplaceBlocker::textured_material:
      return "its material is textured, and an analytic sphere has no texture coordinates";
    case SphereReplaceBlocker::vertex_colours:
      return "it has vertex colours, which an analytic sphere cannot carry";
  }
  return "";
}

}  // namespace prism
