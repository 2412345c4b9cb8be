// glTF images through libpng and libjpeg-turbo (image_decoders.h): sizes checked from the
// header while tinygltf parses the file (before anything is decoded), then every image a
// texture uses decoded once, in parallel.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace prism::gltf_detail {

// State of the tinygltf image callback, over one file.
struct ImageGuard {
  // Per image, the media type the file declares for it ("" for none): its mimeType, or the
  // media type of its data: URI. The bytes' signature must agree with it.
  std::vector<std::string> declared_type;
  std::size_t texels_used = 0;
  std::string element;  // set when an image was refused
  std::string what;
};

// tinygltf's LoadImageDataFunction (user_data: an ImageGuard). Accepts PNG and JPEG only,
// recognised by their signatures (and agreeing with the declared media type) before any
// decoder sees the bytes; reads only the header through the format's own reader, refuses sizes
// over the limits of gltf_limits.h, volumes (depth > 1) and JPEGs with too many scans,
// charges the decoded texels to the load's budget, and keeps the encoded bytes in
// tinygltf::Image::image (as_is = true) for decode_images.
bool check_image_header(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                        int req_width, int req_height, const unsigned char* bytes, int size,
                        void* user_data);

// An image's texels as stored (not linearised), row 0 at the top: an 8-bit image (every JPEG,
// most PNGs) as its codes, a 16-bit PNG normalised to [0, 1] as v * (1.0f / 65535.0f).
// Shared by every texture that reads the image, whatever its sampler or encoding.
struct DecodedImage {
  int width = 0;
  int height = 0;
  int channels = 0;                                   // 1..4
  std::shared_ptr<const std::vector<uint8_t>> codes;  // set for 8-bit images
  std::shared_ptr<const std::vector<float>> texels;   // set for 16-bit images
};

// Decodes model.images[i] for every i with wanted[i], in parallel; the others stay empty.
// Throws LoadError naming the first (lowest-index) image that cannot be decoded.
std::vector<DecodedImage> decode_images(const tinygltf::Model& model,
                                        const std::vector<bool>& wanted, const std::string& file);

}  // namespace prism::gltf_detail
