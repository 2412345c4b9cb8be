#include "scene_io/gltf_images.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <tbb/parallel_for.h>

#include "scene_io/gltf_error.h"
#include "scene_io/gltf_limits.h"

namespace prism::gltf_detail {

namespace {

uint32_t be32(const unsigned char* p) {  // PNG stores sizes big-endian
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

// The name OpenImageIO picks its reader by. Images in a buffer or data URI have no file
// name, and a mimeType or extension may lie, so the two formats glTF allows are recognised
// by their signatures; anything else goes by the URI's extension (OpenImageIO tries its
// other readers when that fails too).
std::string format_hint(const tinygltf::Image& image, const unsigned char* bytes,
                        std::size_t size) {
  if (size >= 8 && std::memcmp(bytes, kPngSignature, 8) == 0) return "image.png";
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return "image.jpg";
  const std::string extension = OIIO::Filesystem::extension(image.uri);
  return "image" + (extension.size() <= 8 ? extension : std::string());
}

std::unique_ptr<OIIO::ImageInput> open(const tinygltf::Image& image, const unsigned char* bytes,
                                       std::size_t size, OIIO::Filesystem::IOMemReader* proxy) {
  auto in = OIIO::ImageInput::open(format_hint(image, bytes, size), nullptr, proxy);
  if (!in) OIIO::geterror();  // clear this thread's message: the caller words its own
  return in;
}

// Empty when width x height fits the limits (counting it against the file's total).
std::string size_problem(long long width, long long height, ImageGuard& guard) {
  const std::string size = std::to_string(width) + " x " + std::to_string(height) + " pixels";
  if (width <= 0 || height <= 0 || width > gltf_limits::kMaxImageSide ||
      height > gltf_limits::kMaxImageSide) {
    return size + "; each side is limited to " + std::to_string(gltf_limits::kMaxImageSide);
  }
  const std::size_t texels = std::size_t(width) * std::size_t(height);
  if (texels > gltf_limits::kMaxImageTexels) {
    return size + " exceed the limit of " + std::to_string(gltf_limits::kMaxImageTexels) +
           " pixels per image";
  }
  if (texels > gltf_limits::kMaxTotalImageTexels - guard.texels_used) {
    return "the file's images together exceed the limit of " +
           std::to_string(gltf_limits::kMaxTotalImageTexels) + " pixels";
  }
  guard.texels_used += texels;
  return {};
}

}  // namespace

bool check_image_header(tinygltf::Image* image, const int index, std::string* err,
                        std::string* /*warn*/, int /*req_width*/, int /*req_height*/,
                        const unsigned char* bytes, int size, void* user_data) {
  auto& guard = *static_cast<ImageGuard*>(user_data);
  const auto refuse = [&](const std::string& what) {
    guard.element = indexed("images", std::size_t(index));
    guard.what = what;
    if (err) *err += guard.element + ": " + what + "\n";
    return false;
  };
  if (size <= 0) return refuse("the image is empty");
  OIIO::Filesystem::IOMemReader proxy(bytes, std::size_t(size));
  const std::unique_ptr<OIIO::ImageInput> in = open(*image, bytes, std::size_t(size), &proxy);
  if (!in) {
    // A PNG whose header is fine but whose data is cut short (or a hostile header alone)
    // fails to open; its claimed size is still worth stating when it is the problem.
    if (size >= 24 && std::memcmp(bytes, kPngSignature, 8) == 0 &&
        std::memcmp(bytes + 12, "IHDR", 4) == 0) {
      const std::string problem = size_problem(be32(bytes + 16), be32(bytes + 20), guard);
      if (!problem.empty()) return refuse(problem);
    }
    return refuse("not an image in a format the decoder reads (PNG, JPEG, ...)");
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (const std::string problem = size_problem(spec.width, spec.height, guard); !problem.empty())
    return refuse(problem);
  if (spec.nchannels < 1) return refuse("the image has no channels");
  image->width = spec.width;
  image->height = spec.height;
  image->component = std::min(spec.nchannels, 4);
  image->bits = static_cast<int>(8 * spec.format.size());
  image->as_is = true;  // the encoded file, decoded later by decode_images
  image->image.assign(bytes, bytes + size);
  return true;
}

std::vector<DecodedImage> decode_images(const tinygltf::Model& model,
                                        const std::vector<bool>& wanted, const std::string& file) {
  const std::size_t count = model.images.size();
  std::vector<DecodedImage> out(count);
  std::vector<std::string> errors(count);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    if (i >= wanted.size() || !wanted[i]) return;
    const tinygltf::Image& image = model.images[i];
    if (!image.as_is || image.image.empty()) {
      errors[i] = "the image could not be read";
      return;
    }
    OIIO::Filesystem::IOMemReader proxy(image.image.data(), image.image.size());
    const std::unique_ptr<OIIO::ImageInput> in =
        open(image, image.image.data(), image.image.size(), &proxy);
    // The header was read before: a size that changed is a broken reader, not a new file.
    if (!in || in->spec().width != image.width || in->spec().height != image.height) {
      errors[i] = "the image cannot be decoded";
      return;
    }
    DecodedImage& d = out[i];
    d.width = image.width;
    d.height = image.height;
    d.channels = image.component;
    d.texels.resize(std::size_t(d.width) * std::size_t(d.height) * std::size_t(d.channels));
    // Integer formats arrive normalised to [0, 1], as glTF defines their values.
    if (!in->read_image(0, 0, 0, d.channels, OIIO::TypeDesc::FLOAT, d.texels.data())) {
      const std::string why = one_line(in->geterror());
      errors[i] = "the image cannot be decoded" + (why.empty() ? std::string() : ": " + why);
      d = DecodedImage();
      return;
    }
    // Float formats (EXR, HDR) may hold anything; a texel must at least be a number.
    for (float& v : d.texels)
      if (!std::isfinite(v)) v = 0.0f;
  });
  for (std::size_t i = 0; i < count; ++i)
    if (!errors[i].empty()) fail(file, indexed("images", i), errors[i]);
  return out;
}

}  // namespace prism::gltf_detail
