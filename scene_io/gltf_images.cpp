#include "scene_io/gltf_images.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include <tbb/parallel_for.h>

#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"
#include "scene_io/gltf_limits.h"
#include "scene_io/image_decoders.h"

namespace prism::gltf_detail {

namespace {

uint32_t be32(const unsigned char* p) {  // PNG stores sizes big-endian
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
constexpr unsigned char kKtx2Signature[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                              '0',  0xBB, '\r', '\n', 0x1A, '\n'};

enum class Format { png, jpeg, webp, ktx2, other };

// By the signature alone: a mimeType, a data: URI's media type or a file's extension may lie,
// and no decoder but the format's own may ever see a glTF image.
Format sniff(const unsigned char* bytes, std::size_t size) {
  if (size >= 8 && std::memcmp(bytes, kPngSignature, 8) == 0) return Format::png;
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return Format::jpeg;
  if (size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0)
    return Format::webp;
  if (size >= 12 && std::memcmp(bytes, kKtx2Signature, 12) == 0) return Format::ktx2;
  return Format::other;
}

const char* media_type(Format f) {
  switch (f) {
    case Format::png:
      return "image/png";
    case Format::jpeg:
      return "image/jpeg";
    case Format::webp:
      return "image/webp";
    case Format::ktx2:
      return "image/ktx2";
    default:
      return "";
  }
}

// The first bytes in hex, to say what an unrecognised image starts with.
std::string first_bytes(const unsigned char* bytes, std::size_t size) {
  std::string out;
  char hex[4];
  for (std::size_t i = 0; i < std::min<std::size_t>(size, 8); ++i) {
    std::snprintf(hex, sizeof hex, "%s%02X", i ? " " : "", bytes[i]);
    out += hex;
  }
  return out;
}

// Empty when the image's format and declared media type are accepted; else why not.
std::string format_problem(Format format, const std::string& declared, const unsigned char* bytes,
                           std::size_t size) {
  switch (format) {
    case Format::webp:
      return "a WebP image (EXT_texture_webp), which is not supported; glTF images must be PNG "
             "or JPEG";
    case Format::ktx2:
      return "a KTX2 image (KHR_texture_basisu), which is not supported; glTF images must be "
             "PNG or JPEG";
    case Format::other:
      return "not a PNG or JPEG image (it starts with " + first_bytes(bytes, size) +
             "); glTF images must be PNG or JPEG";
    default:
      break;
  }
  if (!declared.empty() && declared != media_type(format)) {
    return "declared as " + shown(declared) + " but the bytes are " +
           (format == Format::png ? "PNG" : "JPEG");
  }
  return {};
}

uint16_t be16(const unsigned char* p) {
  return uint16_t(p[0] << 8 | p[1]);
}

// The number of scans (SOS markers) of a JPEG, walked from its markers: a progressive JPEG's
// decoding time grows with its scans, and libjpeg accepts thousands. -1 when the marker
// structure is broken (the decoder then refuses the file itself).
long jpeg_scans(const unsigned char* bytes, std::size_t size) {
  long scans = 0;
  std::size_t pos = 2;  // after SOI
  while (pos + 1 < size) {
    if (bytes[pos] != 0xFF) return -1;
    const unsigned char marker = bytes[pos + 1];
    if (marker == 0xFF) {  // fill byte
      ++pos;
      continue;
    }
    if (marker == 0xD9) break;  // EOI
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {
      pos += 2;
      continue;
    }
    if (pos + 4 > size) return -1;
    const std::size_t length = be16(bytes + pos + 2);
    if (length < 2 || length > size - pos - 2) return -1;
    pos += 2 + length;
    if (marker != 0xDA) continue;
    ++scans;
    // Entropy-coded data runs to the next marker that is neither a stuffed 0xFF00 nor RSTn.
    while (pos + 1 < size && !(bytes[pos] == 0xFF && bytes[pos + 1] != 0x00 &&
                               !(bytes[pos + 1] >= 0xD0 && bytes[pos + 1] <= 0xD7))) {
      ++pos;
    }
  }
  return scans;
}

// The bytes of the image's pixels as the format stores them before compression: for PNG from
// its IHDR (bit depth x samples of the colour type, rows rounded up to bytes), for JPEG
// 8 bits per channel.
std::size_t raw_bytes(Format format, const unsigned char* bytes, std::size_t size,
                      std::size_t width, std::size_t height, int channels) {
  if (format != Format::png || size < 26) return width * height * std::size_t(channels);
  const unsigned depth = bytes[24];
  const unsigned samples = bytes[25] == 2 ? 3 : bytes[25] == 4 ? 2 : bytes[25] == 6 ? 4 : 1;
  return height * ((width * depth * samples + 7) / 8);
}

std::string read_header(Format format, const unsigned char* bytes, std::size_t size,
                        ImageHeader* header) {
  return format == Format::png ? read_png_header(bytes, size, header)
                               : read_jpeg_header(bytes, size, header);
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
  const std::string element = indexed("images", std::size_t(index));
  const auto refuse = [&](const std::string& what) {
    guard.element = element;
    guard.what = what;
    if (err) *err += element + ": " + what + "\n";
    return false;
  };
  if (size <= 0) return refuse("the image is empty");
  const Format format = sniff(bytes, std::size_t(size));
  const std::string declared = std::size_t(index) < guard.declared_type.size()
                                   ? guard.declared_type[std::size_t(index)]
                                   : std::string();
  if (const std::string problem = format_problem(format, declared, bytes, std::size_t(size));
      !problem.empty())
    return refuse(problem);
  ImageHeader spec;
  if (const std::string problem = read_header(format, bytes, std::size_t(size), &spec);
      !problem.empty()) {
    // A PNG whose header is fine but whose data is cut short (or a hostile header alone)
    // fails to open; its claimed size is still worth stating when it is the problem.
    if (size >= 24 && format == Format::png && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
      const std::string size_issue = size_problem(be32(bytes + 16), be32(bytes + 20), guard);
      if (!size_issue.empty()) return refuse(size_issue);
    }
    return refuse(problem);
  }
  if (const std::string problem = size_problem(spec.width, spec.height, guard); !problem.empty())
    return refuse(problem);
  // A decompression bomb: a small file claiming a huge image would have its texels allocated
  // (and zeroed) before the decoder found the data missing.
  const std::size_t raw = raw_bytes(format, bytes, std::size_t(size), std::size_t(spec.width),
                                    std::size_t(spec.height), spec.channels);
  const std::size_t ratio =
      format == Format::png ? gltf_limits::kMaxPngRatio : gltf_limits::kMaxJpegRatio;
  if (raw / ratio > std::size_t(size)) {
    return refuse(std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                  " pixels cannot be encoded in " + std::to_string(size) + " bytes (" +
                  (format == Format::png ? "PNG" : "JPEG") + " compresses at most " +
                  std::to_string(ratio) + ":1)");
  }
  if (format == Format::jpeg) {
    const long scans = jpeg_scans(bytes, std::size_t(size));
    const std::size_t pixels = std::size_t(spec.width) * std::size_t(spec.height);
    if (scans > gltf_limits::kMaxJpegScans ||
        (scans > 0 && pixels > gltf_limits::kMaxJpegScanPixels / std::size_t(scans))) {
      return refuse(std::to_string(scans) + " JPEG scans of " + std::to_string(pixels) +
                    " pixels exceed the decoding limits (" +
                    std::to_string(gltf_limits::kMaxJpegScans) + " scans, " +
                    std::to_string(gltf_limits::kMaxJpegScanPixels) + " pixels x scans)");
    }
  }
  image->width = spec.width;
  image->height = spec.height;
  image->component = spec.channels;
  image->bits = spec.bits;
  image->as_is = true;  // the encoded file, decoded later by decode_images
  image->mimeType = media_type(format);
  // The decoded texels (8-bit codes as bytes, 16-bit samples as floats) and the copy of the
  // encoded bytes kept until then.
  charge(std::size_t(spec.width) * std::size_t(spec.height),
         std::size_t(image->component) * (spec.bits == 8 ? 1 : sizeof(float)), element);
  charge(std::size_t(size), 1, element);
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
    const Format format = sniff(image.image.data(), image.image.size());
    ImageHeader header;
    // The header was read before: a size that changed is a broken reader, not a new file.
    if (!read_header(format, image.image.data(), image.image.size(), &header).empty() ||
        header.width != image.width || header.height != image.height ||
        header.channels != image.component) {
      errors[i] = "the image cannot be decoded";
      return;
    }
    DecodedImage& d = out[i];
    d.width = image.width;
    d.height = image.height;
    d.channels = image.component;
    const std::size_t values =
        std::size_t(d.width) * std::size_t(d.height) * std::size_t(d.channels);
    std::string why;
    if (header.bits == 8) {
      auto codes = std::make_shared<std::vector<uint8_t>>(values);
      why = format == Format::png
                ? decode_png(image.image.data(), image.image.size(), header, codes->data())
                : decode_jpeg(image.image.data(), image.image.size(), header, codes->data());
      d.codes = std::move(codes);
    } else {
      // 16-bit samples, normalised as glTF defines integer values (v / 65535, rounded as
      // v * (1 / 65535)); the samples' own buffer lives only as long as this conversion.
      std::vector<uint16_t> samples(values);
      why = decode_png(image.image.data(), image.image.size(), header,
                       reinterpret_cast<unsigned char*>(samples.data()));
      auto texels = std::make_shared<std::vector<float>>(values);
      const float scale = 1.0f / 65535.0f;
      for (std::size_t k = 0; k < values; ++k) (*texels)[k] = float(samples[k]) * scale;
      d.texels = std::move(texels);
    }
    if (!why.empty()) {
      errors[i] = "the image cannot be decoded: " + why;
      d = DecodedImage();
    }
  });
  for (std::size_t i = 0; i < count; ++i)
    if (!errors[i].empty()) fail(file, indexed("images", i), errors[i]);
  return out;
}

}  // namespace prism::gltf_detail
