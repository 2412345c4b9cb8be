#include "renderer/geometry/embree_scene.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "renderer/geometry/embree_ray.h"
#include "renderer/math.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {

using Imath::M44f;
using Imath::V2f;

// Vertex data as Embree sees it, kept for rebuilding hit points and interpolating normals,
// and the attributes the material reads (texture coordinates, colours, tangents). Positions
// carry one padding element: Embree reads 16 bytes per float3 vertex, 4 past the end of the
// last one.
struct EmbreeScene::TriangleMesh {
  std::vector<V3f> positions;
  std::vector<V3f> normals;  // unit or zero; empty: shade with the geometric normal (flat)
  VertexAttributes attributes;
  bool has_attributes = false;  // any of them: hits point the material at `attributes`
  std::vector<uint32_t> indices;
  // Per triangle: the unit normal of its float vertices, formed in double. Embree's float Ng
  // of a long sliver triangle can point well off the plane, or be zero, and a ray offset
  // along a wrong normal re-hits the triangle it leaves (tests/stress/02_reintersect_test.cpp).
  // Formed once here rather than at every hit, where it cost more than the rest of the hit.
  // Out of the counter-clockwise front face, as Embree's Ng.
  std::vector<V3f> face_normals;
  int material = -1;
  size_t vertex_count() const { return positions.empty() ? 0 : positions.size() - 1; }

  // Once the triangles are final (cleaned).
  void compute_face_normals() {
    face_normals.resize(indices.size() / 3);
    for (size_t t = 0; t < face_normals.size(); ++t) {
      const uint32_t* tri = &indices[3 * t];
      const V3d p0(positions[tri[0]]), p1(positions[tri[1]]), p2(positions[tri[2]]);
      face_normals[t] = V3f((p1 - p0).cross(p2 - p0).normalized());
    }
  }

  // Takes the primitive's attributes that have one value per vertex (the loader checks
  // that; a primitive made in code may not), once `positions` is final.
  void take_attributes(const Primitive& p, const std::vector<Imath::V4f>& tangents) {
    const size_t n = p.positions.size();
    if (p.uv0.size() == n) attributes.texcoords[0] = p.uv0;
    if (p.uv1.size() == n) attributes.texcoords[1] = p.uv1;
    if (p.colours.size() == n) attributes.colours = p.colours;
    if (tangents.size() == n) attributes.tangents = tangents;
    attributes.positions = positions.data();
    has_attributes = !attributes.empty();
  }
};

