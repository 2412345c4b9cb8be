// An image texture in linear working-space RGBA with its mip pyramid, sampled with the glTF
// sampler's wrap modes and min/mag filters (docs/materials.md, "Texture sampling").
#pragma once

#include <memory>
#include <vector>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"

namespace prism {

class ColourPipeline;

class Texture {
 public:
  // sRGB-encoded images are linearised into the working space here, once; data images
  // (metallic-roughness, normals, occlusion) keep their values. The mip pyramid is built
  // here too, from the linear values.
  Texture(const TextureImage& image, const ColourPipeline& colour);

  // The texel values at (u, v), glTF's convention: (0, 0) is the top-left of the image.
  // `footprint` is the width of the pixel's footprint on the surface in UV units (1 = the
  // whole image): at most one texel magnifies (magFilter on the full image), more minifies
  // (minFilter on the mip level whose texels are that wide, or between the two nearest).
  Imath::V4f sample(const Imath::V2f& uv, float footprint = 0.0f) const;

  int width() const { return levels_->front().width; }
  int height() const { return levels_->front().height; }
  int levels() const { return static_cast<int>(levels_->size()); }

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<Imath::V4f> texels;
    Imath::V4f texel(int x, int y) const { return texels[static_cast<size_t>(y) * width + x]; }
  };
  friend std::vector<Texture> make_textures(const std::vector<TextureImage>&,
                                            const ColourPipeline&);
  Texture(std::shared_ptr<const std::vector<Level>> levels, const TextureImage& sampler);
  static std::shared_ptr<const std::vector<Level>> build_levels(const TextureImage& image,
                                                                const ColourPipeline& colour);
  Imath::V4f lookup(const Level& level, const Imath::V2f& uv, TextureFilter filter) const;

  std::shared_ptr<const std::vector<Level>> levels_;  // [0] the image, each next half as wide
  TextureWrap wrap_s_, wrap_t_;
  TextureFilter mag_filter_, min_filter_;
  MipMode mip_mode_;
};

// One Texture per description, built in parallel; textures that read the same decoded
// image (TextureImage::image) with the same encoding share one linearised pyramid.
std::vector<Texture> make_textures(const std::vector<TextureImage>& images,
                                   const ColourPipeline& colour);

}  // namespace prism
