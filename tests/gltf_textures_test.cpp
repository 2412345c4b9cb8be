// The loader's texture side: images through OpenImageIO (each decoded once), samplers'
// filters, texture references (texCoord, KHR_texture_transform, normal and occlusion
// textures), and the COLOR_0, TEXCOORD_1 and TANGENT attributes.
#include <cmath>
#include <filesystem>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "scene_io/gltf_loader.h"
#include "tests/gltf_test_builder.h"
#include "tests/scratch_dir.h"

namespace prism {
namespace {

using test::Builder;
using test::json;

// A 2 x 2 RGB PNG (8-bit) written with OpenImageIO, next to the Builder's files.
std::string write_png(const std::string& name, const std::vector<unsigned char>& rgb) {
  const std::string path = (test::scratch_dir("gltf_loader_test") / name).string();
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8)));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
  out->close();
  return name;
}

int quad(Builder& b, json attributes, int material) {
  attributes["POSITION"] = b.quad_positions();
  json primitive = {{"attributes", attributes}, {"mode", 6}};
  if (material >= 0) primitive["material"] = material;
  return b.node({{"mesh", b.mesh(primitive)}});
}

TEST(GltfTextures, SamplerFiltersAndOneDecodePerImage) {
  Builder b;
  b.doc["images"] = json::array(
      {{{"uri", write_png("filters.png", {0, 51, 102, 153, 204, 255, 255, 0, 0, 0, 0, 255})}}});
  b.doc["samplers"] = json::array(
      {{{"magFilter", 9728}, {"minFilter", 9985}}, {{"minFilter", 9729}, {"wrapS", 33648}}});
  b.doc["textures"] =
      json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 0}, {"sampler", 1}}});
  b.doc["materials"] =
      json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                    {"emissiveTexture", {{"index", 1}}}}});
  quad(b, json::object(), 0);
  const SceneDescription s = load_gltf(b.write("filters.gltf"));
  ASSERT_EQ(s.textures.size(), 2u);
  const TextureImage& a = s.textures[0];
  const TextureImage& c = s.textures[1];
  EXPECT_EQ(a.mag_filter, TextureFilter::nearest);
  EXPECT_EQ(a.min_filter, TextureFilter::linear);  // LINEAR_MIPMAP_NEAREST
  EXPECT_EQ(a.mip_mode, MipMode::nearest);
  EXPECT_EQ(c.mag_filter, TextureFilter::linear);  // left out: bilinear
  EXPECT_EQ(c.min_filter, TextureFilter::linear);  // LINEAR: no mip levels
  EXPECT_EQ(c.mip_mode, MipMode::none);
  EXPECT_EQ(c.wrap_s, TextureWrap::mirrored_repeat);
  // One image behind both textures: the same source, the same decoded values.
  EXPECT_EQ(a.image, 0);
  EXPECT_EQ(c.image, 0);
  ASSERT_EQ(a.value_count(), 12u);
  EXPECT_EQ(a.shared_codes, c.shared_codes);
  EXPECT_FLOAT_EQ(a.value(1), 51.0f / 255.0f);  // 8-bit values normalised
  EXPECT_FLOAT_EQ(a.value(5), 1.0f);

  b.doc["samplers"][0]["minFilter"] = 1234;
  try {
    load_gltf(b.write("bad_filter.gltf"));
    ADD_FAILURE() << "an invalid minFilter loaded";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("samplers[0].minFilter: filter 1234 is invalid"),
              std::string::npos)
        << e.what();
  }
}

