#include "renderer/geometry/embree_scene.h"

#include <cmath>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>

#include "renderer/geometry/embree_ray.h"
#include "renderer/geometry/mesh_preparation.h"
#include "renderer/geometry/sphere_intersect.h"
#include "renderer/geometry/sphere_mesh.h"
#include "renderer/math.h"

namespace prism {

using Imath::M44f;

// A mesh placed by several nodes: its own BVH, in object space, shared by its instances.
struct EmbreeScene::Prototype {
  RTCScene scene = nullptr;
  std::vector<std::unique_ptr<PreparedMesh>> geometries;  // by geomID in `scene`
  std::vector<uint8_t> single_sided;                      // by geomID (BackFaceCulling)
  // What each placement adds to GeometryStatistics.
  size_t triangles = 0, degenerate = 0, nonfinite = 0;
};

struct EmbreeScene::Instance {
  const Prototype* prototype = nullptr;
  M44f object_to_world;
  M44f normal_to_world;                 // inverse transpose, for normals (row-vector convention)
  std::vector<uint32_t> first_emitter;  // by the prototype's geomID: as GeometryRecord's
};

struct EmbreeScene::GeometryRecord {
  // The triangle kinds first, in one unsigned byte: resolve_hit's switch then reaches them
  // with one comparison, where an int enum in another order took four more instructions a hit.
  enum class Kind : uint8_t { triangles, sphere_mesh, instance, analytic_spheres, point_spheres };
  Kind kind = Kind::triangles;
  const PreparedMesh* mesh = nullptr;  // triangles, sphere_mesh
  size_t index = 0;                    // instance: into instances_; sphere_mesh: into spheres_
  // triangles, sphere_mesh: the emitter of triangle 0 when the material emits (triangle k's
  // is first_emitter + k), else kNoEmitter.
  uint32_t first_emitter = kNoEmitter;
};

// How many nodes place each mesh decides baking or instancing: a mesh placed once is baked
// into the world, one placed by several is a prototype its nodes instance. Every primitive to
// prepare, baked or prototype, is one job.
struct EmbreeScene::MeshPlan {
  struct Job {
    const Primitive* primitive = nullptr;
    M44d to_shifted;  // baked only
    bool baked = false;
    std::unique_ptr<PreparedMesh> mesh;
  };
  struct Placement {
    bool placed = false;  // false: the node places nothing that can be hit
    M44d to_shifted;
    size_t first_job = 0;  // baked: its primitives' jobs, in order
  };
  static constexpr size_t kNoJob = ~size_t(0);

  std::vector<int> uses;                     // by mesh
  std::vector<Job> jobs;                     // each node's baked primitives, each prototype's once
  std::vector<Placement> placements;         // by node (SceneDescription::instances)
  std::vector<size_t> prototype_jobs;        // by mesh: its first job, or kNoJob
  std::vector<const Prototype*> prototypes;  // by mesh, once add_prototypes has run

  bool baked(int mesh) const { return uses[static_cast<size_t>(mesh)] == 1; }
};

namespace {

M44f to_float(const M44d& m) {
  M44f f;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) f[i][j] = static_cast<float>(m[i][j]);
  return f;
}

void count_triangles_dropped(const MeshPreparationStatistics& prepared,
                             GeometryStatistics* statistics) {
  statistics->degenerate_triangles += prepared.degenerate_triangles;
  statistics->nonfinite_triangles += prepared.nonfinite_triangles;
  statistics->normals_repaired += prepared.normals_repaired;
}

bool valid_mesh(const SceneDescription& scene, const MeshInstance& node) {
  return node.mesh >= 0 && node.mesh < static_cast<int>(scene.meshes.size());
}

}  // namespace

BuildQuality automatic_build_quality(double expected_rays, double primitives) {
  if (!(primitives > 0.0)) return BuildQuality::medium;  // nothing to build: any will do
  const double rays_per_primitive = expected_rays / primitives;
  if (rays_per_primitive < kLowBuildRaysPerPrimitive) return BuildQuality::low;
  if (rays_per_primitive > kHighBuildRaysPerPrimitive) return BuildQuality::high;
  return BuildQuality::medium;
}

