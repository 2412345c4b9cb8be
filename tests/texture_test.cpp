// Textures: sRGB slots are linearised, data slots are not; bilinear lookups and glTF's wrap
// modes.
#include <cmath>

#include <gtest/gtest.h>

#include "renderer/image/colour.h"
#include "renderer/shading/texture.h"

namespace prism {
namespace {

TextureImage grey_image(std::vector<float> values, int width, TextureEncoding encoding) {
  TextureImage image;
  image.width = width;
  image.height = static_cast<int>(values.size()) / width;
  image.channels = 1;
  image.texels = std::move(values);
  image.encoding = encoding;
  return image;
}

TEST(Texture, SrgbSlotsAreLinearisedAndDataSlotsAreNot) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const Texture srgb(grey_image({0.5f}, 1, TextureEncoding::srgb), colour);
  const Texture data(grey_image({0.5f}, 1, TextureEncoding::linear_data), colour);
  EXPECT_NEAR(srgb.sample(V2f(0.5f, 0.5f)).x, 0.21404114f, 1e-6f);
  EXPECT_EQ(data.sample(V2f(0.5f, 0.5f)).x, 0.5f);
  EXPECT_EQ(data.sample(V2f(0.5f, 0.5f)).w, 1.0f);  // no alpha channel: opaque
}

TEST(Texture, BilinearBetweenTexelCentres) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  // Two texels, 0 and 1: their centres are at u = 0.25 and 0.75.
  TextureImage image = grey_image({0.0f, 1.0f}, 2, TextureEncoding::linear_data);
  image.wrap_s = image.wrap_t = TextureWrap::clamp_to_edge;
  const Texture t(image, colour);
  EXPECT_FLOAT_EQ(t.sample(V2f(0.25f, 0.5f)).x, 0.0f);
  EXPECT_FLOAT_EQ(t.sample(V2f(0.5f, 0.5f)).x, 0.5f);
  EXPECT_FLOAT_EQ(t.sample(V2f(0.625f, 0.5f)).x, 0.75f);
  EXPECT_FLOAT_EQ(t.sample(V2f(0.75f, 0.5f)).x, 1.0f);
}

TEST(Texture, WrapModes) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  // Four texels 0, 1, 2, 3 in a row; sample at texel centres beyond the edge.
  auto at = [&](TextureWrap wrap, float texel_centre) {
    TextureImage image = grey_image({0.0f, 1.0f, 2.0f, 3.0f}, 4, TextureEncoding::linear_data);
    image.wrap_s = image.wrap_t = wrap;
    return Texture(image, colour).sample(V2f((texel_centre + 0.5f) / 4.0f, 0.5f)).x;
  };
  EXPECT_FLOAT_EQ(at(TextureWrap::repeat, 4.0f), 0.0f);   // wraps to texel 0
  EXPECT_FLOAT_EQ(at(TextureWrap::repeat, -1.0f), 3.0f);  // and back to texel 3
  EXPECT_FLOAT_EQ(at(TextureWrap::clamp_to_edge, 6.0f), 3.0f);
  EXPECT_FLOAT_EQ(at(TextureWrap::clamp_to_edge, -5.0f), 0.0f);
  EXPECT_FLOAT_EQ(at(TextureWrap::mirrored_repeat, 4.0f), 3.0f);  // mirrored: 3 2 1 0 | 0 1 2 3
  EXPECT_FLOAT_EQ(at(TextureWrap::mirrored_repeat, 5.0f), 2.0f);
  EXPECT_FLOAT_EQ(at(TextureWrap::mirrored_repeat, -1.0f), 0.0f);
  EXPECT_FLOAT_EQ(at(TextureWrap::mirrored_repeat, -2.0f), 1.0f);
  // Huge and non-finite coordinates stay defined.
  EXPECT_TRUE(std::isfinite(at(TextureWrap::repeat, 1e30f)));
  TextureImage image = grey_image({0.0f, 1.0f}, 2, TextureEncoding::linear_data);
  EXPECT_TRUE(std::isfinite(Texture(image, colour).sample(V2f(NAN, INFINITY)).x));
}

}  // namespace
}  // namespace prism

