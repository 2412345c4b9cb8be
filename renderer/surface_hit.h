// What an integrator knows about a ray's nearest hit. EmbreeScene fills it; the material
// (renderer/material.h) reads the surface attributes from it.
#pragma once

#include <Imath/ImathVec.h>

namespace prism {

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
  Imath::V2f uv{0.0f, 0.0f};
  int material = -1;       // index into the scene's materials, -1 = default
  bool back_face = false;  // the ray arrived from behind (e.g. from inside a sphere)
};

}  // namespace prism