RTCBuildQuality embree_build_quality(BuildQuality quality) {
  switch (quality) {
    case BuildQuality::low:
      return RTC_BUILD_QUALITY_LOW;
    case BuildQuality::medium:
    case BuildQuality::automatic:
      return RTC_BUILD_QUALITY_MEDIUM;
    case BuildQuality::high:
      break;
  }
  return RTC_BUILD_QUALITY_HIGH;
}

EmbreeScene::EmbreeScene(const SceneDescription& scene, const GeometryOptions& options,
                         const std::vector<Material>& materials)
    : EmbreeScene(std::make_shared<EmbreeDevice>(), scene, options, materials) {}

EmbreeScene::EmbreeScene(std::shared_ptr<EmbreeDevice> device, const SceneDescription& scene,
                         const GeometryOptions& options, const std::vector<Material>& materials)
    : device_(std::move(device)), world_origin_(options.world_origin) {
  const EmbreeDevice::ErrorWatch errors(*device_);
  try {
    begin_scenes(scene, options);
    MeshPlan plan = plan_meshes(scene);
    prepare_meshes(&plan);
    add_prototypes(scene, materials, &plan);
    add_placed_meshes(scene, materials, &plan);
    add_spheres(scene.spheres, options.spheres, materials);
    rtcCommitScene(scene_);
    errors.throw_if_failed();
  } catch (...) {
    release();
    throw;
  }
  RTCBounds b;
  rtcGetSceneBounds(scene_, &b);
  bounds_ =
      Imath::Box3f(V3f(b.lower_x, b.lower_y, b.lower_z), V3f(b.upper_x, b.upper_y, b.upper_z));
}

EmbreeScene::~EmbreeScene() {
  release();
}

void EmbreeScene::release() {
  if (analytic_spheres_geom_ != RTC_INVALID_GEOMETRY_ID)
    release_analytic_spheres(scene_, analytic_spheres_geom_);
  analytic_spheres_geom_ = RTC_INVALID_GEOMETRY_ID;
  for (auto& p : prototypes_) rtcReleaseScene(p->scene);
  prototypes_.clear();
  if (scene_) rtcReleaseScene(scene_);
  scene_ = nullptr;
}

void EmbreeScene::begin_scenes(const SceneDescription& scene, const GeometryOptions& options) {
  // Only a scene with a single-sided mesh needs the culling trace's context filter
  // (renderer/geometry/alpha_filter.h); the flag is set on every scene, instanced ones too,
  // since Embree reads it from the scene being traversed.
  for (const MeshInstance& node : scene.instances) {
    if (!valid_mesh(scene, node)) continue;
    for (const Primitive& p : scene.meshes[node.mesh].primitives)
      culling_.any = culling_.any || single_sided(scene, p.material);
  }
  // A LOW build is for few rays per primitive, where building is most of the work, and on
  // a big mesh most of building is the kernel handing Embree fresh pages: the compact layout
  // writes a third less and traces about 10 % slower (docs/benchmarks.md, "16M triangles").
  const bool compact = options.compact || options.build_quality == BuildQuality::low;
  scene_flags_ = static_cast<RTCSceneFlags>(
      (options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
      (compact ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE) |
      (culling_.any ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE));
  build_quality_ = embree_build_quality(options.build_quality);
  scene_ = new_scene();
}

RTCScene EmbreeScene::new_scene() const {
  RTCScene scene = rtcNewScene(device_->get());
  rtcSetSceneFlags(scene, scene_flags_);
  rtcSetSceneBuildQuality(scene, build_quality_);
  return scene;
}

void EmbreeScene::record(unsigned geom_id, const GeometryRecord& record) {
  if (records_.size() <= geom_id) records_.resize(geom_id + 1);
  records_[geom_id] = record;
}

namespace {

bool emits(int material, const std::vector<Material>& materials) {
  if (material < 0 || static_cast<size_t>(material) >= materials.size()) return false;
  const V3f& e = materials[static_cast<size_t>(material)].emissive;
  return e.x > 0.0f || e.y > 0.0f || e.z > 0.0f;
}

}  // namespace

uint32_t EmbreeScene::add_emitters(const PreparedMesh& mesh, const std::vector<Material>& materials,
                                   const M44f* object_to_world) {
  if (!emits(mesh.material, materials)) return kNoEmitter;
  const auto first = static_cast<uint32_t>(emitters_.size());
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    EmissivePrimitive e;
    e.material = mesh.material;
    e.attributes = mesh.has_attributes ? &mesh.attributes : nullptr;
    for (int k = 0; k < 3; ++k) {
      e.vertices[k] = mesh.indices[3 * t + static_cast<size_t>(k)];
      e.corners[k] = mesh.positions[e.vertices[k]];
      if (object_to_world) object_to_world->multVecMatrix(V3f(e.corners[k]), e.corners[k]);
    }
    emitters_.push_back(e);
  }
  return first;
}

