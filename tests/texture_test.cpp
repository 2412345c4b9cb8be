// Textures: sRGB slots are linearised, data slots are not; bilinear lookups and glTF's wrap
// modes; 8-bit images kept as codes look up exactly as their float values did.
#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "renderer/image/colour.h"
#include "renderer/shading/texture.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"
#include "tests/test_scenes.h"

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

using Imath::V4f;

bool same_bits(const V4f& a, const V4f& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// 256 x 3 texels in which every code appears on every channel, each row shifting the
// channels against each other by another amount: as 8-bit codes, and as the floats the
// decoder used to make of them.
TextureImage code_image(int channels, TextureEncoding encoding) {
  TextureImage image;
  image.width = 256;
  image.height = 3;  // odd: the mip levels' box weights are fractional
  image.channels = channels;
  image.encoding = encoding;
  auto codes = std::make_shared<std::vector<uint8_t>>();
  const int shifts[] = {0, 1, 85};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < channels; ++c)
        codes->push_back(static_cast<uint8_t>((x + c * shifts[y]) % 256));
  image.shared_codes = std::move(codes);
  return image;
}

TextureImage as_floats(TextureImage image) {
  image.texels.clear();
  for (size_t i = 0; i < image.value_count(); ++i) image.texels.push_back(image.value(i));
  image.shared_codes.reset();
  return image;
}

// Every code on every channel, for each encoding, channel count and working space: the same
// bits through the table as through the float path (OCIO on the float values), at level 0
// and, minified, through every mip level. A transform that mixes channels (ACEScg's
// primaries) has no per-channel table and keeps its sRGB textures as floats.
TEST(Texture8Bit, EveryCodeLooksUpAsItsFloatValueDid) {
  for (WorkingSpace space : {WorkingSpace::linear_rec709, WorkingSpace::acescg}) {
    const ColourPipeline colour(space);
    EXPECT_EQ(colour.srgb_texture_code_table().has_value(), space == WorkingSpace::linear_rec709);
    for (TextureEncoding encoding : {TextureEncoding::srgb, TextureEncoding::linear_data})
      for (int channels = 1; channels <= 4; ++channels) {
        SCOPED_TRACE(std::string(to_string(space)) + " channels " + std::to_string(channels) +
                     (encoding == TextureEncoding::srgb ? " srgb" : " data"));
        TextureImage codes = code_image(channels, encoding);
        codes.mag_filter = TextureFilter::nearest;
        codes.wrap_s = codes.wrap_t = TextureWrap::clamp_to_edge;
        const TextureImage floats = as_floats(codes);
        const Texture a(codes, colour), b(floats, colour);
        const bool table =
            encoding == TextureEncoding::linear_data || space == WorkingSpace::linear_rec709;
        if (table)
          EXPECT_LT(a.bytes(), b.bytes());  // level 0 holds no floats
        else
          EXPECT_EQ(a.bytes(), b.bytes());
        ASSERT_EQ(a.levels(), b.levels());
        // Level 0, every texel, against OCIO applied to the old float values directly.
        std::vector<float> rgb;
        for (int y = 0; y < 3; ++y)
          for (int x = 0; x < 256; ++x) {
            const size_t t = (static_cast<size_t>(y) * 256 + x) * channels;
            for (int c = 0; c < 3; ++c) rgb.push_back(floats.texels[t + (channels >= 3 ? c : 0)]);
          }
        if (encoding == TextureEncoding::srgb) colour.srgb_texture_to_working(rgb.data(), 768, 3);
        size_t differing = 0;
        for (int y = 0; y < 3; ++y)
          for (int x = 0; x < 256; ++x) {
            const V2f uv((x + 0.5f) / 256.0f, (y + 0.5f) / 3.0f);
            const V4f got = a.sample(uv);
            const size_t i = static_cast<size_t>(y) * 256 + x;
            const size_t t = i * channels;
            const float alpha = channels == 4   ? floats.texels[t + 3]
                                : channels == 2 ? floats.texels[t + 1]
                                                : 1.0f;
            differing += !same_bits(got, V4f(rgb[i * 3], rgb[i * 3 + 1], rgb[i * 3 + 2], alpha));
            differing += !same_bits(got, b.sample(uv));
          }
        EXPECT_EQ(differing, 0u);
        // Minified, bilinear and trilinear: every level's texels are the same bits.
        differing = 0;
        for (int k = 0; k < 997; ++k) {
          const V2f uv(std::fmod(k * 0.61803f, 1.0f), std::fmod(k * 0.41421f, 1.0f));
          const float footprint = std::fmod(k * 0.0137f, 1.0f);
          differing += !same_bits(a.sample(uv, footprint), b.sample(uv, footprint));
        }
        EXPECT_EQ(differing, 0u);
      }
  }
}

// A textured asset renders the same bits with its images kept as 8-bit codes as with the
// floats they used to be decoded to.
TEST(Texture8Bit, BoxTexturedRendersTheSameBitsAsWithFloatTexels) {
  SceneDescription scene =
      load_gltf(std::string(PRISM_ASSIMP_GLTF2_DIR) + "/BoxTextured-glTF/BoxTextured.gltf");
  add_scene_defaults(&scene);
  ASSERT_FALSE(scene.textures.empty());
  SceneDescription floats = scene;
  for (TextureImage& t : floats.textures) {
    ASSERT_TRUE(t.shared_codes);
    t = as_floats(t);
  }
  testing::TestSettings settings;
  settings.width = 160;
  settings.height = 120;
  settings.spp = 4;
  for (const char* integrator : {"shadow", "whitted"}) {
    const testing::Rendered a = testing::render_scene(scene, integrator, settings);
    const testing::Rendered b = testing::render_scene(floats, integrator, settings);
    EXPECT_TRUE(a.image.rgba == b.image.rgba) << integrator;
    size_t lit = 0;  // not a black frame that matches anything
    for (float v : a.image.rgba) lit += v > 0.0f;
    EXPECT_GT(lit, a.image.rgba.size() / 8) << integrator;
  }
}

}  // namespace
}  // namespace prism
