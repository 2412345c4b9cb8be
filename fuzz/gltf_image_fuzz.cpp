// libFuzzer target over the loader's image path: each input is the bytes of one glTF image, as a
// data URI, a bufferView or a file would hand them over, checked by check_image_header (format
// by signature, then libpng's or libjpeg-turbo's header) and, when accepted, decoded by
// decode_images. No other decoder may be reached; LoadError is the expected
// answer to bad input, anything else (crash, sanitizer report, other exception) is a bug.
// Seeded with small images of every format OpenImageIO reads (fuzz/seed_corpus.sh --images).
// Built by fuzz/build.sh; see docs/fuzzing.md.
#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_images.h"
#include "scene_io/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace prism::gltf_detail;
  if (size == 0 || size > INT_MAX) return 0;
  const std::string file = "fuzz.gltf";
  // A smaller budget than a real load's, so that the fuzzer's RSS limit is never what stops it.
  MemoryBudget budget(std::size_t{1} << 30, file);
  const BudgetScope scope(budget);
  tinygltf::Model model;
  model.images.resize(1);
  ImageGuard guard;
  guard.declared_type = {(data[0] & 1) ? "image/png" : ""};  // with and without a mimeType
  std::string err;
  try {
    if (!check_image_header(&model.images[0], 0, &err, nullptr, 0, 0, data, int(size), &guard)) {
      if (guard.element.empty() || err.empty()) std::abort();  // refused without saying why
      return 0;
    }
    const std::vector<DecodedImage> decoded = decode_images(model, {true}, file);
    const DecodedImage& d = decoded.at(0);
    const std::size_t expected =
        std::size_t(d.width) * std::size_t(d.height) * std::size_t(d.channels);
    if (d.codes) {  // 8-bit: every code is a valid value, so touching them is the check
      if (d.texels || d.codes->size() != expected) std::abort();
      unsigned long sum = 0;
      for (uint8_t v : *d.codes) sum += v;  // touch every texel under ASan
      if (sum > 255ul * expected) std::abort();
    } else {
      if (!d.texels || d.texels->size() != expected) std::abort();
      float sum = 0.0f;
      for (float v : *d.texels) sum += v;  // touch every texel under ASan
      if (!(sum >= 0.0f)) std::abort();    // normalised values are never negative or NaN
    }
  } catch (const prism::LoadError&) {
  }
  return 0;
}