EmbreeScene::MeshPlan EmbreeScene::plan_meshes(const SceneDescription& scene) {
  MeshPlan plan;
  plan.uses.assign(scene.meshes.size(), 0);
  for (const MeshInstance& node : scene.instances)
    if (valid_mesh(scene, node)) ++plan.uses[node.mesh];
  plan.placements.resize(scene.instances.size());
  plan.prototype_jobs.assign(scene.meshes.size(), MeshPlan::kNoJob);
  plan.prototypes.assign(scene.meshes.size(), nullptr);
  // World to the shifted frame, composed into every transform in double before anything is
  // rounded to float: v * (M * shift) keeps v's small offsets from a far-away node exactly
  // where v * M - origin would first round them at the node's magnitude.
  M44d shift;
  shift.setTranslation(-world_origin_);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& node = scene.instances[i];
    if (!valid_mesh(scene, node)) continue;
    const Mesh& mesh = scene.meshes[node.mesh];
    // A node that is not finite, or flattens its mesh (determinant 0), places nothing that
    // can be hit; it is skipped whole rather than handed to Embree.
    const bool finite_node = is_finite(node.object_to_world);
    const double det = finite_node ? node.object_to_world.determinant() : 0.0;
    if (!finite_node || !std::isfinite(det) || det == 0.0) {
      size_t triangles = 0;
      for (const Primitive& p : mesh.primitives) triangles += p.indices.size() / 3;
      (finite_node ? statistics_.degenerate_triangles : statistics_.nonfinite_triangles) +=
          triangles;
      continue;
    }
    MeshPlan::Placement& placement = plan.placements[i];
    placement.placed = true;
    placement.to_shifted = node.object_to_world * shift;
    if (plan.baked(node.mesh)) {
      placement.first_job = plan.jobs.size();
      for (const Primitive& p : mesh.primitives)
        plan.jobs.push_back(MeshPlan::Job{&p, placement.to_shifted, true, nullptr});
    } else if (plan.prototype_jobs[node.mesh] == MeshPlan::kNoJob) {
      plan.prototype_jobs[node.mesh] = plan.jobs.size();
      for (const Primitive& p : mesh.primitives)
        plan.jobs.push_back(MeshPlan::Job{&p, M44d(), false, nullptr});
    }
  }
  return plan;
}

// Their per-vertex copy, bake and clean are independent and, serial, cost about as much as
// Embree's own (parallel) build. The meshes are attached to Embree afterwards one at a time in
// the scene's order, so every geomID, and so every image, is the serial one.
void EmbreeScene::prepare_meshes(MeshPlan* plan) {
  tbb::parallel_for(size_t(0), plan->jobs.size(), [plan](size_t j) {
    MeshPlan::Job& job = plan->jobs[j];
    job.mesh = std::make_unique<PreparedMesh>(
        job.baked ? prepare_mesh(*job.primitive, job.to_shifted) : prepare_mesh(*job.primitive));
  });
}