namespace {

struct CleaningCounts {
  size_t degenerate = 0;
  size_t nonfinite = 0;
  size_t normals_repaired = 0;
};

// Makes a triangle list safe to hand to Embree and to shade, in the space Embree will see
// it in (world for baked meshes, object for instanced ones):
//   - drops triangles with an index out of range or repeated, with a non-finite vertex, or
//     with zero area: twice the area |e1 x e2|, in double, at most 1e-12 times the longest
//     edge squared, i.e. a height below 1e-12 of the base, far under float's resolution of
//     1.2e-7, so only triangles that are collinear to rounding go. Embree would never report
//     a useful hit on them (Ng is zero or noise), and garbage indices could crash it;
//   - zeroes the positions of vertices no kept triangle uses, so no NaN reaches Embree;
//   - drops normals that are not one per vertex (the primitive is shaded flat), and rebuilds
//     each zero or non-finite normal of a used vertex as the area-weighted mean of the faces
//     around it (what a loader would generate), normalising the rest.
// The kept triangles keep their order, so a mesh that differs from a clean one only by the
// dropped triangles and unused vertices gives Embree the same primitives and the same BVH.
void clean_mesh(std::vector<V3f>* positions, std::vector<V3f>* normals,
                std::vector<uint32_t>* indices, CleaningCounts* counts) {
  const size_t vertices = positions->size();
  std::vector<uint32_t> kept;
  kept.reserve(indices->size());
  std::vector<char> used(vertices, 0);
  for (size_t i = 0; i + 2 < indices->size(); i += 3) {
    const uint32_t a = (*indices)[i], b = (*indices)[i + 1], c = (*indices)[i + 2];
    if (a >= vertices || b >= vertices || c >= vertices || a == b || b == c || a == c) {
      ++counts->degenerate;
      continue;
    }
    const V3f& pa = (*positions)[a];
    const V3f& pb = (*positions)[b];
    const V3f& pc = (*positions)[c];
    if (!is_finite(pa) || !is_finite(pb) || !is_finite(pc)) {
      ++counts->nonfinite;
      continue;
    }
    const V3d e1 = V3d(pb) - V3d(pa), e2 = V3d(pc) - V3d(pa), e3 = V3d(pc) - V3d(pb);
    const double longest2 = std::max({e1.length2(), e2.length2(), e3.length2()});
    // Finite float vertices keep every double here finite.
    if (!(e1.cross(e2).length2() > 1e-24 * longest2 * longest2)) {
      ++counts->degenerate;
      continue;
    }
    kept.insert(kept.end(), {a, b, c});
    used[a] = used[b] = used[c] = 1;
  }
  // A trailing partial triangle is not a triangle.
  if (indices->size() % 3 != 0) ++counts->degenerate;
  *indices = std::move(kept);
  for (size_t v = 0; v < vertices; ++v)
    if (!used[v] && !is_finite((*positions)[v])) (*positions)[v] = V3f(0.0f);

  if (normals->empty()) return;
  if (normals->size() != vertices) {
    normals->clear();
    return;
  }
  std::vector<char> broken(vertices, 0);
  bool any_broken = false;
  for (size_t v = 0; v < vertices; ++v) {
    V3f& n = (*normals)[v];
    const double len2 = V3d(n).length2();
    if (is_finite(n) && len2 > 1e-30) {
      n = V3f(V3d(n) / std::sqrt(len2));
    } else {
      n = V3f(0.0f);
      broken[v] = used[v];
      any_broken = any_broken || used[v];
    }
  }
  if (!any_broken) return;
  std::vector<V3d> sum(vertices, V3d(0.0));
  for (size_t i = 0; i < indices->size(); i += 3) {
    const uint32_t t[3] = {(*indices)[i], (*indices)[i + 1], (*indices)[i + 2]};
    // Counter-clockwise: the cross product points out of the front face, its length is
    // twice the area, which weights the mean.
    const V3d face = (V3d((*positions)[t[1]]) - V3d((*positions)[t[0]]))
                         .cross(V3d((*positions)[t[2]]) - V3d((*positions)[t[0]]));
    for (uint32_t v : t)
      if (broken[v]) sum[v] += face;
  }
  for (size_t v = 0; v < vertices; ++v) {
    if (!broken[v]) continue;
    ++counts->normals_repaired;
    const double len = sum[v].length();
    // Faces that cancel (a vertex of two back-to-back faces) leave it zero, and the hit
    // falls back to the geometric normal there.
    if (len > 0.0) (*normals)[v] = V3f(sum[v] / len);
  }
}

}  // namespace

// The primitive as is, in its own space, cleaned and padded for Embree's read-ahead.
std::unique_ptr<EmbreeScene::TriangleMesh> EmbreeScene::copy_for_embree(const Primitive& p,
                                                                        size_t* dropped_degenerate,
                                                                        size_t* dropped_nonfinite) {
  auto mesh = std::make_unique<EmbreeScene::TriangleMesh>();
  mesh->positions.reserve(p.positions.size() + 1);
  mesh->positions = p.positions;
  mesh->normals = p.normals;
  mesh->indices = p.indices;
  mesh->material = p.material;
  CleaningCounts counts;
  clean_mesh(&mesh->positions, &mesh->normals, &mesh->indices, &counts);
  *dropped_degenerate += counts.degenerate;
  *dropped_nonfinite += counts.nonfinite;
  // The constructor copies several primitives at once.
  std::atomic_ref<size_t>(statistics_.normals_repaired) += counts.normals_repaired;
  mesh->compute_face_normals();
  mesh->positions.push_back(V3f(0.0f));
  mesh->take_attributes(p, p.tangents);
  return mesh;
}

