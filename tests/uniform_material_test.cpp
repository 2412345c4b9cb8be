// A material that does not vary over its surface answers evaluate() from the response
// make_material stored: it must be the response built in full, bit for bit, at every hit.
#include <bit>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/geometry/surface_hit.h"
#include "renderer/image/colour.h"
#include "renderer/shading/material.h"
#include "renderer/shading/texture.h"

namespace prism {
namespace {

using Imath::V2f;
using Imath::V4f;

uint32_t bits(float x) {
  return std::bit_cast<uint32_t>(x);
}

void expect_same_bits(const V3f& a, const V3f& b, const char* what) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bits(a[i]), bits(b[i])) << what << " channel " << i;
}

// Everything an integrator can ask of the two responses, compared bit for bit.
void expect_same_response(const SurfaceResponse& a, const SurfaceResponse& b) {
  expect_same_bits(a.emission, b.emission, "emission");
  EXPECT_EQ(bits(a.alpha), bits(b.alpha));
  EXPECT_EQ(bits(a.ambient_occlusion), bits(b.ambient_occlusion));
  for (const bool back_face : {false, true}) {
    const Bsdf x = a.bsdf.path_traced(back_face), y = b.bsdf.path_traced(back_face);
    expect_same_bits(x.shading_normal(), y.shading_normal(), "shading normal");
    EXPECT_EQ(x.flags(), y.flags());
    const V3f n = x.shading_normal();
    const V3f wos[] = {n, (n + V3f(0.3f, -0.2f, 0.1f)).normalized(), V3f(0.6f, 0.0f, 0.8f)};
    for (const V3f& wo : wos) {
      expect_same_bits(x.albedo(wo, n, back_face, AlbedoScope::all_lobes),
                       y.albedo(wo, n, back_face, AlbedoScope::all_lobes), "albedo");
      const V3f wi = (n + V3f(-0.4f, 0.25f, 0.05f)).normalized();
      expect_same_bits(x.eval(wo, wi), y.eval(wo, wi), "eval");
      EXPECT_EQ(bits(x.pdf(wo, wi)), bits(y.pdf(wo, wi)));
      for (const float u_lobe : {0.05f, 0.5f, 0.95f}) {
        BsdfSample sx, sy;
        const bool ox = x.sample(wo, u_lobe, V2f(0.3f, 0.7f), back_face, &sx);
        const bool oy = y.sample(wo, u_lobe, V2f(0.3f, 0.7f), back_face, &sy);
        ASSERT_EQ(ox, oy);
        if (!ox) continue;
        expect_same_bits(sx.wi, sy.wi, "sampled wi");
        expect_same_bits(sx.f, sy.f, "sampled f");
        EXPECT_EQ(bits(sx.pdf), bits(sy.pdf));
        EXPECT_EQ(sx.lobe, sy.lobe);
      }
    }
  }
}

// The materials of the scenes people render untextured: each has a uniform response.
std::vector<MaterialDescription> untextured_materials() {
  std::vector<MaterialDescription> all;
  MaterialDescription m;
  m.base_colour = C3f(0.8f, 0.3f, 0.2f);
  m.metallic = 0.0f;
  m.specular = 0.0f;  // Lambert
  all.push_back(m);
  m.specular = 1.0f;
  m.roughness = 0.4f;  // glossy plastic
  all.push_back(m);
  m.metallic = 1.0f;
  m.roughness = 0.0f;  // a perfect mirror
  all.push_back(m);
  m.roughness = 0.3f;  // rough metal
  all.push_back(m);
  m.metallic = 0.0f;
  m.transmission = 1.0f;  // rough glass with a volume
  m.thickness = 1.0f;
  m.attenuation_distance = 2.0f;
  m.attenuation_colour = C3f(0.9f, 0.5f, 0.5f);
  all.push_back(m);
  m.roughness = 0.0f;  // smooth glass
  all.push_back(m);
  m = MaterialDescription{};
  m.sheen_colour = C3f(0.5f, 0.4f, 0.3f);  // sheen over a dielectric
  m.sheen_roughness = 0.5f;
  m.metallic = 0.0f;
  all.push_back(m);
  m = MaterialDescription{};
  m.emissive = C3f(2.0f, 1.0f, 0.5f);  // an emitter
  all.push_back(m);
  m = MaterialDescription{};
  m.unlit = true;
  all.push_back(m);
  return all;
}

// Hits of every orientation, as the same material meets them over a scene.
std::vector<SurfaceHit> hits() {
  std::vector<SurfaceHit> all;
  const V3f normals[] = {V3f(0, 0, 1), V3f(0, -1, 0), V3f(0.48f, 0.6f, -0.64f)};
  for (const V3f& n : normals) {
    SurfaceHit h;
    h.geometric_normal = h.shading_normal = n;
    h.position = V3f(0.5f, -1.0f, 2.0f);
    h.cone_width = 0.01f;
    all.push_back(h);
  }
  return all;
}

TEST(UniformMaterial, ItsResponseIsTheResponseBuiltInFullAtEveryHit) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const std::vector<Texture> textures;
  for (const MaterialDescription& d : untextured_materials()) {
    const Material stored = make_material(d, textures, colour);
    ASSERT_TRUE(stored.uniform_response.has_value());
    Material in_full = stored;
    in_full.uniform_response.reset();
    for (const SurfaceHit& hit : hits()) {
      const SurfaceResponse a = evaluate(stored, hit), b = evaluate(in_full, hit);
      expect_same_bits(a.bsdf.shading_normal(), hit.shading_normal, "the hit's normal");
      expect_same_response(a, b);
    }
  }
}

TEST(UniformMaterial, VertexColoursTexturesAndCoatsAreEvaluatedAtTheHit) {
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  std::vector<Texture> textures;
  TextureImage image;
  image.width = image.height = 1;
  image.channels = 3;
  image.texels = {0.5f, 0.25f, 1.0f};
  image.encoding = TextureEncoding::linear_data;
  textures.emplace_back(image, colour);

  MaterialDescription d;
  d.metallic = 0.0f;
  d.specular = 0.0f;
  d.base_colour = C3f(0.8f, 0.8f, 0.8f);
  // COLOR_0 tints the base where the mesh has it: the stored response must not be used.
  const Material plain = make_material(d, textures, colour);
  ASSERT_TRUE(plain.uniform_response.has_value());
  VertexAttributes attributes;
  const std::vector<V3f> positions = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(0, 1, 0)};
  attributes.positions = positions.data();
  attributes.colours.assign(3, V4f(0.5f, 1.0f, 0.25f, 1.0f));
  SurfaceHit hit = hits()[0];
  hit.attributes = &attributes;
  const V3f tinted = evaluate(plain, hit).bsdf.lobes().diffuse_albedo;
  EXPECT_FLOAT_EQ(tinted.x, 0.8f * 0.5f);
  EXPECT_FLOAT_EQ(tinted.y, 0.8f);
  EXPECT_FLOAT_EQ(tinted.z, 0.8f * 0.25f);

  MaterialDescription textured = d;
  textured.base_colour_texture = 0;
  EXPECT_FALSE(make_material(textured, textures, colour).uniform_response.has_value());
  MaterialDescription coated = d;
  coated.clearcoat = 1.0f;  // its normal is the hit's
  EXPECT_FALSE(make_material(coated, textures, colour).uniform_response.has_value());
}

}  // namespace
}  // namespace prism
