// An image texture in linear working-space RGBA, sampled bilinearly with glTF's wrap modes.
#pragma once

#include <vector>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"

namespace prism {

class ColourPipeline;

class Texture {
 public:
  // sRGB-encoded images are linearised into the working space here, once; data images
  // (metallic-roughness, normals, occlusion) keep their values.
  Texture(const TextureImage& image, const ColourPipeline& colour);

  // Bilinear lookup at (u, v), glTF's convention: (0, 0) is the top-left of the image.
  Imath::V4f sample(const Imath::V2f& uv) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Imath::V4f texel(int x, int y) const { return texels_[static_cast<size_t>(y) * width_ + x]; }

  int width_ = 0, height_ = 0;
  TextureWrap wrap_s_, wrap_t_;
  std::vector<Imath::V4f> texels_;
};

}  // namespace prism