// The prototypes, each mesh's primitives in order; their BVHs are small, so Embree's parallel
// build of one keeps few threads busy and several are committed at once.
void EmbreeScene::add_prototypes(const SceneDescription& scene,
                                 const std::vector<Material>& materials, MeshPlan* plan) {
  const size_t first = prototypes_.size();
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (plan->prototype_jobs[m] == MeshPlan::kNoJob) continue;
    auto proto = std::make_unique<Prototype>();
    proto->scene = new_scene();
    const size_t end = plan->prototype_jobs[m] + scene.meshes[m].primitives.size();
    for (size_t j = plan->prototype_jobs[m]; j < end; ++j) {
      std::unique_ptr<PreparedMesh>& mesh = plan->jobs[j].mesh;
      // Dropped triangles count at every placement, repaired normals once: they are shared.
      proto->degenerate += mesh->statistics.degenerate_triangles;
      proto->nonfinite += mesh->statistics.nonfinite_triangles;
      statistics_.normals_repaired += mesh->statistics.normals_repaired;
      if (mesh->indices.empty()) continue;
      proto->triangles += mesh->triangle_count();
      const unsigned id =
          attach_triangles(proto->scene, *mesh, surface_filter(scene, *mesh, materials));
      if (proto->geometries.size() <= id) {
        proto->geometries.resize(id + 1);
        proto->single_sided.resize(id + 1, 0);
      }
      proto->single_sided[id] = single_sided(scene, mesh->material);
      proto->geometries[id] = std::move(mesh);
    }
    plan->prototypes[m] = proto.get();
    prototypes_.push_back(std::move(proto));
  }
  tbb::parallel_for(first, prototypes_.size(),
                    [&](size_t i) { rtcCommitScene(prototypes_[i]->scene); });
}

// In the nodes' order: each node's baked primitives, or its instance.
void EmbreeScene::add_placed_meshes(const SceneDescription& scene,
                                    const std::vector<Material>& materials, MeshPlan* plan) {
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshPlan::Placement& placement = plan->placements[i];
    if (!placement.placed) continue;
    const MeshInstance& node = scene.instances[i];
    if (!plan->baked(node.mesh)) {
      add_instance(*plan->prototypes[static_cast<size_t>(node.mesh)], node, placement.to_shifted,
                   materials);
      continue;
    }
    const size_t end = placement.first_job + scene.meshes[node.mesh].primitives.size();
    for (size_t j = placement.first_job; j < end; ++j)
      add_baked_mesh(scene, materials, std::move(plan->jobs[j].mesh));
  }
}

void EmbreeScene::add_baked_mesh(const SceneDescription& scene,
                                 const std::vector<Material>& materials,
                                 std::unique_ptr<PreparedMesh> mesh) {
  count_triangles_dropped(mesh->statistics, &statistics_);
  if (mesh->indices.empty()) return;
  statistics_.triangles += mesh->triangle_count();
  const unsigned id = attach_triangles(scene_, *mesh, surface_filter(scene, *mesh, materials));
  record(id,
         {GeometryRecord::Kind::triangles, mesh.get(), 0, add_emitters(*mesh, materials, nullptr)});
  if (culling_.top_level.size() <= id) culling_.top_level.resize(id + 1, 0);
  culling_.top_level[id] = single_sided(scene, mesh->material);
  baked_.push_back(std::move(mesh));
  ++statistics_.meshes_baked;
}

void EmbreeScene::add_instance(const Prototype& prototype, const MeshInstance& node,
                               const M44d& to_shifted, const std::vector<Material>& materials) {
  statistics_.triangles += prototype.triangles;
  statistics_.degenerate_triangles += prototype.degenerate;
  statistics_.nonfinite_triangles += prototype.nonfinite;
  Instance instance;
  instance.prototype = &prototype;
  instance.object_to_world = to_float(to_shifted);
  instance.normal_to_world = to_float(node.object_to_world.inverse().transposed());
  RTCGeometry g = rtcNewGeometry(device_->get(), RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(g, prototype.scene);
  // Imath's row-vector matrix, read in memory order, is the column-major matrix of the
  // same transform in the column-vector convention that Embree uses.
  rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &instance.object_to_world[0][0]);
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(scene_, g);
  rtcReleaseGeometry(g);
  for (const std::unique_ptr<PreparedMesh>& mesh : prototype.geometries)
    instance.first_emitter.push_back(
        mesh ? add_emitters(*mesh, materials, &instance.object_to_world) : kNoEmitter);
  record(id, {GeometryRecord::Kind::instance, nullptr, instances_.size()});
  if (culling_.instanced.size() <= id) culling_.instanced.resize(id + 1, nullptr);
  culling_.instanced[id] = &prototype.single_sided;
  instances_.push_back(instance);
  ++statistics_.mesh_instances;
}

