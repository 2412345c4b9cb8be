#include "renderer/geometry/alpha_filter.h"

#include <bit>

#include "renderer/sampling/random.h"

namespace prism {
namespace {

uint64_t float_bits(float f) {
  return std::bit_cast<uint32_t>(f);
}

// Keeps or drops the candidate hit `i` of a filter call under the geometry's alpha rule.
bool keeps_alpha(const SurfaceFilter& f, const RTCFilterFunctionNArguments* args, unsigned i) {
  if (f.mode == AlphaMode::opaque) return true;
  const unsigned n = args->N;
  const unsigned primitive = RTCHitN_primID(args->hit, n, i);
  const float alpha = f.alpha(primitive, RTCHitN_u(args->hit, n, i), RTCHitN_v(args->hit, n, i));
  if (f.mode == AlphaMode::mask) return alpha >= f.cutoff;
  const auto* context = reinterpret_cast<const TraceContext*>(args->context);
  // The ray's own id, not i: Embree may hand a 16-ray packet to the filters in narrower
  // batches (two of 8 on AVX2), where i is the lane within the batch. The packet's id
  // fields hold each ray's index into context->rays (set_packet_lane); a single ray's is 0.
  const unsigned lane = RTCRayN_id(args->ray, n, i);
  return blend_uniform(ray_hash(context->rays[lane]), RTCHitN_instID(args->hit, n, i, 0),
                       RTCHitN_geomID(args->hit, n, i), primitive) < alpha;
}

// Shadow and camera rays alike: alpha decides whether a surface is there at all.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto& f = *static_cast<const SurfaceFilter*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && !keeps_alpha(f, args, i)) args->valid[i] = 0;
}

}  // namespace

void cull_camera_back_faces(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const TraceContext*>(args->context);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] == 0) continue;
    if (!context->culling->culls(RTCHitN_instID(args->hit, n, i, 0),
                                 RTCHitN_geomID(args->hit, n, i)))
      continue;
    // Ray and Ng are both in the hit geometry's own space (object space inside an instance),
    // where the sign of their dot product says which side the ray arrives at whatever the
    // transform. Embree's Ng points out of the counter-clockwise front face.
    const float facing = RTCRayN_dir_x(args->ray, n, i) * RTCHitN_Ng_x(args->hit, n, i) +
                         RTCRayN_dir_y(args->ray, n, i) * RTCHitN_Ng_y(args->hit, n, i) +
                         RTCRayN_dir_z(args->ray, n, i) * RTCHitN_Ng_z(args->hit, n, i);
    if (facing > 0.0f) args->valid[i] = 0;
  }
}

float SurfaceFilter::alpha(unsigned primitive, float u, float v) const {
  if (!material) return alpha_factor;
  // Only what base_colour_alpha reads: where the hit is, at the texture's finest level.
  SurfaceHit hit;
  hit.attributes = attributes;
  const uint32_t* tri = &indices[static_cast<size_t>(primitive) * 3];
  hit.vertices[0] = tri[0];
  hit.vertices[1] = tri[1];
  hit.vertices[2] = tri[2];
  hit.barycentric_u = u;
  hit.barycentric_v = v;
  return base_colour_alpha(*material, hit);
}

SurfaceFilter make_surface_filter(const MaterialDescription* description, const Material* material,
                                  const uint32_t* indices, const VertexAttributes* attributes) {
  SurfaceFilter f;
  f.indices = indices;
  f.attributes = attributes;
  if (!description || description->alpha_mode == AlphaMode::opaque) return f;
  f.mode = description->alpha_mode;
  f.cutoff = description->alpha_cutoff;
  f.alpha_factor = description->alpha;
  f.material = material;
  const bool varies = material && (material->base_colour_texture.texture ||
                                   (attributes && !attributes->colours.empty()));
  if (!varies) {
    const float alpha = material ? material->alpha : f.alpha_factor;
    const bool always_kept = f.mode == AlphaMode::mask ? alpha >= f.cutoff : alpha >= 1.0f;
    if (always_kept) f.mode = AlphaMode::opaque;
  }
  return f;
}

void attach_surface_filter(RTCGeometry geometry, const SurfaceFilter* filter) {
  if (!needs_filter(*filter)) return;
  rtcSetGeometryUserData(geometry, const_cast<SurfaceFilter*>(filter));
  rtcSetGeometryIntersectFilterFunction(geometry, alpha_filter);
  rtcSetGeometryOccludedFilterFunction(geometry, alpha_filter);
}

uint64_t ray_hash(const Ray& ray) {
  uint64_t h = mix64(float_bits(ray.origin.x) | float_bits(ray.origin.y) << 32);
  h = mix64(h ^ (float_bits(ray.origin.z) | float_bits(ray.direction.x) << 32));
  return mix64(h ^ (float_bits(ray.direction.y) | float_bits(ray.direction.z) << 32));
}

float blend_uniform(uint64_t ray_hash, unsigned instance, unsigned geometry, unsigned primitive) {
  const uint64_t key = mix64(ray_hash ^ (static_cast<uint64_t>(instance) << 32 | geometry)) ^
                       (static_cast<uint64_t>(primitive) * 0x9e3779b97f4a7c15ULL);
  // The top 24 bits: every float in [0, 1) with spacing 2^-24, never 1.0, so alpha 1 always
  // keeps the hit and alpha 0 never does.
  return static_cast<float>(mix64(key) >> 40) * 0x1.0p-24f;
}

}  // namespace prism