namespace prism {
namespace {

// A width x height checker of single texels, 0 and 1.
TextureImage checker(int width, int height) {
  TextureImage image;
  image.width = width;
  image.height = height;
  image.channels = 1;
  image.encoding = TextureEncoding::linear_data;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.texels.push_back(static_cast<float>((x + y) % 2));
  return image;
}

TEST(TextureMipMaps, EveryLevelKeepsTheMean) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  // Odd sizes too: the box filter's fractional weights keep the mean exact. 7 x 5 texels
  // with values 0..34: mean 17.
  TextureImage ramp;
  ramp.width = 7;
  ramp.height = 5;
  ramp.channels = 1;
  ramp.encoding = TextureEncoding::linear_data;
  for (int i = 0; i < 35; ++i) ramp.texels.push_back(static_cast<float>(i));
  const Texture t(ramp, colour);
  EXPECT_EQ(t.levels(), 3);  // 7x5, 3x2, 1x1
  // A footprint wider than the image reads the last level: the mean, to float rounding.
  EXPECT_NEAR(t.sample(V2f(0.3f, 0.6f), 4.0f).x, 17.0f, 1e-4f);

  const Texture c(checker(64, 64), colour);
  EXPECT_EQ(c.levels(), 7);
  // Footprints of 2, 4, ... 64 texels land on levels 1..6, all exactly 0.5 for a
  // single-texel checker; one texel or less magnifies (0 or 1).
  for (float texels : {2.0f, 3.0f, 4.0f, 16.0f, 64.0f, 1000.0f})
    EXPECT_FLOAT_EQ(c.sample(V2f(0.37f, 0.81f), texels / 64.0f).x, 0.5f) << texels;
  EXPECT_FLOAT_EQ(c.sample(V2f(0.5f / 64, 0.5f / 64), 0.5f / 64).x, 0.0f);
  EXPECT_FLOAT_EQ(c.sample(V2f(1.5f / 64, 0.5f / 64), 0.5f / 64).x, 1.0f);
  // Trilinear: a footprint of sqrt(2) texels is half-way between level 0 (0) and level 1
  // (0.5) at a texel centre of value 0: 0.25.
  EXPECT_NEAR(c.sample(V2f(0.5f / 64, 0.5f / 64), std::sqrt(2.0f) / 64).x, 0.25f, 1e-6f);
}

TEST(TextureMipMaps, SamplerFilters) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  TextureImage image = grey_image({0.0f, 1.0f, 2.0f, 3.0f}, 4, TextureEncoding::linear_data);
  image.wrap_s = image.wrap_t = TextureWrap::clamp_to_edge;
  // u = 0.3 is texel 1 (centre 0.375), 0.2 of a texel left of its centre.
  image.mag_filter = TextureFilter::nearest;
  EXPECT_FLOAT_EQ(Texture(image, colour).sample(V2f(0.3f, 0.5f)).x, 1.0f);
  image.mag_filter = TextureFilter::linear;
  EXPECT_NEAR(Texture(image, colour).sample(V2f(0.3f, 0.5f)).x, 0.7f, 1e-6f);
  // Minification without mip levels reads the full image with the min filter.
  image.mip_mode = MipMode::none;
  image.min_filter = TextureFilter::nearest;
  EXPECT_FLOAT_EQ(Texture(image, colour).sample(V2f(0.3f, 0.5f), 0.9f).x, 1.0f);
  // Level 1 of 4 x 1 is 2 x 1: (0 + 1) / 2 and (2 + 3) / 2. A footprint of 2.5 texels
  // (lod 1.32) picks level 1 with MipMode::nearest.
  image.mip_mode = MipMode::nearest;
  EXPECT_FLOAT_EQ(Texture(image, colour).sample(V2f(0.3f, 0.5f), 2.5f / 2.0f).x, 0.5f);
}

}  // namespace
}  // namespace prism