void EmbreeScene::add_spheres(const std::vector<Sphere>& spheres, const SphereOptions& options,
                              const std::vector<Material>& materials) {
  spheres_ = spheres;
  for (Sphere& s : spheres_) s.centre -= world_origin_;
  statistics_.spheres = spheres_.size();
  // Tessellated spheres emit as their triangles, below.
  sphere_emitters_.assign(spheres_.size(), kNoEmitter);
  if (options.mode != SphereMode::mesh) {
    for (size_t i = 0; i < spheres_.size(); ++i) {
      if (!emits(spheres_[i].material, materials)) continue;
      sphere_emitters_[i] = static_cast<uint32_t>(emitters_.size());
      EmissivePrimitive e;
      e.shape = EmissivePrimitive::Shape::sphere;
      e.corners[0] = V3f(spheres_[i].centre);
      e.radius = static_cast<float>(spheres_[i].radius);
      e.material = spheres_[i].material;
      emitters_.push_back(e);
    }
  }
  if (spheres_.empty()) return;
  switch (options.mode) {
    case SphereMode::analytic:
      analytic_spheres_geom_ = attach_analytic_spheres(device_->get(), scene_, spheres_);
      record(analytic_spheres_geom_, {GeometryRecord::Kind::analytic_spheres, nullptr, 0});
      break;
    case SphereMode::embree_points:
      record(attach_point_spheres(device_->get(), scene_, spheres_),
             {GeometryRecord::Kind::point_spheres, nullptr, 0});
      break;
    case SphereMode::mesh:
      for (size_t i = 0; i < spheres_.size(); ++i) {
        auto mesh = std::make_unique<PreparedMesh>(
            prepare_mesh(tessellate_sphere(spheres_[i], options.mesh_level)));
        count_triangles_dropped(mesh->statistics, &statistics_);
        if (mesh->indices.empty()) continue;
        statistics_.triangles += mesh->triangle_count();
        record(attach_triangles(scene_, *mesh, nullptr),
               {GeometryRecord::Kind::sphere_mesh, mesh.get(), i,
                add_emitters(*mesh, materials, nullptr)});
        baked_.push_back(std::move(mesh));
      }
      break;
  }
}

bool EmbreeScene::single_sided(const SceneDescription& scene, int material) {
  const bool known = material >= 0 && static_cast<size_t>(material) < scene.materials.size();
  return is_single_sided(known ? &scene.materials[static_cast<size_t>(material)] : nullptr);
}

const SurfaceFilter* EmbreeScene::surface_filter(const SceneDescription& scene,
                                                 const PreparedMesh& mesh,
                                                 const std::vector<Material>& materials) {
  const auto index = static_cast<size_t>(mesh.material);
  const bool known = mesh.material >= 0 && index < scene.materials.size();
  auto filter = std::make_unique<SurfaceFilter>(
      make_surface_filter(known ? &scene.materials[index] : nullptr,
                          known && index < materials.size() ? &materials[index] : nullptr,
                          mesh.indices.data(), mesh.has_attributes ? &mesh.attributes : nullptr));
  if (!needs_filter(*filter)) return nullptr;
  filters_.push_back(std::move(filter));
  return filters_.back().get();
}

unsigned EmbreeScene::attach_triangles(RTCScene scene, const PreparedMesh& mesh,
                                       const SurfaceFilter* filter) {
  RTCGeometry g = rtcNewGeometry(device_->get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(),
                             0, sizeof(V3f), mesh.vertex_count());
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                             3 * sizeof(uint32_t), mesh.indices.size() / 3);
  if (filter) attach_surface_filter(g, filter);
  // Embree builds a triangle mesh at its own quality, not the scene's: without this,
  // --build-quality low and high would both build meshes at medium.
  rtcSetGeometryBuildQuality(g, build_quality_);
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  return id;
}