// A mesh placed by several nodes: its own BVH, in object space, shared by its instances.
struct EmbreeScene::Prototype {
  RTCScene scene = nullptr;
  std::vector<std::unique_ptr<TriangleMesh>> geometries;  // by geomID in `scene`
  std::vector<uint8_t> single_sided;                      // by geomID (BackFaceCulling)
};

struct EmbreeScene::Instance {
  const Prototype* prototype = nullptr;
  M44f object_to_world;
  M44f normal_to_world;  // inverse transpose, for normals (row-vector convention)
};

struct EmbreeScene::GeometryRecord {
  enum class Kind { triangles, instance, analytic_spheres, point_spheres, sphere_mesh };
  Kind kind = Kind::triangles;
  const TriangleMesh* mesh = nullptr;  // triangles, sphere_mesh
  size_t index = 0;                    // instance: into instances_; sphere_mesh: into spheres_
};

namespace {

// Where Embree's first error goes; Embree may report from several threads at once (the
// prototypes are committed in parallel).
struct EmbreeErrors {
  std::mutex mutex;
  std::string first;
};

void report_embree_error(void* errors_out, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  auto* errors = static_cast<EmbreeErrors*>(errors_out);
  const std::lock_guard<std::mutex> lock(errors->mutex);
  if (errors->first.empty()) errors->first = message ? message : "unknown Embree error";
}

M44f to_float(const M44d& m) {
  M44f f;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) f[i][j] = static_cast<float>(m[i][j]);
  return f;
}

// The primitive moved into world space (shifted by the world origin, which `to_world`
// already includes). A transform that mirrors (negative determinant) would turn
// counter-clockwise triangles clockwise, so their winding is flipped to keep the authored
// front face in front, as glTF requires.
void bake(const Primitive& p, const M44d& to_world, std::vector<V3f>* positions,
          std::vector<V3f>* normals, std::vector<uint32_t>* indices) {
  const M44d normal_matrix = to_world.inverse().transposed();
  positions->reserve(p.positions.size() + 1);
  for (const V3f& v : p.positions) {
    V3d w;
    to_world.multVecMatrix(V3d(v), w);
    positions->push_back(V3f(w));
  }
  normals->reserve(p.normals.size());
  for (const V3f& n : p.normals) {
    V3d w;
    normal_matrix.multDirMatrix(V3d(n), w);
    normals->push_back(V3f(w.normalized()));
  }
  *indices = p.indices;
  if (to_world.determinant() < 0.0) {
    for (size_t i = 0; i + 2 < indices->size(); i += 3)
      std::swap((*indices)[i + 1], (*indices)[i + 2]);
  }
}

// Tangents move with the surface (as directions, unlike normals). A mirroring transform
// flips the bitangent cross(normal, tangent) relative to the surface, so w flips with it.
std::vector<Imath::V4f> bake_tangents(const std::vector<Imath::V4f>& tangents,
                                      const M44d& to_world) {
  const float handedness = to_world.determinant() < 0.0 ? -1.0f : 1.0f;
  std::vector<Imath::V4f> out;
  out.reserve(tangents.size());
  for (const Imath::V4f& t : tangents) {
    V3d w;
    to_world.multDirMatrix(V3d(t.x, t.y, t.z), w);
    const V3f d(w.normalized());
    out.emplace_back(d.x, d.y, d.z, t.w * handedness);
  }
  return out;
}

}  // namespace

