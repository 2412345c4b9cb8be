// Textures: sRGB slots are linearised, data slots are not; bilinear lookups and glTF's wrap
// modes.
#include <gtest/gtest.h>

#include "renderer/colour.h"
#include "renderer/texture.h"

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
