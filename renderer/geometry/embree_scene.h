// The scene's geometry in one Embree BVH: triangle meshes (baked into world space when a
// mesh is placed once, instanced when several nodes share it) and spheres in the mode the
// user chose. Answers the two questions integrators ask: the nearest hit, and whether a
// segment is blocked.
//
// The renderer does not trust its input (docs/stress-shading.md):
//   - triangles that cannot be hit meaningfully (an index out of range, a repeated index,
//     zero area, a non-finite vertex) are dropped at build time and counted, and vertex
//     normals that are zero or not finite are rebuilt from the faces around them
//     (renderer/geometry/mesh_preparation.h);
//   - rays with a non-finite origin, direction or range never reach Embree.
//
// World origin: Embree works in float, whose spacing at 1e6 m is 6 cm. Everything is moved
// by -GeometryOptions::world_origin in double before it is rounded to float, so with the
// origin at the camera every ray, hit and light lives near 0 whatever the scene's absolute
// coordinates. Hit positions and bounds are in this shifted frame; the camera and the lights
// must be shifted by the same point (Camera's world_origin argument, RenderScene).
//
// Geometry kinds: each top-level Embree geometry has a GeometryRecord whose kind says how its
// hits are read. A new kind takes an entry in GeometryRecord::Kind, one add_* function that
// attaches it and records it (called from the constructor), and one resolve_*_hit function
// that resolve_hit's switch calls for it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Imath/ImathBox.h>
#include <Imath/ImathVec.h>
#include <embree3/rtcore.h>

#include "renderer/enum_names.h"
#include "renderer/geometry/alpha_filter.h"
#include "renderer/geometry/embree_device.h"
#include "renderer/geometry/ray.h"
#include "renderer/geometry/sphere_geometry.h"
#include "renderer/geometry/surface_hit.h"
#include "renderer/scene_description.h"