RTCBuildQuality embree_build_quality(BuildQuality quality) {
  switch (quality) {
    case BuildQuality::low:
      return RTC_BUILD_QUALITY_LOW;
    case BuildQuality::medium:
      return RTC_BUILD_QUALITY_MEDIUM;
    case BuildQuality::high:
      break;
  }
  return RTC_BUILD_QUALITY_HIGH;
}

EmbreeScene::EmbreeScene(const SceneDescription& scene, const GeometryOptions& options,
                         const std::vector<Material>& materials)
    : world_origin_(options.world_origin) {
  EmbreeErrors error;
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(device_, report_embree_error, &error);
  // Only a scene with a single-sided mesh needs the culling trace's context filter
  // (renderer/geometry/alpha_filter.h); the flag is set on every scene, instanced ones too, since
  // Embree reads it from the scene being traversed.
  for (const MeshInstance& inst : scene.instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size())) continue;
    for (const Primitive& p : scene.meshes[inst.mesh].primitives)
      culling_.any = culling_.any || single_sided(scene, p.material);
  }
  const RTCSceneFlags flags = static_cast<RTCSceneFlags>(
      (options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
      (options.compact ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE) |
      (culling_.any ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE));
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, flags);
  const RTCBuildQuality quality = embree_build_quality(options.build_quality);
  rtcSetSceneBuildQuality(scene_, quality);

  auto record = [&](unsigned geom_id, GeometryRecord r) {
    if (records_.size() <= geom_id) records_.resize(geom_id + 1);
    records_[geom_id] = r;
  };

  // World to the shifted frame, composed into every transform in double before anything is
  // rounded to float: v * (M * shift) keeps v's small offsets from a far-away node exactly
  // where v * M - origin would first round them at the node's magnitude.
  M44d shift;
  shift.setTranslation(-world_origin_);

  // How many nodes place each mesh decides baking or instancing.
  std::vector<int> uses(scene.meshes.size(), 0);
  for (const MeshInstance& inst : scene.instances)
    if (inst.mesh >= 0 && inst.mesh < static_cast<int>(scene.meshes.size())) ++uses[inst.mesh];
  struct PrototypeUse {
    const Prototype* prototype = nullptr;
    size_t triangles = 0, degenerate = 0, nonfinite = 0;  // per placement
  };
  std::vector<PrototypeUse> prototype_of(scene.meshes.size());

  // Each primitive's TriangleMesh (baked for a mesh placed once, copied for a prototype) is
  // made in parallel: their per-vertex copy, bake and clean are independent and, serial, cost
  // about as much as Embree's own (parallel) build. They are attached to Embree afterwards one
  // at a time in the scene's order, so every geomID, and so every image, is the serial one.
  struct MeshJob {
    const Primitive* primitive = nullptr;
    M44d to_shifted;  // baked only
    bool baked = false;
    std::unique_ptr<TriangleMesh> mesh;
    CleaningCounts counts;
  };
  struct Placement {
    bool placed = false;
    M44d to_shifted;
    size_t first_job = 0;  // baked: its primitives' jobs, in order
  };
  std::vector<MeshJob> jobs;
  std::vector<Placement> placements(scene.instances.size());
  constexpr size_t kNoJob = ~size_t(0);
  std::vector<size_t> prototype_jobs(scene.meshes.size(), kNoJob);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& inst = scene.instances[i];
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size())) continue;
    const Mesh& mesh = scene.meshes[inst.mesh];
    // A node that is not finite, or flattens its mesh (determinant 0), places nothing that
    // can be hit; it is skipped whole rather than handed to Embree.
    const bool finite_node = is_finite(inst.object_to_world);
    const double det = finite_node ? inst.object_to_world.determinant() : 0.0;
    if (!finite_node || !std::isfinite(det) || det == 0.0) {
      size_t triangles = 0;
      for (const Primitive& p : mesh.primitives) triangles += p.indices.size() / 3;
      (finite_node ? statistics_.degenerate_triangles : statistics_.nonfinite_triangles) +=
          triangles;
      continue;
    }
    Placement& placement = placements[i];
    placement.placed = true;
    placement.to_shifted = inst.object_to_world * shift;
    if (uses[inst.mesh] == 1) {
      placement.first_job = jobs.size();
      for (const Primitive& p : mesh.primitives)
        jobs.push_back(MeshJob{&p, placement.to_shifted, true, nullptr, {}});
    } else if (prototype_jobs[inst.mesh] == kNoJob) {
      prototype_jobs[inst.mesh] = jobs.size();
      for (const Primitive& p : mesh.primitives)
        jobs.push_back(MeshJob{&p, M44d(), false, nullptr, {}});
    }
  }
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t j) {
    MeshJob& job = jobs[j];
    const Primitive& p = *job.primitive;
    if (!job.baked) {
      job.mesh = copy_for_embree(p, &job.counts.degenerate, &job.counts.nonfinite);
      return;
    }
    job.mesh = std::make_unique<TriangleMesh>();
    TriangleMesh& baked = *job.mesh;
    bake(p, job.to_shifted, &baked.positions, &baked.normals, &baked.indices);
    clean_mesh(&baked.positions, &baked.normals, &baked.indices, &job.counts);
    if (baked.indices.empty()) return;
    baked.compute_face_normals();
    baked.positions.push_back(V3f(0.0f));  // Embree's read-ahead padding
    baked.take_attributes(p, bake_tangents(p.tangents, job.to_shifted));
    baked.material = p.material;
  });

  // The prototypes, each mesh's primitives in order; their BVHs are small, so Embree's
  // parallel build of one keeps few threads busy and several are committed at once.
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (prototype_jobs[m] == kNoJob) continue;
    PrototypeUse& use = prototype_of[m];
    auto proto = std::make_unique<Prototype>();
    proto->scene = rtcNewScene(device_);
    rtcSetSceneFlags(proto->scene, flags);
    rtcSetSceneBuildQuality(proto->scene, quality);
    const size_t end = prototype_jobs[m] + scene.meshes[m].primitives.size();
    for (size_t j = prototype_jobs[m]; j < end; ++j) {
      MeshJob& job = jobs[j];
      use.degenerate += job.counts.degenerate;
      use.nonfinite += job.counts.nonfinite;
      if (job.mesh->indices.empty()) continue;
      use.triangles += job.mesh->indices.size() / 3;
      const unsigned id =
          attach_triangles(proto->scene, *job.mesh, surface_filter(scene, *job.mesh, materials));
      if (proto->geometries.size() <= id) {
        proto->geometries.resize(id + 1);
        proto->single_sided.resize(id + 1, 0);
      }
      proto->geometries[id] = std::move(job.mesh);
      proto->single_sided[id] = single_sided(scene, job.primitive->material);
    }
    use.prototype = proto.get();
    prototypes_.push_back(std::move(proto));
  }
  tbb::parallel_for(size_t(0), prototypes_.size(),
                    [&](size_t i) { rtcCommitScene(prototypes_[i]->scene); });

  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Placement& placement = placements[i];
    if (!placement.placed) continue;
    const MeshInstance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    if (uses[inst.mesh] == 1) {
      for (size_t j = placement.first_job; j < placement.first_job + mesh.primitives.size(); ++j) {
        MeshJob& job = jobs[j];
        statistics_.degenerate_triangles += job.counts.degenerate;
        statistics_.nonfinite_triangles += job.counts.nonfinite;
        statistics_.normals_repaired += job.counts.normals_repaired;
        std::unique_ptr<TriangleMesh>& baked = job.mesh;
        if (baked->indices.empty()) continue;
        statistics_.triangles += baked->indices.size() / 3;
        const unsigned id =
            attach_triangles(scene_, *baked, surface_filter(scene, *baked, materials));
        record(id, {GeometryRecord::Kind::triangles, baked.get(), 0});
        if (culling_.top_level.size() <= id) culling_.top_level.resize(id + 1, 0);
        culling_.top_level[id] = single_sided(scene, job.primitive->material);
        baked_.push_back(std::move(baked));
        ++statistics_.meshes_baked;
      }
      continue;
    }
    const PrototypeUse& use = prototype_of[inst.mesh];
    const M44d& to_shifted = placement.to_shifted;
    statistics_.triangles += use.triangles;
    statistics_.degenerate_triangles += use.degenerate;
    statistics_.nonfinite_triangles += use.nonfinite;
    Instance instance;
    instance.prototype = use.prototype;
    instance.object_to_world = to_float(to_shifted);
    instance.normal_to_world = to_float(inst.object_to_world.inverse().transposed());
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, instance.prototype->scene);
    // Imath's row-vector matrix, read in memory order, is the column-major matrix of the
    // same transform in the column-vector convention that Embree uses.
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                            &instance.object_to_world[0][0]);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    record(id, {GeometryRecord::Kind::instance, nullptr, instances_.size()});
    if (culling_.instanced.size() <= id) culling_.instanced.resize(id + 1, nullptr);
    culling_.instanced[id] = &instance.prototype->single_sided;
    instances_.push_back(instance);
    ++statistics_.mesh_instances;
  }

  spheres_ = scene.spheres;
  for (Sphere& s : spheres_) s.centre -= world_origin_;
  statistics_.spheres = spheres_.size();
  if (!spheres_.empty()) {
    switch (options.spheres.mode) {
      case SphereMode::analytic:
        analytic_spheres_geom_ = attach_analytic_spheres(device_, scene_, spheres_);
        record(analytic_spheres_geom_, {GeometryRecord::Kind::analytic_spheres, nullptr, 0});
        break;
      case SphereMode::embree_points:
        record(attach_point_spheres(device_, scene_, spheres_),
               {GeometryRecord::Kind::point_spheres, nullptr, 0});
        break;
      case SphereMode::mesh:
        for (size_t i = 0; i < spheres_.size(); ++i) {
          const Primitive p = tessellate_sphere(spheres_[i], options.spheres.mesh_level);
          auto mesh = copy_for_embree(p, &statistics_.degenerate_triangles,
                                      &statistics_.nonfinite_triangles);
          if (mesh->indices.empty()) continue;
          statistics_.triangles += mesh->indices.size() / 3;
          record(attach_triangles(scene_, *mesh, nullptr),
                 {GeometryRecord::Kind::sphere_mesh, mesh.get(), i});
          baked_.push_back(std::move(mesh));
        }
        break;
    }
  }

  rtcCommitScene(scene_);
  if (!error.first.empty()) throw std::runtime_error("Embree: " + error.first);
  rtcSetDeviceErrorFunction(device_, nullptr, nullptr);
  RTCBounds b;
  rtcGetSceneBounds(scene_, &b);
  bounds_ =
      Imath::Box3f(V3f(b.lower_x, b.lower_y, b.lower_z), V3f(b.upper_x, b.upper_y, b.upper_z));
}

