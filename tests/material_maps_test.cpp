// Normal maps, occlusion maps, COLOR_0, KHR_texture_transform, tangent generation and
// mip-mapped texture filtering, each against an analytic answer.
#include <cmath>

#include <gtest/gtest.h>

#include "integrators/registry.h"
#include "renderer/shading/material.h"
#include "renderer/geometry/tangents.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

constexpr float kPi = 3.14159265358979323846f;

TextureImage one_texel(float r, float g, float b) {
  TextureImage image;
  image.width = image.height = 1;
  image.channels = 3;
  image.texels = {r, g, b};
  image.encoding = TextureEncoding::linear_data;
  return image;
}

// A 4 x 4 m quad in the XY plane facing +Z, UVs laid out as an image seen from the front
// (u to +x, v down to -y), tangents generated.
Primitive front_quad(int material) {
  Primitive p;
  p.positions = {V3f(-2, -2, 0), V3f(2, -2, 0), V3f(2, 2, 0), V3f(-2, 2, 0)};
  p.normals = {V3f(0, 0, 1), V3f(0, 0, 1), V3f(0, 0, 1), V3f(0, 0, 1)};
  p.uv0 = {V2f(0, 1), V2f(1, 1), V2f(1, 0), V2f(0, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.tangents = generate_tangents(p.positions, p.normals, p.uv0, p.indices);
  p.material = material;
  return p;
}

// A Lambert surface: no specular layer (KHR_materials_specular factor 0), not metallic.
MaterialDescription lambert(float rho) {
  MaterialDescription m = testing::lambert_like(rho);
  m.specular = 0.0f;
  return m;
}

SceneDescription quad_scene(const MaterialDescription& material, const Primitive& quad) {
  SceneDescription s;
  s.materials.push_back(material);
  s.meshes.push_back(Mesh{"quad", {quad}});
  s.instances.push_back(MeshInstance{0, M44d(), "quad"});
  s.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.0));
  return s;
}

Light sun(const V3f& to_light, float lux) {
  Light l;
  l.type = LightType::directional;
  l.intensity = lux;
  l.direction = -V3d(to_light);
  return l;
}

testing::TestSettings small(const V3f& ambient) {
  testing::TestSettings settings;
  settings.width = settings.height = 8;
  settings.ambient = ambient.x;  // grey
  settings.threads = 1;
  return settings;
}

