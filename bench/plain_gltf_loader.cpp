// The yardstick for Prism's texture loading (docs/benchmarks.md, "Textured level against a
// plain loader"): tinygltf as it comes, reading a .gltf or .glb with its own image decoder
// (stb_image, one image after another) and keeping every texel as the 8-bit codes the file
// holds. It checks nothing, converts nothing and builds no BVH, so what Prism spends beyond
// it is validation, colour conversion, mip levels and the BVH.
//
//     build/bench/plain_gltf_loader SCENE.{gltf,glb}
//
// Prints the load's seconds, the images and their texel bytes; peak memory is the process's
// (measure it from outside, e.g. with /usr/bin/time).
#include <chrono>
#include <cstdio>
#include <string>

#include <tiny_gltf.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: plain_gltf_loader SCENE.{gltf,glb}\n");
    return 2;
  }
  const std::string path = argv[1];
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  const auto start = std::chrono::steady_clock::now();
  const bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                         : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ok) {
    std::fprintf(stderr, "plain_gltf_loader: %s: %s\n", path.c_str(), error.c_str());
    return 1;
  }
  size_t texel_bytes = 0, buffer_bytes = 0;
  for (const tinygltf::Image& image : model.images) texel_bytes += image.image.size();
  for (const tinygltf::Buffer& buffer : model.buffers) buffer_bytes += buffer.data.size();
  std::printf("%s: loaded in %.3f s: %zu images, %zu texel bytes, %zu buffer bytes\n", path.c_str(),
              seconds, model.images.size(), texel_bytes, buffer_bytes);
  return 0;
}