EmbreeScene::~EmbreeScene() {
  if (analytic_spheres_geom_ != RTC_INVALID_GEOMETRY_ID)
    release_analytic_spheres(scene_, analytic_spheres_geom_);
  for (auto& p : prototypes_) rtcReleaseScene(p->scene);
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

bool EmbreeScene::single_sided(const SceneDescription& scene, int material) {
  const bool known = material >= 0 && static_cast<size_t>(material) < scene.materials.size();
  return is_single_sided(known ? &scene.materials[static_cast<size_t>(material)] : nullptr);
}

const SurfaceFilter* EmbreeScene::surface_filter(const SceneDescription& scene,
                                                 const TriangleMesh& mesh,
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

unsigned EmbreeScene::attach_triangles(RTCScene scene, const TriangleMesh& mesh,
                                       const SurfaceFilter* filter) {
  RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(),
                             0, sizeof(V3f), mesh.vertex_count());
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                             3 * sizeof(uint32_t), mesh.indices.size() / 3);
  if (filter) attach_surface_filter(g, filter);
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  return id;
}

void EmbreeScene::fill_triangle_hit(const TriangleMesh& mesh, const RTCRayHit& rh,
                                    SurfaceHit* hit) const {
  const uint32_t* tri = &mesh.indices[static_cast<size_t>(rh.hit.primID) * 3];
  const float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
  hit->position =
      w * mesh.positions[tri[0]] + u * mesh.positions[tri[1]] + v * mesh.positions[tri[2]];
  hit->geometric_normal = mesh.face_normals[rh.hit.primID];
  hit->terminator_offset = V3f(0.0f);
  hit->surface_error = 0.0f;
  if (!mesh.normals.empty()) {
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
      const float below = std::fmin(0.0f, dot(hit->position - mesh.positions[tri[k]], n));
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

void EmbreeScene::resolve_hit(const Ray& ray, const RTCRayHit& rh, SurfaceHit* hit) const {
  hit->t = rh.ray.tfar;
  hit->object_to_world = nullptr;
  if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
    const Instance& inst = instances_[records_[rh.hit.instID[0]].index];
    fill_triangle_hit(*inst.prototype->geometries[rh.hit.geomID], rh, hit);
    // Everything above is in object space; normals move with the inverse transpose.
    V3f p;
    inst.object_to_world.multVecMatrix(hit->position, p);
    hit->object_to_world = &inst.object_to_world;
    hit->position = p;
    inst.object_to_world.multDirMatrix(hit->terminator_offset, p);
    hit->terminator_offset = p;
    V3f n;
    inst.normal_to_world.multDirMatrix(hit->geometric_normal, n);
    hit->geometric_normal = normalize(n);
    inst.normal_to_world.multDirMatrix(hit->shading_normal, n);
    hit->shading_normal = n;
  } else {
    const GeometryRecord& r = records_[rh.hit.geomID];
    if (r.kind == GeometryRecord::Kind::analytic_spheres ||
        r.kind == GeometryRecord::Kind::point_spheres) {
      const Sphere& s = spheres_[rh.hit.primID];
      // The intersector's Ng is hit point - centre, computed more precisely than
      // o + t d - centre could be here; the hit point is projected back onto the sphere
      // along it, in double, so it is on the surface to the rounding of its coordinates
      // instead of an error growing with t or with the radius.
      const V3d radial = V3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
      hit->position = V3f(s.centre + s.radius * radial);
      hit->geometric_normal = V3f(radial);
      hit->shading_normal = hit->geometric_normal;
      // Embree's own sphere test works in float on coordinates of size |centre| + r: near
      // the surface it cannot tell a ray's start from the surface closer than a few ulps of
      // that size, so a ray leaving by less could find the sphere again (a wall made of an
      // r = 1e5 sphere self-shadows: tests/stress/04). Measured on that wall: 2^-26 of it is
      // too little (every lit pixel self-shadowed), 2^-25 enough; 2^-22 keeps a margin of 8.
      // The robust analytic test needs nothing beyond the hit point's rounding.
      hit->surface_error =
          r.kind == GeometryRecord::Kind::point_spheres
              ? 0x1.0p-22f * static_cast<float>(std::fabs(s.centre.x) + std::fabs(s.centre.y) +
                                                std::fabs(s.centre.z) + s.radius)
              : 0.0f;
      hit->terminator_offset = V3f(0.0f);  // the surface is the smooth one already
      hit->material = s.material;
      hit->attributes = nullptr;
    } else {
      fill_triangle_hit(*r.mesh, rh, hit);
    }
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