namespace prism {

// Embree's BVH build quality (RTC_BUILD_QUALITY_*): a better tree traces faster and takes
// longer to build; which pays depends on how many rays the tree will see
// (docs/benchmarks.md, "BVH build quality and flags").
// `automatic` is a request, settled by automatic_build_quality before anything is built.
enum class BuildQuality { low, medium, high, automatic };
inline constexpr EnumName<BuildQuality> kBuildQualityNames[] = {{BuildQuality::low, "low"},
                                                                {BuildQuality::medium, "medium"},
                                                                {BuildQuality::high, "high"},
                                                                {BuildQuality::automatic, "auto"}};
constexpr std::span<const EnumName<BuildQuality>> enum_names(BuildQuality) {
  return kBuildQualityNames;
}
// `automatic` builds as medium.
RTCBuildQuality embree_build_quality(BuildQuality quality);

// The build that costs least in total for `expected_rays` rays through `primitives`
// primitives: a build's time grows with the primitives and a better tree saves time per ray,
// so below kLowBuildRaysPerPrimitive rays per primitive LOW's faster build outweighs its
// slower traversal, above kHighBuildRaysPerPrimitive HIGH's slower build pays, and MEDIUM
// between (the crossovers measured in docs/benchmarks.md, "Automatic build quality").
inline constexpr double kLowBuildRaysPerPrimitive = 8.0;
inline constexpr double kHighBuildRaysPerPrimitive = 64.0;
BuildQuality automatic_build_quality(double expected_rays, double primitives);

struct GeometryOptions {
  SphereOptions spheres;
  // Watertight triangle test and robust traversal (RTC_SCENE_FLAG_ROBUST), at some speed.
  bool robust = false;
  // For every BVH: the top-level scene and the prototypes of instanced meshes. HIGH (spatial
  // splits) built 2.2 to 5 times slower than MEDIUM for at most 3 % fewer instructions per
  // render; LOW built and traced as MEDIUM.
  BuildQuality build_quality = BuildQuality::medium;
  // RTC_SCENE_FLAG_COMPACT: 40 % less BVH memory, traced 10 to 16 % slower (1M triangles).
  // BuildQuality::low always builds compact.
  bool compact = false;
  // The world-space point that becomes (0, 0, 0) for Embree and the integrators; (0, 0, 0)
  // keeps world coordinates. The camera's position is the best choice.
  Imath::V3d world_origin{0.0, 0.0, 0.0};
};

struct PreparedMesh;

struct GeometryStatistics {
  size_t meshes_baked = 0;
  size_t mesh_instances = 0;
  size_t triangles = 0;  // handed to Embree, as placed in the world, counting each instance
  size_t spheres = 0;
  // Dropped at build time (counting each instance): an index out of range, a repeated
  // index or zero area; a non-finite vertex or node transform.
  size_t degenerate_triangles = 0;
  size_t nonfinite_triangles = 0;
  size_t normals_repaired = 0;  // zero or non-finite vertex normals rebuilt from the faces
};

// A triangle or sphere whose material emits, in the shifted frame: what the area lights are
// made of (renderer/shading/area_lights.h). A hit on it names its index (SurfaceHit::emitter).
struct EmissivePrimitive {
  enum class Shape : uint8_t { triangle, sphere };
  Shape shape = Shape::triangle;
  Imath::V3f corners[3] = {
      Imath::V3f(0.0f), Imath::V3f(0.0f),
      Imath::V3f(0.0f)};  // a triangle's, counter-clockwise from the front; a sphere's centre first
  float radius = 0.0f;    // sphere
  int material = -1;
  // Where a sampled point reads an emissive texture: the mesh's attributes (null without
  // any) and the triangle's vertex indices into them.
  const VertexAttributes* attributes = nullptr;
  uint32_t vertices[3] = {0, 0, 0};
};

class EmbreeScene {
 public:
  // Throws std::runtime_error if Embree fails (with Embree's message). `materials` are the
  // scene's materials resolved (RenderScene's, one per SceneDescription::materials entry),
  // whose base colour alpha the filters of MASK and BLEND materials read
  // (renderer/geometry/alpha_filter.h); they must outlive this scene. Without them only the
  // alpha factor counts. The scene keeps `device` (not null) alive while it lives.
  EmbreeScene(std::shared_ptr<EmbreeDevice> device, const SceneDescription& scene,
              const GeometryOptions& options, const std::vector<Material>& materials = {});
  // On a device of its own.
  EmbreeScene(const SceneDescription& scene, const GeometryOptions& options,
              const std::vector<Material>& materials = {});
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // A ray with a non-finite origin, direction, tnear or a NaN tfar hits nothing...
  bool intersect(const Ray& ray, SurfaceHit* hit) const;
  // True if anything lies on the ray within (ray.tnear, ray.tfar). ...and is occluded, so
  // that a broken shadow ray can darken a pixel but never light it.
  bool occluded(const Ray& ray) const;

  // The nearest hits of `count` (at most kPacketSize) coherent rays, such as the camera
  // rays of a 4 x 4 pixel block, traced as one Embree packet (rtcIntersect16): Embree visits
  // each BVH node once for all of them. found[i] says whether rays[i] hit; the hits are
  // those intersect() finds, culling and filters included, except that a ray meeting a
  // shared triangle edge within rounding may get the other triangle
  // (tests/packet_trace_test.cpp).
  static constexpr int kPacketSize = 16;
  void intersect_packet(const Ray* rays, int count, SurfaceHit* hits, bool* found) const;
  // occluded() for `count` (at most kPacketSize) rays at once (rtcOccluded16), such as the
  // shadow rays of a packet of camera hits towards one light.
  void occluded_packet(const Ray* rays, int count, bool* blocked) const;

  // In the shifted frame (world minus world_origin).
  Imath::Box3f bounds() const { return bounds_; }
  const Imath::V3d& world_origin() const { return world_origin_; }
  const GeometryStatistics& statistics() const { return statistics_; }
  // Every primitive whose material emits (Material::emissive non-zero), in a fixed order: baked
  // meshes, instances and spheres as they are attached, each mesh's triangles in order.
  const std::vector<EmissivePrimitive>& emitters() const { return emitters_; }
  const std::shared_ptr<EmbreeDevice>& device() const { return device_; }

 private:
  struct Prototype;
  struct Instance;
  struct GeometryRecord;
  struct MeshPlan;

