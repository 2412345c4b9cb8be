// glTF's alphaMode and doubleSided as Embree geometry filters, decided at each candidate hit
// during traversal, so that every query agrees on what exists: camera rays, reflection and
// refraction rays, and shadow rays (a cut-out leaf casts a leaf-shaped shadow).
//
//   - MASK: a hit whose alpha (baseColorFactor alpha x base colour texture alpha x COLOR_0
//     alpha, at the hit's texture coordinates) is below alphaCutoff does not exist; at or
//     above it the surface is opaque (glTF: "greater than or equal to ... fully opaque").
//   - BLEND: stochastic transparency, as pbrt-v4 does. A hit is kept with probability
//     alpha, drawn from a hash of the ray, the primitive and the instance, so the choice is
//     the same every time Embree reports that hit (it may report one more than once), and
//     the image is the same for any thread count. Averaged over samples a pixel converges
//     to alpha x surface + (1 - alpha) x what lies behind, and a shadow ray through it to
//     (1 - alpha) of the light: glTF's "over" blending, in any order, with no sorting.
//   - doubleSided false (glTF's default): camera rays pass through back faces, as the glTF
//     viewers' back-face culling shows them; secondary and shadow rays see both sides, so a
//     closed single-sided object still casts shadows and glass still refracts out of its
//     back faces (docs/materials.md explains the choice).
//
// Alpha filters are attached only to geometries whose material needs one: an opaque mesh,
// and every sphere, costs nothing. Culling is not a geometry filter: a filter on every
// single-sided mesh (most glTF files) ran on every candidate hit of every ray and cost 4-5 %
// of the render (docs/benchmarks.md), while a camera ray's nearest hit is a back face only
// rarely. EmbreeScene traces camera rays without culling and, only when the nearest hit is
// the back face of a single-sided mesh, traces that ray once more with
// cull_camera_back_faces as the context filter: the hit found is the one a culling filter
// would have found. Spheres ignore alpha modes and are seen from both sides in all three
// sphere modes.
#pragma once

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>
#include <embree3/rtcore.h>

#include "renderer/geometry/ray.h"
#include "renderer/geometry/surface_hit.h"
#include "renderer/scene_description.h"
#include "renderer/shading/material.h"

namespace prism {

// What EmbreeScene hands to each query. Embree passes the context pointer unchanged to the
// filters (rtcInitIntersectContext(3)), which is how they learn about the ray as Prism
// traced it: its kind, and the world-frame origin and direction the BLEND hash reads (the
// filter's own ray is in object space inside instances).
struct BackFaceCulling;

struct TraceContext {
  RTCIntersectContext embree;  // first, so that a pointer to it is a pointer to this
  // The traced rays, by the ray id Embree gives the filters (RTCRayN_id: the lane of the
  // packet as Prism built it, 0 for rtcIntersect1).
  const Ray* rays = nullptr;
  // Set, with embree.filter = cull_camera_back_faces, only for a culling trace.
  const BackFaceCulling* culling = nullptr;

  explicit TraceContext(const Ray* traced) : rays(traced) { rtcInitIntersectContext(&embree); }
};

// Which triangle geometries belong to single-sided materials, by Embree's ids: a geometry of
// the top-level scene by its geomID, one inside an instance by the instance's geomID (the
// hit's instID[0]) and its geomID in the instanced scene.
struct BackFaceCulling {
  std::vector<uint8_t> top_level;                      // 1: single-sided
  std::vector<const std::vector<uint8_t>*> instanced;  // the prototype's flags, or null
  bool any = false;                                    // some geometry is single-sided

  bool culls(unsigned instance, unsigned geometry) const {
    if (instance != RTC_INVALID_GEOMETRY_ID) {
      const std::vector<uint8_t>* flags =
          instance < instanced.size() ? instanced[instance] : nullptr;
      return flags && geometry < flags->size() && (*flags)[geometry] != 0;
    }
    return geometry < top_level.size() && top_level[geometry] != 0;
  }
};

// The context filter of a culling trace: drops back-face hits on single-sided geometries.
// The scenes traced must have RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION.
void cull_camera_back_faces(const RTCFilterFunctionNArguments* args);

// One triangle geometry's filter state: the material's rule, and where the alpha at a hit
// comes from. Points into the material and the mesh, which must outlive it and not move.
struct SurfaceFilter {
  AlphaMode mode = AlphaMode::opaque;
  float cutoff = 0.5f;
  // The alpha is base_colour_alpha(*material, hit) (renderer/shading/material.h: the factor, the
  // base colour texture through its texCoord and transform, COLOR_0), the same as the
  // shading reads; alpha_factor alone when there is no resolved material.
  const Material* material = nullptr;
  float alpha_factor = 1.0f;
  const uint32_t* indices = nullptr;             // 3 per triangle
  const VertexAttributes* attributes = nullptr;  // null: the mesh has none

  // The alpha at barycentrics (u, v) of triangle `primitive`, Embree's convention: the point
  // is (1 - u - v) p0 + u p1 + v p2.
  float alpha(unsigned primitive, float u, float v) const;
};

// The filter a material needs on a triangle mesh. `description` null is glTF's default
// material (opaque, single-sided); `material` is its resolved form, or null to read the
// alpha factor alone. An alpha that cannot vary over the mesh and always keeps the hit
// (BLEND at 1, MASK at or above the cutoff, with no base colour texture and no COLOR_0) is
// turned into mode opaque.
SurfaceFilter make_surface_filter(const MaterialDescription* description, const Material* material,
                                  const uint32_t* indices, const VertexAttributes* attributes);

// True when `filter` changes any query (alpha testing).
inline bool needs_filter(const SurfaceFilter& filter) {
  return filter.mode != AlphaMode::opaque;
}

// Whether camera rays skip the back faces of a mesh of this material: glTF's doubleSided
// false, the default (null is glTF's default material).
inline bool is_single_sided(const MaterialDescription* description) {
  return !description || !description->double_sided;
}

// Registers `filter`'s intersection and occlusion filters on an uncommitted triangle
// geometry, when it needs them.
void attach_surface_filter(RTCGeometry geometry, const SurfaceFilter* filter);

// The hash of a traced ray that the BLEND decision starts from, and the uniform number in
// [0, 1) it gives for one primitive of one geometry of one instance (RTC_INVALID_GEOMETRY_ID
// when not instanced). Exposed for tests.
uint64_t ray_hash(const Ray& ray);
float blend_uniform(uint64_t ray_hash, unsigned instance, unsigned geometry, unsigned primitive);

}  // namespace prism
