#include "renderer/geometry/sphere_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace prism {
namespace {

void check_level(int level) {
  if (level < 0 || level > kMaxSphereMeshLevel) {
    throw std::out_of_range("sphere mesh level " + std::to_string(level) + " is not in 0.." +
                            std::to_string(kMaxSphereMeshLevel));
  }
}

// Both the mesh and tessellation_max_error place a new vertex with this function, so the
// error is measured on the very vertices the mesh has. a + b == b + a in IEEE arithmetic, so
// the order in which an edge is met does not matter.
V3d unit_midpoint(const V3d& a, const V3d& b) {
  return (a + b).normalized();
}

struct Icosahedron {
  std::array<V3d, 12> vertices;
  std::array<std::array<uint32_t, 3>, 20> faces;
};

// The 12 vertices are the cyclic permutations of (0, +-1, +-phi), edge length 2. The faces are
// found rather than typed in: exactly the triples of mutually adjacent vertices, turned to be
// counter-clockwise from outside. This cannot contain a mistyped index.
Icosahedron make_icosahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  Icosahedron ico;
  int n = 0;
  for (double s1 : {-1.0, 1.0}) {
    for (double s2 : {-phi, phi}) {
      ico.vertices[n++] = V3d(0.0, s1, s2);
      ico.vertices[n++] = V3d(s1, s2, 0.0);
      ico.vertices[n++] = V3d(s2, 0.0, s1);
    }
  }
  // Neighbours are 2 apart (squared 4); the next nearest are 2 phi apart (squared 10.5).
  auto adjacent = [&](int i, int j) { return (ico.vertices[i] - ico.vertices[j]).length2() < 5.0; };
  int f = 0;
  for (int i = 0; i < 12; ++i) {
    for (int j = i + 1; j < 12; ++j) {
      for (int k = j + 1; k < 12; ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        const V3d& a = ico.vertices[i];
        const V3d& b = ico.vertices[j];
        const V3d& c = ico.vertices[k];
        const bool outward = (b - a).cross(c - a).dot(a + b + c) > 0.0;
        ico.faces.at(f++) = outward
                                ? std::array<uint32_t, 3>{uint32_t(i), uint32_t(j), uint32_t(k)}
                                : std::array<uint32_t, 3>{uint32_t(i), uint32_t(k), uint32_t(j)};
      }
    }
  }
  if (f != 20) throw std::logic_error("icosahedron construction found " + std::to_string(f));
  for (V3d& v : ico.vertices) v.normalize();
  return ico;
}

const Icosahedron& icosahedron() {
  static const Icosahedron ico = make_icosahedron();
  return ico;
}

// Distance from the origin to the triangle (a, b, c) whose vertices are unit vectors. The
// origin's foot on the plane is then the circumcentre, which is inside an acute triangle;
// otherwise the nearest point is on an edge.
double distance_from_centre(const V3d& a, const V3d& b, const V3d& c) {
  const V3d n = (b - a).cross(c - a).normalized();
  const bool acute =
      (b - a).dot(c - a) > 0.0 && (a - b).dot(c - b) > 0.0 && (a - c).dot(b - c) > 0.0;
  if (acute) return std::abs(n.dot(a));
  auto segment = [](const V3d& p, const V3d& q) {
    const V3d e = q - p;
    const double s = std::clamp(-p.dot(e) / e.length2(), 0.0, 1.0);
    return (p + s * e).length();
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// Smallest distance from the centre over the sub-triangles of (a, b, c) after `level` splits,
// splitting exactly as make_unit_icosphere does.
double min_face_distance(const V3d& a, const V3d& b, const V3d& c, int level) {
  if (level == 0) return distance_from_centre(a, b, c);
  const V3d ab = unit_midpoint(a, b);
  const V3d bc = unit_midpoint(b, c);
  const V3d ca = unit_midpoint(c, a);
  return std::min({min_face_distance(a, ab, ca, level - 1), min_face_distance(ab, b, bc, level - 1),
                   min_face_distance(ca, bc, c, level - 1),
                   min_face_distance(ab, bc, ca, level - 1)});
}

}  // namespace

UnitIcosphere make_unit_icosphere(int level) {
  check_level(level);
  const Icosahedron& ico = icosahedron();
  UnitIcosphere mesh;
  const size_t final_vertices = 10 * (size_t(1) << (2 * level)) + 2;
  mesh.vertices.reserve(final_vertices);
  mesh.vertices.assign(ico.vertices.begin(), ico.vertices.end());
  for (const auto& f : ico.faces) mesh.indices.insert(mesh.indices.end(), f.begin(), f.end());

  for (int l = 0; l < level; ++l) {
    // One new vertex per edge, found again by the neighbouring triangle through this map.
    std::unordered_map<uint64_t, uint32_t> midpoints;
    midpoints.reserve(mesh.indices.size() / 2);
    auto midpoint = [&](uint32_t i, uint32_t j) {
      const uint64_t key = (uint64_t(std::min(i, j)) << 32) | std::max(i, j);
      auto [it, inserted] = midpoints.try_emplace(key, uint32_t(mesh.vertices.size()));
      if (inserted) mesh.vertices.push_back(unit_midpoint(mesh.vertices[i], mesh.vertices[j]));
      return it->second;
    };
    std::vector<uint32_t> split;
    split.reserve(mesh.indices.size() * 4);
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
      const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      // Each child keeps its parent's turning direction, so all stay counter-clockwise.
      split.insert(split.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    mesh.indices = std::move(split);
  }
  return mesh;
}

Primitive tessellate_sphere(const Sphere& s, int level) {
  const UnitIcosphere unit = make_unit_icosphere(level);
  Primitive prim;
  prim.positions.reserve(unit.vertices.size());
  prim.normals.reserve(unit.vertices.size());
  for (const V3d& u : unit.vertices) {
    const V3d p = s.centre + s.radius * u;
    prim.positions.emplace_back(float(p.x), float(p.y), float(p.z));
    prim.normals.emplace_back(float(u.x), float(u.y), float(u.z));
  }
  prim.indices = unit.indices;
  prim.material = s.material;
  return prim;
}

double tessellation_max_error(double radius, int level) {
  check_level(level);
  // The 20 faces are congruent, so one face's subdivision has the worst triangle.
  const Icosahedron& ico = icosahedron();
  const auto& f = ico.faces[0];
  const double h =
      min_face_distance(ico.vertices[f[0]], ico.vertices[f[1]], ico.vertices[f[2]], level);
  return radius * (1.0 - h);
}

}  // namespace prism