TEST(TangentGeneration, KnownUvLayouts) {
  Primitive p = front_quad(-1);
  for (const Imath::V4f& t : p.tangents) {
    EXPECT_NEAR(t.x, 1.0f, 1e-6f);  // dP/du = +x
    EXPECT_NEAR(t.y, 0.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);  // cross(N, T) = +y = -dP/dv: not mirrored
  }
  // u mirrored (runs to -x): the tangent turns round, and so does the handedness, which
  // keeps the bitangent cross(N, T) w pointing to decreasing v (+y) still.
  p.uv0 = {V2f(1, 1), V2f(0, 1), V2f(0, 0), V2f(1, 0)};
  for (const Imath::V4f& t : generate_tangents(p.positions, p.normals, p.uv0, p.indices)) {
    EXPECT_NEAR(t.x, -1.0f, 1e-6f);
    EXPECT_EQ(t.w, -1.0f);
  }
  // The image turned a quarter: u runs to +y, v to +x. cross(N, +y) = -x = -dP/dv.
  p.uv0 = {V2f(0, 0), V2f(0, 1), V2f(1, 1), V2f(1, 0)};
  for (const Imath::V4f& t : generate_tangents(p.positions, p.normals, p.uv0, p.indices)) {
    EXPECT_NEAR(t.y, 1.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
  }
  // No UVs: still a unit tangent orthogonal to the normal.
  for (const Imath::V4f& t : generate_tangents(p.positions, p.normals, {}, p.indices)) {
    EXPECT_NEAR(V3f(t.x, t.y, t.z).length(), 1.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
  }
}

// A constant normal-map texel tilting the normal by `angle` towards +x (the tangent) or +y
// (the bitangent) on a flat quad: the radiance is the Lambert cosine of the tilted normal,
// E rho / pi (n . L), to float rounding.
TEST(NormalMap, ConstantTexelGivesTheTiltedNormalsLambertCosine) {
  const float angle = 0.5f, rho = 0.8f, lux = 3.0f;
  const V3f to_light = V3f(0.6f, -0.8f, 0.5f).normalized();
  for (int axis : {0, 1}) {
    V3f n(0.0f, 0.0f, std::cos(angle));
    n[axis] = std::sin(angle);
    SceneDescription s = quad_scene(lambert(rho), front_quad(0));
    s.materials[0].normal_texture = 0;
    s.textures.push_back(one_texel(0.5f * (n.x + 1.0f), 0.5f * (n.y + 1.0f), 0.5f * (n.z + 1.0f)));
    s.lights.push_back(sun(to_light, lux));
    const auto phong = make_integrator("phong");
    const testing::Rendered r = testing::render_scene(s, "phong", small(V3f(0.0f)));
    const float expected = lux * rho / kPi * n.dot(to_light);
    const float flat = lux * rho / kPi * to_light.z;
    ASSERT_GT(std::fabs(expected - flat), 0.05f * flat);  // the tilt is visible
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) ASSERT_NEAR(r.image.pixel(x, y)[0], expected, 2e-6f) << axis;
  }
}

TEST(NormalMap, StaysOnTheGeometricNormalsSide) {
  // A texel pointing straight into the surface (0, 0, -1): clamped just above it.
  SceneDescription s = quad_scene(lambert(1.0f), front_quad(0));
  s.materials[0].normal_texture = 0;
  s.textures.push_back(one_texel(0.5f, 0.5f, 0.0f));
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const RenderScene scene(s, {}, colour);
  Ray ray;
  ray.origin = V3f(0.1f, 0.2f, 5.0f);
  ray.direction = V3f(0.0f, 0.0f, -1.0f);
  SurfaceHit hit;
  ASSERT_TRUE(scene.geometry().intersect(ray, &hit));
  const SurfaceResponse r = evaluate(scene.material(hit.material), hit);
  EXPECT_NEAR(r.bsdf.shading_normal().length(), 1.0f, 1e-6f);
  EXPECT_GT(r.bsdf.shading_normal().dot(hit.geometric_normal), 0.0f);
}

// Occlusion scales the ambient term only: rho I_a (1 + strength (occlusion - 1)) plus the
// unchanged direct light.
TEST(OcclusionMap, ScalesTheAmbientTermOnly) {
  const float rho = 0.8f, lux = 2.0f, occlusion = 0.25f, strength = 0.5f;
  SceneDescription s = quad_scene(lambert(rho), front_quad(0));
  s.materials[0].occlusion_texture = 0;
  s.materials[0].occlusion_strength = strength;
  s.textures.push_back(one_texel(occlusion, 1.0f, 1.0f));  // glTF reads red only
  s.lights.push_back(sun(V3f(0.0f, 0.0f, 1.0f), lux));
  const auto phong = make_integrator("phong");
  const testing::Rendered r = testing::render_scene(s, "phong", small(V3f(1.0f)));
  const float expected = rho * (1.0f + strength * (occlusion - 1.0f)) + lux * rho / kPi;
  EXPECT_NEAR(r.image.pixel(3, 4)[0], expected, 2e-6f);
}

// COLOR_0 multiplies the base colour (and its alpha).
TEST(VertexColours, MultiplyTheBaseColour) {
  Primitive quad = front_quad(0);
  quad.colours.assign(4, Imath::V4f(0.5f, 0.25f, 1.0f, 0.4f));
  MaterialDescription m = lambert(1.0f);
  m.base_colour = C3f(0.5f, 1.0f, 1.0f);
  m.alpha = 0.5f;
  const SceneDescription s = quad_scene(m, quad);
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const RenderScene scene(s, {}, colour);
  Ray ray;
  ray.origin = V3f(0.3f, -0.7f, 5.0f);
  ray.direction = V3f(0.0f, 0.0f, -1.0f);
  SurfaceHit hit;
  ASSERT_TRUE(scene.geometry().intersect(ray, &hit));
  const SurfaceResponse r = evaluate(scene.material(hit.material), hit);
  EXPECT_NEAR(r.bsdf.lobes().diffuse_albedo.x, 0.25f, 1e-6f);
  EXPECT_NEAR(r.bsdf.lobes().diffuse_albedo.y, 0.25f, 1e-6f);
  EXPECT_NEAR(r.bsdf.lobes().diffuse_albedo.z, 1.0f, 1e-6f);
  EXPECT_NEAR(r.alpha, 0.2f, 1e-6f);
  EXPECT_NEAR(base_colour_alpha(scene.material(hit.material), hit), 0.2f, 1e-6f);
}

// KHR_texture_transform maps a known uv to a known texel: offset (0.5, 0), rotation pi/2,
// scale 0.5 take uv (0.25, 0.25) to (0.5 + 0.5 * 0.25, -0.5 * 0.25) = (0.625, -0.125), which
// REPEAT wraps to (0.625, 0.875): texel (2, 3) of a 4 x 4 image; the same with texCoord 1
// reads TEXCOORD_1.
TEST(TextureTransform, MapsAKnownUvToAKnownTexel) {
  TextureImage image;
  image.width = image.height = 4;
  image.channels = 1;
  image.encoding = TextureEncoding::linear_data;
  image.mag_filter = TextureFilter::nearest;
  for (int i = 0; i < 16; ++i) image.texels.push_back(static_cast<float>(i) / 16.0f);
  const ColourPipeline colour(WorkingSpace::linear_rec709);
  const std::vector<Texture> textures = make_textures({image}, colour);
  for (int set : {0, 1}) {
    MaterialDescription d;
    d.base_colour_texture = 0;
    d.base_colour_mapping.offset = V2f(0.5f, 0.0f);
    d.base_colour_mapping.rotation = kPi / 2;
    d.base_colour_mapping.scale = V2f(0.5f, 0.5f);
    d.base_colour_mapping.texcoord = set;
    const Material m = make_material(d, textures, colour);
    VertexAttributes attributes;
    const std::vector<V3f> positions = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(0, 1, 0)};
    attributes.positions = positions.data();
    attributes.texcoords[0].assign(3, V2f(0.9f, 0.9f));  // the other set: another texel if read
    attributes.texcoords[set].assign(3, V2f(0.25f, 0.25f));
    SurfaceHit hit;
    hit.attributes = &attributes;
    hit.vertices[1] = 1;
    hit.vertices[2] = 2;
    EXPECT_FLOAT_EQ(evaluate(m, hit).bsdf.lobes().transmission_tint.x, 14.0f / 16.0f) << set;
  }
}