void EmbreeScene::fill_triangle_hit(const PreparedMesh& mesh, const RTCRayHit& rh,
                                    SurfaceHit* hit) const {
  const uint32_t* tri = &mesh.indices[static_cast<size_t>(rh.hit.primID) * 3];
  const float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
  hit->position =
      w * mesh.positions[tri[0]] + u * mesh.positions[tri[1]] + v * mesh.positions[tri[2]];
  hit->geometric_normal = mesh.face_normals[rh.hit.primID];
  hit->terminator_offset = V3f(0.0f);
  hit->surface_error = 0.0f;
  if (!mesh.normals.empty() && !mesh.shading_is_flat) {
    hit->shading_normal =
        w * mesh.normals[tri[0]] + u * mesh.normals[tri[1]] + v * mesh.normals[tri[2]];
    // Hanika's shadow-terminator fix (Ray Tracing Gems II ch. 4): a flat triangle under
    // smooth normals lies inside the surface those normals describe, so near the terminator
    // a shadow ray from it runs into the neighbouring triangles and the smooth shading ends
    // in a blocky shadow. Projecting the point onto each vertex's tangent plane and taking
    // the barycentric mean of the three projections lifts it onto a smooth (quadratic)
    // patch; only planes the point lies below push (min with 0), so concave parts stay put.
    const float b[3] = {w, u, v};
    const V3f& front = hit->geometric_normal;
    V3f offset(0.0f);
    for (int k = 0; k < 3; ++k) {
      const V3f n = face_forward(mesh.normals[tri[k]], front);
      const float below = fmin_inline(0.0f, dot(hit->position - mesh.positions[tri[k]], n));
      offset -= (b[k] * below) * n;
    }
    if (is_finite(offset)) hit->terminator_offset = offset;
  } else {
    hit->shading_normal = hit->geometric_normal;
  }
  // Only where the hit is: the material interpolates the attributes it reads.
  hit->attributes = mesh.has_attributes ? &mesh.attributes : nullptr;
  hit->vertices[0] = tri[0];
  hit->vertices[1] = tri[1];
  hit->vertices[2] = tri[2];
  hit->barycentric_u = u;
  hit->barycentric_v = v;
  hit->material = mesh.material;
}

namespace {

// Embree's behaviour on NaN or infinite rays is undefined (NaN fails every comparison in
// traversal, so a ray may report a hit with garbage t or walk the whole tree); such a ray
// is answered here instead. tfar may be +infinity, the usual "unbounded".
bool ray_is_valid(const Ray& ray) {
  return is_finite(ray.origin) && is_finite(ray.direction) && std::isfinite(ray.tnear) &&
         !std::isnan(ray.tfar);
}

}  // namespace

bool EmbreeScene::culled_back_face(const Ray& ray, const RTCRayHit& rh) const {
  if (!ray.from_camera || !culling_.culls(rh.hit.instID[0], rh.hit.geomID)) return false;
  // The culling filter's test, in world space: Ng is in the hit geometry's own space, and
  // normals move with the inverse transpose, which keeps the sign of their dot product with
  // a direction.
  V3f ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
    V3f world;
    instances_[records_[rh.hit.instID[0]].index].normal_to_world.multDirMatrix(ng, world);
    ng = world;
  }
  return dot(ray.direction, ng) > 0.0f;
}

