// How long writing a large EXR master takes, by compression and thread count, and how big it
// is: the measurement behind kDefaultExrCompression (docs/benchmarks.md, "EXR writing").
//
//   prism render scenes/whitted.gltf --res 4000x3000 --spp 4 -o /tmp/big.exr
//   build/bench/exr_write_bench /tmp/big.exr [ROUNDS]
//
// Reads the render once, then writes it ROUNDS times (default 5) with every lossless
// compression on 1 and 2 threads and, as the path Prism used before, through OpenImageIO
// (zip, its default thread pool), interleaved round by round so a change in the machine's load
// falls on every variant alike; prints each variant's median seconds and the file's size.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "renderer/image/exr_file.h"

namespace {

using prism::ExrCompression;

struct Variant {
  std::string name;
  std::function<void(const std::string&)> write;
  std::vector<double> seconds;
  uintmax_t bytes = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s IMAGE.exr [ROUNDS]\n", argv[0]);
    return 2;
  }
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const prism::Image image = prism::read_exr_file(argv[1]);
  const std::string out =
      (std::filesystem::temp_directory_path() / "prism_exr_write_bench.exr").string();

  std::vector<Variant> variants;
  const auto add = [&](ExrCompression c, int level, int threads) {
    std::string name = prism::to_string(c);
    if (c == ExrCompression::zip || c == ExrCompression::zips)
      name += " level " + std::to_string(level);
    name += threads == 1 ? ", 1 thread" : ", " + std::to_string(threads) + " threads";
    variants.push_back({name,
                        [&image, c, level, threads](const std::string& path) {
                          prism::write_exr_file(path, image, {},
                                                {prism::ExrPixelType::float32, c, threads, level});
                        },
                        {},
                        0});
  };
  for (int threads : {1, 2}) {
    for (ExrCompression c : {ExrCompression::none, ExrCompression::rle, ExrCompression::piz})
      add(c, 0, threads);
    for (ExrCompression c : {ExrCompression::zips, ExrCompression::zip})
      for (int level : {1, 4, 6}) add(c, level, threads);
  }
  variants.push_back({"OpenImageIO (zip), as before",
                      [&image](const std::string& path) {
                        OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
                        spec.attribute("compression", "zip");
                        auto o = OIIO::ImageOutput::create(path);
                        if (!o || !o->open(path, spec) ||
                            !o->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data()) ||
                            !o->close())
                          std::fprintf(stderr, "OpenImageIO: %s\n", OIIO::geterror().c_str());
                      },
                      {},
                      0});

  for (int r = 0; r < rounds; ++r) {
    for (Variant& v : variants) {
      const auto start = std::chrono::steady_clock::now();
      v.write(out);
      v.seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      v.bytes = std::filesystem::file_size(out);
    }
  }
  std::filesystem::remove(out);
  std::printf("%s: %d x %d float RGBA, %d rounds\n\n", argv[1], image.width, image.height, rounds);
  std::printf("| write | median s | MiB |\n| --- | --- | --- |\n");
  for (const Variant& v : variants)
    std::printf("| %s | %.3f | %.1f |\n", v.name.c_str(), median(v.seconds),
                double(v.bytes) / (1024.0 * 1024.0));
  return 0;
}
