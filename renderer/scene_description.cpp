#include "renderer/scene_description.h"

#include <unordered_set>

namespace prism {
namespace {

template <typename T>
uint64_t bytes_of(const std::vector<T>& v) {
  return static_cast<uint64_t>(v.capacity()) * sizeof(T);
}

}  // namespace

uint64_t description_bytes(const SceneDescription& scene) {
  uint64_t bytes = 0;
  for (const Mesh& mesh : scene.meshes)
    for (const Primitive& p : mesh.primitives)
      bytes += bytes_of(p.positions) + bytes_of(p.normals) + bytes_of(p.uv0) + bytes_of(p.uv1) +
               bytes_of(p.colours) + bytes_of(p.tangents) + bytes_of(p.indices);
  // Textures that read one image (a sampler or an encoding apart) share its texels: each
  // shared buffer is counted once.
  std::unordered_set<const void*> counted;
  for (const TextureImage& t : scene.textures) {
    if (t.shared_codes) {
      if (counted.insert(t.shared_codes.get()).second) bytes += bytes_of(*t.shared_codes);
    } else if (t.shared_texels) {
      if (counted.insert(t.shared_texels.get()).second) bytes += bytes_of(*t.shared_texels);
    } else {
      bytes += bytes_of(t.texels);
    }
  }
  bytes += bytes_of(scene.meshes) + bytes_of(scene.instances) + bytes_of(scene.spheres) +
           bytes_of(scene.materials) + bytes_of(scene.lights) + bytes_of(scene.cameras);
  return bytes;
}

}  // namespace prism