TEST(GltfTextures, TextureReferencesAndTransform) {
  Builder b;
  b.doc["images"] =
      json::array({{{"uri", write_png("refs.png", std::vector<unsigned char>(12, 128))}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["extensionsUsed"] = json::array({"KHR_texture_transform"});
  b.doc["materials"] = json::array(
      {{{"pbrMetallicRoughness",
         {{"baseColorTexture",
           {{"index", 0},
            {"texCoord", 1},
            {"extensions",
             {{"KHR_texture_transform",
               {{"offset", {0.5, -0.25}}, {"rotation", 0.75}, {"scale", {2.0, 3.0}}}}}}}}}},
        {"normalTexture", {{"index", 0}, {"scale", 0.5}}},
        {"occlusionTexture",
         {{"index", 0},
          {"strength", 0.25},
          {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}}});
  const int uv = b.accessor(b.view(std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}), 5126, 4, "VEC2");
  quad(b, {{"TEXCOORD_0", uv}, {"TEXCOORD_1", uv}}, 0);
  const SceneDescription s = load_gltf(b.write("refs.gltf"));
  const MaterialDescription& m = s.materials.at(0);
  EXPECT_EQ(m.base_colour_mapping.texcoord, 1);
  EXPECT_EQ(m.base_colour_mapping.offset, V2f(0.5f, -0.25f));
  EXPECT_FLOAT_EQ(m.base_colour_mapping.rotation, 0.75f);
  EXPECT_EQ(m.base_colour_mapping.scale, V2f(2.0f, 3.0f));
  EXPECT_GE(m.normal_texture, 0);
  EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
  EXPECT_EQ(m.normal_mapping.texcoord, 0);
  EXPECT_GE(m.occlusion_texture, 0);
  EXPECT_FLOAT_EQ(m.occlusion_strength, 0.25f);
  EXPECT_EQ(m.occlusion_mapping.texcoord, 1);  // the extension's texCoord overrides
  // Normal and occlusion maps are data, the base colour sRGB: two textures of one image.
  EXPECT_EQ(s.textures.at(std::size_t(m.normal_texture)).encoding, TextureEncoding::linear_data);
  EXPECT_EQ(m.normal_texture, m.occlusion_texture);
  EXPECT_NE(m.normal_texture, m.base_colour_texture);
  const Primitive& p = s.meshes.at(0).primitives.at(0);
  EXPECT_EQ(p.uv1.size(), 4u);
  // Normal-mapped without TANGENT: generated from TEXCOORD_0 (u along +x): (1, 0, 0, 1).
  ASSERT_EQ(p.tangents.size(), 4u);
  for (const Imath::V4f& t : p.tangents) {
    EXPECT_NEAR(t.x, 1.0f, 1e-6f);
    EXPECT_EQ(t.w, -1.0f);  // v runs up the quad here (+y): a mirrored layout
  }
}

// COLOR_0 in each type glTF allows, normalised: 255 -> 1, 65535 -> 1, floats as they are.
TEST(GltfTextures, VertexColoursInEveryType) {
  Builder b;
  const int bytes = b.accessor(b.view(std::vector<uint8_t>{255, 0, 51, 255, 0, 255, 102, 0, 255,
                                                           255, 255, 255, 0, 0, 0, 51}),
                               5121, 4, "VEC4", true);
  const int shorts = b.accessor(
      b.view(std::vector<uint16_t>{65535, 0, 13107, 0, 65535, 0, 65535, 65535, 65535, 0, 0, 0}),
      5123, 4, "VEC3", true);
  const int floats = b.accessor(
      b.view(std::vector<float>{0.25f, 0.5f, 0.75f, 1, 0, 0, 1, 1, 0, 0, 1, 1}), 5126, 4, "VEC3");
  for (int colours : {bytes, shorts, floats}) quad(b, {{"COLOR_0", colours}}, -1);
  const SceneDescription s = load_gltf(b.write("colours.gltf"));
  ASSERT_EQ(s.meshes.size(), 3u);
  const auto& c8 = s.meshes[0].primitives[0].colours;
  const auto& c16 = s.meshes[1].primitives[0].colours;
  const auto& c32 = s.meshes[2].primitives[0].colours;
  ASSERT_EQ(c8.size(), 4u);
  EXPECT_EQ(c8[0], Imath::V4f(1.0f, 0.0f, 0.2f, 1.0f));
  EXPECT_FLOAT_EQ(c8[1].z, 102.0f / 255.0f);
  EXPECT_FLOAT_EQ(c8[3].w, 0.2f);
  ASSERT_EQ(c16.size(), 4u);
  EXPECT_EQ(c16[0], Imath::V4f(1.0f, 0.0f, 0.2f, 1.0f));  // VEC3: alpha 1
  ASSERT_EQ(c32.size(), 4u);
  EXPECT_EQ(c32[0], Imath::V4f(0.25f, 0.5f, 0.75f, 1.0f));

  // Signed or unnormalised integers are not colours.
  Builder bad;
  quad(bad, {{"COLOR_0", bad.accessor(bad.view(std::vector<uint8_t>(12, 1)), 5121, 4, "VEC3")}},
       -1);
  try {
    load_gltf(bad.write("bad_colours.gltf"));
    ADD_FAILURE() << "unnormalised COLOR_0 loaded";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("COLOR_0 must be FLOAT or normalized"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace prism
