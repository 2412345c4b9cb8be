// Spheres as triangle meshes (SphereMode::mesh): an icosahedron whose faces are split into
// four `level` times, every new vertex pushed out onto the sphere.
//
// An icosphere rather than a latitude/longitude grid because its triangles are nearly equal
// and nearly equilateral, so one level bounds the error everywhere instead of wasting
// triangles at the poles; and it needs no seam, so every vertex is shared.
//
// How far the mesh is from the sphere: all vertices lie on the sphere and the mesh is convex,
// so the mesh is inside the sphere and the largest gap is over the face that is largest on
// the sphere: r - h, h being that face's plane distance from the centre, i.e. the sagitta
// r (1 - cos theta) of the face's angular circumradius theta. Level 0 has theta = 37.4 deg
// (error 0.205 r); the first splits also even out the triangles, so the error falls by 3.1x
// and 3.7x before settling at 4x per level: error(level) ~= 0.29 r / 4^level from level 3
// on (0.0045 r at level 3, 0.00028 r at 5, 4.5e-6 r at 8). tessellation_max_error gives the
// exact value.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/scene_description.h"

namespace prism {

// Level 8 is 1,310,720 triangles (about 40 MB once Embree has built its BVH) for an error of
// 4.5e-6 r, a fraction of a pixel for any sphere that fits on screen; every further level costs
// four times the memory of the one before.
inline constexpr int kMaxSphereMeshLevel = 8;

// The subdivided icosahedron on the unit sphere, in double: vertices are unit vectors (to the
// last bit of double), triangles are counter-clockwise seen from outside, every vertex is
// shared by all triangles that touch it. 10 * 4^level + 2 vertices, 20 * 4^level triangles.
struct UnitIcosphere {
  std::vector<V3d> vertices;
  std::vector<uint32_t> indices;  // 3 per triangle
};

// Throws std::out_of_range unless 0 <= level <= kMaxSphereMeshLevel.
UnitIcosphere make_unit_icosphere(int level);

// The icosphere placed on s in world space: position = centre + radius * unit vector and
// normal = unit vector, both worked out in double and then rounded to float; the material is
// s.material; no UVs (a sphere has no seam-free UV layout, and none is asked for). Throws
// std::out_of_range for a level make_unit_icosphere rejects.
Primitive tessellate_sphere(const Sphere& s, int level);

// The largest distance between the level-`level` icosphere and the sphere of that radius
// (Hausdorff distance, in radius units times radius), as exactly as double gives it. It is
// also the largest error of a hit distance t for a ray perpendicular to the surface, and
// the angle between a face normal and the true normal under it is at most acos(1 - err / r).
// Throws std::out_of_range for a level make_unit_icosphere rejects.
double tessellation_max_error(double radius, int level);

}  // namespace prism
