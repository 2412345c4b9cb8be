// An image texture in linear working-space RGBA with its mip pyramid, sampled with the glTF
// sampler's wrap modes and min/mag filters (docs/materials.md, "Texture sampling").
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Imath/ImathVec.h>

#include "renderer/scene_description.h"

namespace prism {

class ColourPipeline;

class Texture {
 public:
  // An 8-bit image stays 8-bit: its codes convert at lookup through a table of the 256 values
  // (for sRGB-encoded images, what the colour pipeline gives each code; data images,
  // metallic-roughness, normals, occlusion, keep code / 255). Other images, and sRGB images
  // under a working space whose transform mixes channels, are linearised here, once. The mip
  // pyramid is built here too, from the linear values.
  Texture(const TextureImage& image, const ColourPipeline& colour);

  // The texel values at (u, v), glTF's convention: (0, 0) is the top-left of the image.
  // `footprint` is the width of the pixel's footprint on the surface in UV units (1 = the
  // whole image): at most one texel magnifies (magFilter on the full image), more minifies
  // (minFilter on the mip level whose texels are that wide, or between the two nearest).
  Imath::V4f sample(const Imath::V2f& uv, float footprint = 0.0f) const;

  int width() const { return pyramid_->levels.front().width; }
  int height() const { return pyramid_->levels.front().height; }
  int levels() const { return static_cast<int>(pyramid_->levels.size()); }
  // Bytes the pyramid holds beyond the image it reads (the 8-bit codes are the image's own).
  size_t bytes() const;

 private:
  // How a level's 8-bit codes become values: per colour channel (the working-space value of
  // an sRGB code, or code / 255 for data) and for alpha (always code / 255).
  struct CodeTable {
    std::array<std::array<float, 256>, 3> colour;
    std::array<float, 256> alpha;
  };
  // Texels in an image's channel layout: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA, grey
  // broadcast to RGB and a missing alpha opaque. 8-bit codes (the loaded image's own bytes,
  // converted at lookup through `table`), or floats: the values themselves, in the smallest
  // layout that holds them exactly.
  struct Level {
    int width = 0, height = 0, channels = 4;
    const uint8_t* codes = nullptr;
    const CodeTable* table = nullptr;
    std::vector<float> values;
    Imath::V4f texel(int x, int y) const {
      const size_t i = (static_cast<size_t>(y) * width + x) * channels;
      if (codes) {
        const uint8_t* t = codes + i;
        const auto& c = table->colour;
        if (channels >= 3)
          return {c[0][t[0]], c[1][t[1]], c[2][t[2]], channels == 4 ? table->alpha[t[3]] : 1.0f};
        return {c[0][t[0]], c[1][t[0]], c[2][t[0]], channels == 2 ? table->alpha[t[1]] : 1.0f};
      }
      const float* t = &values[i];
      if (channels >= 3) return {t[0], t[1], t[2], channels == 4 ? t[3] : 1.0f};
      return {t[0], t[0], t[0], channels == 2 ? t[1] : 1.0f};
    }
  };
  // The levels and what the first one's codes point into.
  struct Pyramid {
    std::shared_ptr<const std::vector<uint8_t>> codes;
    std::shared_ptr<const CodeTable> table;
    std::vector<Level> levels;  // [0] the image, each next half as wide
  };
  struct CodeTables {
    std::shared_ptr<const CodeTable> linear, srgb;  // srgb empty when no table is exact
  };
  static CodeTables code_tables(const ColourPipeline& colour);
  friend std::vector<Texture> make_textures(const std::vector<TextureImage>&,
                                            const ColourPipeline&);
  Texture(std::shared_ptr<const Pyramid> pyramid, const TextureImage& sampler);
  static std::shared_ptr<const Pyramid> build_pyramid(const TextureImage& image,
                                                      const ColourPipeline& colour,
                                                      const CodeTables& tables);
  static Level exact_level(int width, int height, const std::vector<Imath::V4f>& texels);
  Imath::V4f lookup(const Level& level, const Imath::V2f& uv, TextureFilter filter) const;

  std::shared_ptr<const Pyramid> pyramid_;
  TextureWrap wrap_s_, wrap_t_;
  TextureFilter mag_filter_, min_filter_;
  MipMode mip_mode_;
};

// One Texture per description, built in parallel; textures that read the same decoded
// image (TextureImage::image) with the same encoding share one pyramid.
std::vector<Texture> make_textures(const std::vector<TextureImage>& images,
                                   const ColourPipeline& colour);

}  // namespace prism