// A plane seen at grazing angles with a checker of single texels (0 and 1): with mip-maps
// every pixel is the checker's box-filtered mean 0.5, where point sampling aliases to 0 or 1.
TEST(TextureFiltering, GrazingCheckerConvergesToItsMean) {
  auto render = [](MipMode mip) {
    SceneDescription s;
    // Lambertian: the ambient radiance is I_a x base colour at every angle.
    MaterialDescription m = testing::lambert_like(1.0f);
    m.base_colour_texture = 0;
    s.materials.push_back(m);
    TextureImage checker;
    checker.width = checker.height = 64;
    checker.channels = 1;
    checker.encoding = TextureEncoding::linear_data;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) checker.texels.push_back(static_cast<float>((x + y) % 2));
    checker.mip_mode = mip;
    s.textures.push_back(checker);
    Mesh plane = testing::quad_mesh(50.0f, 0.0f, 0);
    for (const V3f& p : plane.primitives[0].positions)  // 1 UV (64 texels) per metre
      plane.primitives[0].uv0.push_back(V2f(p.x, p.z));
    s.meshes.push_back(plane);
    s.instances.push_back(MeshInstance{0, M44d(), "plane"});
    CameraDescription c;  // 0.5 m above the plane, looking level: the horizon mid-image
    c.yfov = 0.5;
    c.camera_to_world = M44d().setTranslation(V3d(0.0, 0.5, 0.0));
    s.cameras.push_back(c);
    testing::TestSettings settings = small(V3f(1.0f));
    settings.width = settings.height = 64;
    return testing::render_scene(s, "phong", settings);
  };
  auto worst = [](const Image& image) {
    float worst = 0.0f;
    for (int y = 33; y < 64; ++y)  // the plane, below the horizon
      for (int x = 0; x < 64; ++x) worst = std::max(worst, std::fabs(image.pixel(x, y)[0] - 0.5f));
    return worst;
  };
  // The nearest pixel's footprint is about 4 texels, so every one reads level >= 1: 0.5.
  EXPECT_LT(worst(render(MipMode::linear).image), 1e-5f);
  EXPECT_GT(worst(render(MipMode::none).image), 0.4f);
}

}  // namespace
}  // namespace prism
