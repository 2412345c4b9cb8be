// Meshes that are tessellated spheres, found from their vertices so that `prism info` can
// report them and `prism render --detect-spheres` can swap them for the analytic sphere
// (docs/spheres.md, "Spheres hidden in meshes").
//
// It works on SceneDescription, beside scene_defaults.h, because it is a rewrite of the scene
// that any loader's output can get, not a part of reading glTF.
//
// A placement (MeshInstance) of a mesh is a sphere when, in world space:
// - the least-squares sphere through its vertices (algebraic fit, refined by Gauss-Newton on
//   the geometric distances, all in double) leaves no vertex further than `tolerance` x radius
//   from its surface; a non-uniform scale in the node's transform makes an ellipsoid, which
//   fails here;
// - it has at least `min_vertices` distinct positions;
// - it is closed and covers the sphere once: after welding positions closer than 1e-6 of
//   the mesh's size (UV and normal seams, poles), every edge is shared by exactly two triangles
//   with opposite directions, every triangle faces away from the centre with its plane at least
//   `min_facet_distance` x radius from it (fine enough that the mesh means a sphere, not a
//   polyhedron: this rejects a cube or an octahedron, whose vertices lie on a sphere exactly), and
//   the solid angles of the triangles seen from the centre add up to 4 pi. A hemisphere, a cap, or
//   a sphere with a triangle missing fails.
// Each placement of an instanced mesh is checked on its own, in its own world transform.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "renderer/scene_description.h"

namespace prism {

struct SphereDetectionOptions {
  double tolerance = 1e-3;          // largest |distance to centre - radius| / radius
  size_t min_vertices = 20;         // distinct positions
  double min_facet_distance = 0.9;  // every facet's plane >= this x radius from the centre
};

// What keeps a sphere-shaped placement from being replaced: the analytic sphere has one
// material and no texture coordinates, vertex colours or tangents, so a mesh whose look
// depends on them would change.
enum class SphereReplaceBlocker { none, several_materials, textured_material, vertex_colours };

struct SphereCandidate {
  size_t instance = 0;  // index into SceneDescription::instances
  int mesh = -1;
  V3d centre{0.0, 0.0, 0.0};  // world space
  double radius = 0.0;
  double deviation = 0.0;  // largest |distance to centre - radius| / radius over the vertices
  int material = -1;       // the material all its primitives share
  SphereReplaceBlocker blocker = SphereReplaceBlocker::none;
};

// Every placement that is a sphere by the rules above, in instance order.
std::vector<SphereCandidate> find_sphere_meshes(const SceneDescription& scene,
                                                const SphereDetectionOptions& options);

// Turns each candidate without a blocker into an analytic Sphere (centre, radius, the mesh's
// material, the node's name) and removes its MeshInstance; the mesh stays for its other
// placements. `candidates` must come from find_sphere_meshes on this scene. Returns the ones
// replaced, their `instance` still the index they had before the removal.
std::vector<SphereCandidate> replace_sphere_meshes(SceneDescription* scene,
                                                   const std::vector<SphereCandidate>& candidates);

// "several materials", ... for messages; "" for none.
const char* to_string(SphereReplaceBlocker blocker);

// "mesh [2] 'Ball' (node 'Ball'): centre (x, y, z), radius r, deviation d", as info and render
// print a candidate.
std::string describe_sphere_candidate(const SceneDescription& scene, const SphereCandidate& c);

}  // namespace prism
