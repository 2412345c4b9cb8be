// glTF images through OpenImageIO: sizes checked from the header while tinygltf parses the
// file (before anything is decoded), then every image a texture uses decoded once, in
// parallel.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace prism::gltf_detail {

// State of the tinygltf image callback, over one file.
struct ImageGuard {
  std::size_t texels_used = 0;
  std::string element;  // set when an image was refused
  std::string what;
};

// tinygltf's LoadImageDataFunction (user_data: an ImageGuard). Reads only the image's header,
// refuses sizes over the limits of gltf_limits.h, and keeps the encoded bytes in
// tinygltf::Image::image (as_is = true) for decode_images.
bool check_image_header(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                        int req_width, int req_height, const unsigned char* bytes, int size,
                        void* user_data);

// An image's texels normalised to [0, 1] as stored (not linearised), row 0 at the top.
struct DecodedImage {
  int width = 0;
  int height = 0;
  int channels = 0;  // 1..4
  std::vector<float> texels;
};

// Decodes model.images[i] for every i with wanted[i], in parallel; the others stay empty.
// Throws LoadError naming the first (lowest-index) image that cannot be decoded.
std::vector<DecodedImage> decode_images(const tinygltf::Model& model,
                                        const std::vector<bool>& wanted, const std::string& file);

}  // namespace prism::gltf_detail