  // The constructor's steps, in its order.
  void begin_scenes(const SceneDescription& scene, const GeometryOptions& options);
  MeshPlan plan_meshes(const SceneDescription& scene);
  static void prepare_meshes(MeshPlan* plan);  // in parallel
  void add_prototypes(const SceneDescription& scene, const std::vector<Material>& materials,
                      MeshPlan* plan);
  void add_placed_meshes(const SceneDescription& scene, const std::vector<Material>& materials,
                         MeshPlan* plan);
  // One per geometry kind; each attaches to the top-level scene and records what it added.
  void add_baked_mesh(const SceneDescription& scene, const std::vector<Material>& materials,
                      std::unique_ptr<PreparedMesh> mesh);
  void add_instance(const Prototype& prototype, const MeshInstance& node, const M44d& to_shifted,
                    const std::vector<Material>& materials);

  RTCScene new_scene() const;  // with the flags and build quality every BVH here shares
  void record(unsigned geom_id, const GeometryRecord& record);
  // Appends the mesh's triangles to emitters_ if its material emits; returns the first one's
  // index, or kNoEmitter.
  uint32_t add_emitters(const PreparedMesh& mesh, const std::vector<Material>& materials,
                        const Imath::M44f* object_to_world);
  void add_spheres(const std::vector<Sphere>& spheres, const SphereOptions& options,
                   const std::vector<Material>& materials);
  // `filter`: the mesh's alpha and culling rule, or null for none (spheres).
  unsigned attach_triangles(RTCScene scene, const PreparedMesh& mesh, const SurfaceFilter* filter);
  // The filter the mesh's material needs, kept in filters_; null when it needs none.
  const SurfaceFilter* surface_filter(const SceneDescription& scene, const PreparedMesh& mesh,
                                      const std::vector<Material>& materials);
  static bool single_sided(const SceneDescription& scene, int material);
  void release();

  // Whether `rh`, found for `ray` without culling, is a back face a camera ray must not see.
  bool culled_back_face(const Ray& ray, const RTCRayHit& rh) const;
  // Rare: the nearest surface was such a back face; traces `ray` again with the culling
  // filter on (renderer/geometry/alpha_filter.h). False when it then hits nothing.
  bool trace_culling(const Ray& ray, RTCRayHit* rh) const;
  // Fills `hit` from Embree's nearest hit `rh` of `ray`: the kind's resolve function, then
  // what every kind shares.
  void resolve_hit(const Ray& ray, const RTCRayHit& rh, SurfaceHit* hit) const;
  // One per geometry kind (baked triangles and sphere meshes: fill_triangle_hit).
  void fill_triangle_hit(const PreparedMesh& mesh, const RTCRayHit& rh, SurfaceHit* hit) const;
  void resolve_instance_hit(const Instance& instance, const RTCRayHit& rh, SurfaceHit* hit) const;
  void resolve_sphere_hit(bool embree_points, const Ray& ray, const RTCRayHit& rh,
                          SurfaceHit* hit) const;

  std::shared_ptr<EmbreeDevice> device_;
  RTCScene scene_ = nullptr;
  RTCSceneFlags scene_flags_ = RTC_SCENE_FLAG_NONE;
  RTCBuildQuality build_quality_ = RTC_BUILD_QUALITY_MEDIUM;
  std::vector<std::unique_ptr<PreparedMesh>> baked_;
  std::vector<std::unique_ptr<Prototype>> prototypes_;
  std::vector<Instance> instances_;
  std::vector<GeometryRecord> records_;                  // by top-level geomID
  std::vector<std::unique_ptr<SurfaceFilter>> filters_;  // Embree's user data: must not move
  BackFaceCulling culling_;
  std::vector<Sphere> spheres_;
  std::vector<uint32_t> sphere_emitters_;  // by sphere: its emitter, or kNoEmitter
  std::vector<EmissivePrimitive> emitters_;
  unsigned analytic_spheres_geom_ = RTC_INVALID_GEOMETRY_ID;
  Imath::Box3f bounds_;
  Imath::V3d world_origin_{0.0, 0.0, 0.0};
  GeometryStatistics statistics_;
};

}  // namespace prism
