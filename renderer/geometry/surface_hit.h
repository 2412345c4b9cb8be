// What an integrator knows about a ray's nearest hit. EmbreeScene fills it; the material
// (renderer/shading/material.h) reads the surface attributes from it.
#pragma once

#include <cstdint>
#include <vector>

#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>

namespace prism {

// The per-vertex data a material may read besides positions and normals, shared by every
// hit on one mesh. A hit only records where it is (SurfaceHit::vertices, barycentrics), and
// the material interpolates what it needs: a hit on an untextured, uncoloured mesh costs
// nothing for them (docs/materials.md, "Cost").
struct VertexAttributes {
  const Imath::V3f* positions = nullptr;  // the mesh's, in the space Embree sees it in
  std::vector<Imath::V2f> texcoords[2];   // TEXCOORD_0, TEXCOORD_1; each per vertex or empty
  std::vector<Imath::V4f> colours;        // COLOR_0 as linear Rec.709 RGBA, or empty
  std::vector<Imath::V4f> tangents;       // xyz unit, w = bitangent sign (glTF), or empty
  bool empty() const {
    return texcoords[0].empty() && texcoords[1].empty() && colours.empty() && tangents.empty();
  }
};

// SurfaceHit::emitter of a surface that emits nothing.
inline constexpr uint32_t kNoEmitter = ~uint32_t(0);

struct SurfaceHit {
  float t = 0.0f;
  Imath::V3f position;          // on the surface, rebuilt from the primitive, not o + t d
  Imath::V3f geometric_normal;  // unit, world space, out of the front (authored) side
  Imath::V3f shading_normal;    // unit, on the same side as geometric_normal
  // Hanika's shadow-terminator fix (Ray Tracing Gems II ch. 4): position + terminator_offset
  // is the hit point moved onto the smooth surface the vertex normals describe, for rays
  // leaving on the front (geometric_normal's) side. Zero for flat triangles and spheres.
  Imath::V3f terminator_offset{0.0f, 0.0f, 0.0f};
  // How far the intersector itself may misplace the surface, beyond the hit point's
  // rounding: a ray must leave by more than this (offset_ray_origin's third argument).
  float surface_error = 0.0f;
  int material = -1;  // index into the scene's materials, -1 = default
  // The emissive primitive hit (EmbreeScene::emitters()), kNoEmitter when the material emits
  // nothing: a path tracer weighs the light a ray finds by that light's own sampling density.
  uint32_t emitter = kNoEmitter;
  bool back_face = false;  // the ray arrived from behind (e.g. from inside a sphere)

  // Where on which triangle, for the attributes: null on spheres and on meshes without any.
  const VertexAttributes* attributes = nullptr;
  uint32_t vertices[3] = {0, 0, 0};
  float barycentric_u = 0.0f, barycentric_v = 0.0f;  // Embree's: weights of vertices[1], [2]
  // The instance's object-to-world transform (row vectors) when the mesh is instanced, for
  // tangents and triangle areas; null when the mesh is baked in world space.
  const Imath::M44f* object_to_world = nullptr;
  // The pixel's footprint for texture filtering: the width across the ray of the cone the
  // pixel sees, at the hit (Ray::cone_width + Ray::cone_spread * t; 0 = unknown, textures
  // are magnified), and |cos| of the angle between the ray and the geometric normal, which
  // stretches the footprint on the surface by 1 / cos.
  float cone_width = 0.0f;
  float cos_incidence = 1.0f;

  // TEXCOORD_set at the hit, (0, 0) where the mesh has none.
  Imath::V2f texcoord(int set) const {
    if (!attributes || set < 0 || set > 1 || attributes->texcoords[set].empty())
      return Imath::V2f(0.0f, 0.0f);
    return interpolate(attributes->texcoords[set]);
  }
  // COLOR_0 (linear Rec.709 RGBA) at the hit, opaque white where the mesh has none.
  Imath::V4f vertex_colour() const {
    if (!attributes || attributes->colours.empty()) return Imath::V4f(1.0f, 1.0f, 1.0f, 1.0f);
    return interpolate(attributes->colours);
  }

  template <typename T>
  T interpolate(const std::vector<T>& values) const {
    const float w = 1.0f - barycentric_u - barycentric_v;
    return values[vertices[0]] * w + values[vertices[1]] * barycentric_u +
           values[vertices[2]] * barycentric_v;
  }
};

}  // namespace prism
