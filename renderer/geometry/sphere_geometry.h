// The three ways Prism can hand an analytic sphere (scene_description.h's Sphere) to Embree.
// docs/spheres-rendering.md compares them.
#pragma once

#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "renderer/scene_description.h"

namespace prism {

enum class SphereMode {
  analytic,       // Embree user geometry running intersect_sphere (sphere_intersect.h)
  mesh,           // an icosphere of triangles (sphere_mesh.h)
  embree_points,  // Embree's built-in RTC_GEOMETRY_TYPE_SPHERE_POINT
};

struct SphereOptions {
  SphereMode mode = SphereMode::analytic;
  int mesh_level = 3;  // subdivisions of the icosahedron, used by SphereMode::mesh only
};

// Accepts "analytic", "mesh" (level 3), "mesh:N" with 0 <= N <= kMaxSphereMeshLevel, and
// "embree-points". On failure returns false, leaves *options alone and, if error is not null,
// says what was wrong.
bool parse_sphere_options(const std::string& text, SphereOptions* options, std::string* error);

// The inverse of parse_sphere_options; a mesh always carries its level ("mesh:3") so the
// string round-trips whatever the default is.
std::string to_string(const SphereOptions& options);

// Adds every sphere to scene as one Embree user geometry whose primID is the index into
// spheres, and returns its geomID. The scene still needs rtcCommitScene.
//
// Hits report what Embree's triangles report: tfar, Ng = hit point - centre (unnormalised,
// object = world space, pointing out of the sphere also when the ray starts inside), u = v = 0,
// primID, geomID and the instance stack. A ray is inside-to-outside exactly when
// dot(dir, Ng) > 0. Intersection and occlusion filter functions (geometry and context) are
// called as for built-in geometry.
//
// Ownership: Embree 3 has no destructor hook for geometry user data and refuses buffers on
// user geometries, so the float copy of the spheres the callbacks read is a heap block set as
// the geometry's user data. It lives until release_analytic_spheres(scene, geomID) is called,
// which must happen after the last ray query on scene and before the scene is released (the
// geometry must not be traced afterwards). Not calling it leaks the block.
unsigned attach_analytic_spheres(RTCDevice device, RTCScene scene,
                                 const std::vector<Sphere>& spheres);

// Frees the data attach_analytic_spheres gave geomID. Calling it twice is harmless.
void release_analytic_spheres(RTCScene scene, unsigned geom_id);

// Adds every sphere to scene as one RTC_GEOMETRY_TYPE_SPHERE_POINT geometry (primID = index),
// returning its geomID. Embree owns the vertex buffer; nothing to release. Embree reports
// tfar, an unnormalised Ng pointing out of the sphere, u = v = 0.
unsigned attach_point_spheres(RTCDevice device, RTCScene scene, const std::vector<Sphere>& spheres);

}  // namespace prism