bool EmbreeScene::intersect(const Ray& ray, SurfaceHit* hit) const {
  if (!ray_is_valid(ray)) return false;
  TraceContext context(&ray);  // the surface filters read the ray from it
  RTCRayHit rh = to_rtc_rayhit(ray);
  rtcIntersect1(scene_, &context.embree, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  if (culled_back_face(ray, rh) && !trace_culling(ray, &rh)) return false;
  resolve_hit(ray, rh, hit);
  return true;
}

bool EmbreeScene::trace_culling(const Ray& ray, RTCRayHit* rh) const {
  TraceContext context(&ray);
  context.culling = &culling_;
  context.embree.filter = cull_camera_back_faces;
  *rh = to_rtc_rayhit(ray);
  rtcIntersect1(scene_, &context.embree, rh);
  return rh->hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

void EmbreeScene::intersect_packet(const Ray* rays, int count, SurfaceHit* hits,
                                   bool* found) const {
  static_assert(kPacketSize == 16, "traced with rtcIntersect16");
  if (count <= 0) return;
  alignas(64) int valid[kPacketSize];
  alignas(64) RTCRayHit16 packet;
  for (int i = 0; i < kPacketSize; ++i) {
    const bool traced = i < count && ray_is_valid(rays[i]);
    valid[i] = traced ? -1 : 0;
    set_packet_lane(&packet.ray, i, rays[traced ? i : 0]);
    packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  TraceContext context(rays);  // the filters find lane i's ray at rays[i]
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(valid, scene_, &context.embree, &packet);
  for (int i = 0; i < count; ++i) {
    found[i] = false;
    if (valid[i] == 0 || packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    RTCRayHit rh = to_rtc_rayhit(rays[i]);
    rh.ray.tfar = packet.ray.tfar[i];
    rh.hit.Ng_x = packet.hit.Ng_x[i];
    rh.hit.Ng_y = packet.hit.Ng_y[i];
    rh.hit.Ng_z = packet.hit.Ng_z[i];
    rh.hit.u = packet.hit.u[i];
    rh.hit.v = packet.hit.v[i];
    rh.hit.primID = packet.hit.primID[i];
    rh.hit.geomID = packet.hit.geomID[i];
    rh.hit.instID[0] = packet.hit.instID[0][i];
    if (culled_back_face(rays[i], rh) && !trace_culling(rays[i], &rh)) continue;
    resolve_hit(rays[i], rh, &hits[i]);
    found[i] = true;
  }
}

// Inline, as resolve_sphere_hit below: resolve_hit is their only caller, and a member function,
// which has external linkage, is otherwise kept out of line (0.25 % more instructions in a whitted
// render of scenes/spheres.gltf).
inline void EmbreeScene::resolve_instance_hit(const Instance& instance, const RTCRayHit& rh,
                                              SurfaceHit* hit) const {
  fill_triangle_hit(*instance.prototype->geometries[rh.hit.geomID], rh, hit);
  const uint32_t first = instance.first_emitter[rh.hit.geomID];
  hit->emitter = first == kNoEmitter ? kNoEmitter : first + rh.hit.primID;
  // Everything above is in object space; normals move with the inverse transpose.
  V3f p;
  instance.object_to_world.multVecMatrix(hit->position, p);
  hit->object_to_world = &instance.object_to_world;
  hit->position = p;
  instance.object_to_world.multDirMatrix(hit->terminator_offset, p);
  hit->terminator_offset = p;
  V3f n;
  instance.normal_to_world.multDirMatrix(hit->geometric_normal, n);
  hit->geometric_normal = normalize(n);
  instance.normal_to_world.multDirMatrix(hit->shading_normal, n);
  hit->shading_normal = n;
}

inline void EmbreeScene::resolve_sphere_hit(bool embree_points, const Ray& ray, const RTCRayHit& rh,
                                            SurfaceHit* hit) const {
  const Sphere& s = spheres_[rh.hit.primID];
  if (embree_points) {
    // Embree's native test solves in float and its distance can be off by a few ulps more
    // than the robust form's (8.06 ulps of t on AVX2 for a ray leaving a sphere from
    // inside: tests/stress/03). The robust root within 64 ulps of Embree's replaces it; the
    // window keeps Embree's choice of root, and where the two disagree on the hit (no root
    // in the window) Embree's stands.
    const float t = rh.ray.tfar;
    const float window = 64.0f * ulp_of(t);
    if (const auto root = intersect_sphere(ray.origin, ray.direction, V3f(s.centre),
                                           static_cast<float>(s.radius), t - window, t + window))
      hit->t = root->t;
  }
  // The intersector's Ng is hit point - centre, computed more precisely than o + t d - centre
  // could be here; the hit point is projected back onto the sphere along it, in double, so it
  // is on the surface to the rounding of its coordinates instead of an error growing with t
  // or with the radius.
  const V3d radial = V3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  hit->position = V3f(s.centre + s.radius * radial);
  hit->geometric_normal = V3f(radial);
  hit->shading_normal = hit->geometric_normal;
  // Embree's own sphere test works in float on coordinates of size |centre| + r: near the
  // surface it cannot tell a ray's start from the surface closer than a few ulps of that
  // size, so a ray leaving by less could find the sphere again (a wall made of an r = 1e5
  // sphere self-shadows: tests/stress/04). Measured on that wall: 2^-26 of it is too little
  // (every lit pixel self-shadowed), 2^-25 enough; 2^-22 keeps a margin of 8. The robust
  // analytic test needs nothing beyond the hit point's rounding.
  hit->surface_error =
      embree_points
          ? 0x1.0p-22f * static_cast<float>(std::fabs(s.centre.x) + std::fabs(s.centre.y) +
                                            std::fabs(s.centre.z) + s.radius)
          : 0.0f;
  hit->terminator_offset = V3f(0.0f);  // the surface is the smooth one already
  hit->material = s.material;
  hit->attributes = nullptr;
  hit->emitter = sphere_emitters_[rh.hit.primID];
}

void EmbreeScene::resolve_hit(const Ray& ray, const RTCRayHit& rh, SurfaceHit* hit) const {
  hit->t = rh.ray.tfar;
  hit->object_to_world = nullptr;
  // A hit inside an instance names the instance's top-level geometry in instID[0].
  const bool instanced = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID;
  const GeometryRecord& r = records_[instanced ? rh.hit.instID[0] : rh.hit.geomID];
  switch (r.kind) {
    case GeometryRecord::Kind::triangles:
    case GeometryRecord::Kind::sphere_mesh:
      fill_triangle_hit(*r.mesh, rh, hit);
      hit->emitter = r.first_emitter == kNoEmitter ? kNoEmitter : r.first_emitter + rh.hit.primID;
      break;
    case GeometryRecord::Kind::instance:
      resolve_instance_hit(instances_[r.index], rh, hit);
      break;
    case GeometryRecord::Kind::analytic_spheres:
    case GeometryRecord::Kind::point_spheres:
      resolve_sphere_hit(r.kind == GeometryRecord::Kind::point_spheres, ray, rh, hit);
      break;
  }
  // Interpolated normals can be zero, non-finite, or point through the surface; they are
  // kept on the geometric normal's side and fall back to it when unusable.
  const float len2 = hit->shading_normal.length2();
  if (!(len2 > 1e-20f) || !std::isfinite(len2)) {
    hit->shading_normal = hit->geometric_normal;
  } else {
    hit->shading_normal /= std::sqrt(len2);
    if (dot(hit->shading_normal, hit->geometric_normal) < 0.0f)
      hit->shading_normal = -hit->shading_normal;
  }
  const float cos_incidence = dot(ray.direction, hit->geometric_normal);
  hit->back_face = cos_incidence > 0.0f;
  hit->cos_incidence = std::fabs(cos_incidence);
  hit->cone_width = ray.cone_width + ray.cone_spread * hit->t;
}

void EmbreeScene::occluded_packet(const Ray* rays, int count, bool* blocked) const {
  static_assert(kPacketSize == 16, "traced with rtcOccluded16");
  if (count <= 0) return;
  alignas(64) int valid[kPacketSize];
  alignas(64) RTCRay16 packet;
  for (int i = 0; i < kPacketSize; ++i) {
    const bool traced = i < count && ray_is_valid(rays[i]);
    valid[i] = traced ? -1 : 0;
    set_packet_lane(&packet, i, rays[traced ? i : 0]);
  }
  TraceContext context(rays);  // the alpha filters find lane i's ray at rays[i]
  rtcOccluded16(valid, scene_, &context.embree, &packet);
  // As occluded(): a ray that cannot be traced is blocked.
  for (int i = 0; i < count; ++i) blocked[i] = valid[i] == 0 || packet.tfar[i] < 0.0f;
}

bool EmbreeScene::occluded(const Ray& ray) const {
  // Blocked: a shadow ray that cannot be traced must not light the point it came from.
  if (!ray_is_valid(ray)) return true;
  TraceContext context(&ray);  // the surface filters read the ray from it
  RTCRay r = to_rtc_ray(ray);
  rtcOccluded1(scene_, &context.embree, &r);
  return r.tfar < 0.0f;
}

}  // namespace prism
