// The scene's geometry in one Embree BVH: triangle meshes (baked into world space when a
// mesh is placed once, instanced when several nodes share it) and spheres in the mode the
// user chose. Answers the two questions integrators ask: the nearest hit, and whether a
// segment is blocked.
#pragma once

#include <memory>
#include <vector>

#include <Imath/ImathBox.h>
#include <Imath/ImathVec.h>
#include <embree3/rtcore.h>

#include "renderer/ray.h"
#include "renderer/scene_description.h"
#include "renderer/sphere_geometry.h"

namespace prism {

struct GeometryOptions {
  SphereOptions spheres;
  // Watertight triangle test and robust traversal (RTC_SCENE_FLAG_ROBUST), at some speed.
  bool robust = false;
};

struct SurfaceHit {
  float t = 0.0f;
  Imath::V3f position;          // on the surface, rebuilt from the primitive, not o + t d
  Imath::V3f geometric_normal;  // unit, world space, out of the front (authored) side
  Imath::V3f shading_normal;    // unit, on the same side as geometric_normal
  Imath::V2f uv{0.0f, 0.0f};
  int material = -1;       // index into the scene's materials, -1 = default
  bool back_face = false;  // the ray arrived from behind (e.g. from inside a sphere)
};

struct GeometryStatistics {
  size_t meshes_baked = 0;
  size_t mesh_instances = 0;
  size_t triangles = 0;  // as placed in the world, counting each instance
  size_t spheres = 0;
};

class EmbreeScene {
 public:
  // Throws std::runtime_error if Embree fails (with Embree's message).
  EmbreeScene(const SceneDescription& scene, const GeometryOptions& options);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  bool intersect(const Ray& ray, SurfaceHit* hit) const;
  // True if anything lies on the ray within (ray.tnear, ray.tfar).
  bool occluded(const Ray& ray) const;

  Imath::Box3f bounds() const { return bounds_; }
  const GeometryStatistics& statistics() const { return statistics_; }

 private:
  struct TriangleMesh;
  struct Prototype;
  struct Instance;
  struct GeometryRecord;

  static std::unique_ptr<TriangleMesh> copy_for_embree(const Primitive& p);
  unsigned attach_triangles(RTCScene scene, const TriangleMesh& mesh);
  void fill_triangle_hit(const TriangleMesh& mesh, const RTCRayHit& rh, SurfaceHit* hit) const;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<std::unique_ptr<TriangleMesh>> baked_;
  std::vector<std::unique_ptr<Prototype>> prototypes_;
  std::vector<Instance> instances_;
  std::vector<GeometryRecord> records_;  // by top-level geomID
  std::vector<Sphere> spheres_;
  unsigned analytic_spheres_geom_ = RTC_INVALID_GEOMETRY_ID;
  Imath::Box3f bounds_;
  GeometryStatistics statistics_;
};

}  // namespace prism
