// glTF alpha modes (OPAQUE, MASK, BLEND) and doubleSided, as renderer/geometry/alpha_filter.h
// implements them: for camera, secondary and shadow rays alike, on baked and instanced
// meshes, with answers counted against the analytic area or the blended value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "integrators/registry.h"
#include "renderer/geometry/alpha_filter.h"
#include "renderer/image/colour.h"
#include "renderer/geometry/embree_scene.h"
#include "renderer/shading/material.h"
#include "renderer/scene_features.h"
#include "renderer/shading/texture.h"
#include "scene_io/gltf_loader.h"
#include "tests/gltf_test_builder.h"
#include "tests/test_scenes.h"

namespace prism {
namespace {

using testing::ortho_camera_looking_down_y;
using testing::render_scene;

// A purely Lambertian material (no specular layer: KHR_materials_specular factor 0), whose
// radiance under a light is exactly rho / pi times the irradiance.
MaterialDescription lambert_like(float rho) {
  MaterialDescription m = testing::lambert_like(rho);
  m.specular = 0.0f;
  return m;
}

// A horizontal square of half size `half` at height y, centred on (cx, cz), facing +Y
// (counter-clockwise seen from above), u growing with x and v with -z.
Primitive square(float half, float y, int material, float cx = 0.0f, float cz = 0.0f) {
  Primitive p;
  p.positions = {V3f(cx - half, y, cz + half), V3f(cx + half, y, cz + half),
                 V3f(cx + half, y, cz - half), V3f(cx - half, y, cz - half)};
  p.normals.assign(4, V3f(0, 1, 0));
  p.uv0 = {V2f(0, 1), V2f(1, 1), V2f(1, 0), V2f(0, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = material;
  return p;
}

// The same square facing -Y: its back face is seen from above.
Primitive square_facing_down(float half, float y, int material) {
  Primitive p = square(half, y, material);
  p.normals.assign(4, V3f(0, -1, 0));
  p.indices = {0, 2, 1, 0, 3, 2};
  return p;
}

int add_mesh(SceneDescription* scene, Primitive p) {
  Mesh m;
  m.primitives.push_back(std::move(p));
  scene->meshes.push_back(std::move(m));
  return static_cast<int>(scene->meshes.size() - 1);
}

void place(SceneDescription* scene, int mesh, const M44d& transform = M44d()) {
  scene->instances.push_back(MeshInstance{mesh, transform, "node"});
}

// A 2 x 1 texture, clamped: alpha 0 in the left texel, 1 in the right. Bilinear filtering
// ramps alpha from 0 at u = 0.25 to 1 at u = 0.75, so alpha >= 0.5 exactly where u >= 0.5:
// the right half of the surface.
TextureImage left_half_transparent() {
  TextureImage t;
  t.name = "half";
  t.width = 2;
  t.height = 1;
  t.channels = 4;
  t.texels = {1, 1, 1, 0, 1, 1, 1, 1};
  t.wrap_s = t.wrap_t = TextureWrap::clamp_to_edge;
  return t;
}

MaterialDescription masked(int texture, float factor = 1.0f, float cutoff = 0.5f) {
  MaterialDescription m = lambert_like(0.8f);
  m.alpha_mode = AlphaMode::mask;
  m.base_colour_texture = texture;
  m.alpha = factor;
  m.alpha_cutoff = cutoff;
  return m;
}

Ray down_from(float x, float z, bool from_camera = false) {
  Ray r;
  r.origin = V3f(x, 10.0f, z);
  r.direction = V3f(0, -1, 0);
  r.from_camera = from_camera;
  return r;
}

// The geometry with its textures and materials, as RenderScene builds it.
struct Geometry {
  explicit Geometry(const SceneDescription& scene) {
    const ColourPipeline colour(WorkingSpace::linear_rec709);
    textures = make_textures(scene.textures, colour);
    for (const MaterialDescription& m : scene.materials)
      materials.push_back(make_material(m, textures, colour));
    embree = std::make_unique<EmbreeScene>(scene, GeometryOptions{}, materials);
  }
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::unique_ptr<EmbreeScene> embree;
};

bool hits(const EmbreeScene& g, const Ray& r) {
  SurfaceHit hit;
  return g.intersect(r, &hit);
}

// ---- MASK ----

// The ground, a masked square of half size 0.5 at height 1 whose left half is cut out, and
// a sun travelling along (1, -1, 0): the opaque right half, x in [0, 0.5], shadows the
// ground at x in [1, 1.5], z in [-0.5, 0.5] (0.5 m^2), clear of the square seen from above.
SceneDescription masked_square_over_ground() {
  SceneDescription scene;
  scene.materials.push_back(lambert_like(0.5f));
  scene.textures.push_back(left_half_transparent());
  scene.materials.push_back(masked(0));
  place(&scene, add_mesh(&scene, square(4.0f, 0.0f, 0)));
  place(&scene, add_mesh(&scene, square(0.5f, 1.0f, 1)));
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 3.0f;
  sun.direction = V3d(1.0, -1.0, 0.0).normalized();
  scene.lights.push_back(sun);
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 2.0));
  return scene;
}

TEST(AlphaModes, MaskCutsTheShadowToTheOpaqueHalf) {
  const SceneDescription scene = masked_square_over_ground();
  testing::TestSettings settings;
  settings.width = settings.height = 200;  // 2 cm pixels over [-2, 2]^2
  const auto shadow = make_integrator("shadow");
  const Image image = render_scene(scene, *shadow, settings).image;
  // Pixel centres sit at odd multiples of 1 cm, never on the shadow's edges (x = 1, 1.5,
  // z = +-0.5), so counting centres measures the area exactly: 25 x 50 pixels = 0.5 m^2.
  // One column of pixels (50) is the tolerance stated for it.
  const float lit = image.pixel(20, 100)[0];  // x = -1.59: open ground
  ASSERT_GT(lit, 0.0f);
  int shadowed = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.pixel(x, y)[0] < 0.5f * lit) ++shadowed;
  std::printf("mask shadow: %d shadowed pixels, 1250 expected\n", shadowed);
  EXPECT_NEAR(shadowed, 1250, 50);
  // Where the left half would have cast its shadow (x in [0.5, 1]) the ground is lit.
  EXPECT_EQ(image.pixel(137, 100)[0], lit);         // x = 0.75
  EXPECT_LT(image.pixel(162, 100)[0], 0.5f * lit);  // x = 1.25
}

TEST(AlphaModes, CameraRaysSeeThroughTheCutHalf) {
  const SceneDescription scene = masked_square_over_ground();
  testing::TestSettings settings;
  settings.width = settings.height = 200;
  const auto shadow = make_integrator("shadow");
  const Image image = render_scene(scene, *shadow, settings).image;
  const float ground = image.pixel(20, 100)[0];
  // The square's top (rho 0.8) and the ground (rho 0.5) face the same sun: 0.8 / 0.5 of it.
  const float top = image.pixel(112, 100)[0];  // x = 0.25, over the opaque half
  EXPECT_NEAR(top / ground, 0.8f / 0.5f, 1e-5f);
  EXPECT_EQ(image.pixel(87, 100)[0], ground);  // x = -0.25: the ground through the cut
  EXPECT_EQ(image.pixel(87, 100)[3], 1.0f);    // the ground is hit: alpha 1
}

TEST(AlphaModes, MaskCutoffIsInclusive) {
  // glTF: alpha >= alphaCutoff is opaque. Factor alone (no texture), then texture alone.
  for (const bool textured : {false, true}) {
    const float below = std::nextafter(0.5f, 0.0f);
    for (const float alpha : {0.5f, below}) {
      SceneDescription scene;
      if (textured) {
        TextureImage t;
        t.width = t.height = 1;
        t.channels = 4;
        t.texels = {1, 1, 1, alpha};
        t.encoding = TextureEncoding::srgb;  // alpha is never colour-converted
        scene.textures.push_back(t);
        scene.materials.push_back(masked(0, 1.0f, 0.5f));
      } else {
        scene.materials.push_back(masked(-1, alpha, 0.5f));
      }
      place(&scene, add_mesh(&scene, square(1.0f, 0.0f, 0)));
      const Geometry g(scene);
      Ray up;
      up.origin = V3f(0.1f, -5.0f, 0.2f);
      up.direction = V3f(0, 1, 0);
      up.tfar = 10.0f;
      const bool kept = alpha == 0.5f;
      EXPECT_EQ(hits(*g.embree, down_from(0.1f, 0.2f, true)), kept) << textured << " " << alpha;
      EXPECT_EQ(hits(*g.embree, down_from(0.1f, 0.2f)), kept) << textured << " " << alpha;
      EXPECT_EQ(g.embree->occluded(up), kept) << textured << " " << alpha;
    }
  }
}

TEST(AlphaModes, CutoffExtremes) {
  // Cutoff 0 keeps even alpha 0; a cutoff above 1 (glTF sets no maximum) removes all.
  for (const float cutoff : {0.0f, 1.5f}) {
    SceneDescription scene;
    scene.materials.push_back(masked(-1, cutoff == 0.0f ? 0.0f : 1.0f, cutoff));
    scene.materials[0].double_sided = true;
    place(&scene, add_mesh(&scene, square(1.0f, 0.0f, 0)));
    const Geometry g(scene);
    Ray up;
    up.origin = V3f(0.0f, -5.0f, 0.0f);
    up.direction = V3f(0, 1, 0);
    up.tfar = 10.0f;
    EXPECT_EQ(hits(*g.embree, down_from(0.0f, 0.0f, true)), cutoff == 0.0f);
    EXPECT_EQ(g.embree->occluded(up), cutoff == 0.0f);
  }
}

TEST(AlphaModes, AlphaReadsTexCoordTransformAndVertexColoursAsTheShadingDoes) {
  // The right half is opaque (u >= 0.5) through TEXCOORD_0 as is; KHR_texture_transform
  // u' = 1 - u (scale -1, offset 1) or TEXCOORD_1 = 1 - u make it the left half; so does
  // COLOR_0 alpha 1 on the left vertices and 0 on the right, untextured (alpha = 1 - u).
  enum class Case { plain, transform, texcoord1, colours };
  for (const Case c : {Case::plain, Case::transform, Case::texcoord1, Case::colours}) {
    SceneDescription scene;
    scene.textures.push_back(left_half_transparent());
    scene.materials.push_back(masked(c == Case::colours ? -1 : 0));
    scene.materials[0].double_sided = true;
    Primitive p = square(0.5f, 0.0f, 0);
    if (c == Case::transform) {
      scene.materials[0].base_colour_mapping.scale = V2f(-1.0f, 1.0f);
      scene.materials[0].base_colour_mapping.offset = V2f(1.0f, 0.0f);
    }
    if (c == Case::texcoord1) {
      scene.materials[0].base_colour_mapping.texcoord = 1;
      for (const V2f& uv : p.uv0) p.uv1.push_back(V2f(1.0f - uv.x, uv.y));
    }
    if (c == Case::colours)
      for (const V2f& uv : p.uv0) p.colours.push_back(Imath::V4f(1, 1, 1, 1.0f - uv.x));
    place(&scene, add_mesh(&scene, p));
    const Geometry g(scene);
    const bool right_opaque = c == Case::plain;
    EXPECT_EQ(hits(*g.embree, down_from(0.25f, 0.1f, true)), right_opaque) << int(c);
    EXPECT_EQ(hits(*g.embree, down_from(-0.25f, 0.1f, true)), !right_opaque) << int(c);
    Ray up;
    up.origin = V3f(-0.25f, -5.0f, 0.1f);
    up.direction = V3f(0, 1, 0);
    up.tfar = 10.0f;
    EXPECT_EQ(g.embree->occluded(up), !right_opaque) << int(c);
  }
}

TEST(AlphaModes, OpaqueIgnoresAlpha) {
  SceneDescription scene;
  scene.textures.push_back(left_half_transparent());
  MaterialDescription m = masked(0, 0.0f);
  m.alpha_mode = AlphaMode::opaque;
  scene.materials.push_back(m);
  place(&scene, add_mesh(&scene, square(0.5f, 0.0f, 0)));
  const Geometry g(scene);
  EXPECT_TRUE(hits(*g.embree, down_from(-0.25f, 0.0f, true)));
  EXPECT_TRUE(hits(*g.embree, down_from(0.25f, 0.0f, true)));
}

TEST(AlphaModes, InstancedMaskedMeshesMatchBakedOnes) {
  // The same masked square placed by two nodes (instanced: the filter runs in object space
  // and reads the instance's ID), one of them mirrored in x, which moves its opaque half
  // to world x < 0; and each placement alone (baked into world space).
  SceneDescription base;
  base.textures.push_back(left_half_transparent());
  base.materials.push_back(masked(0));
  base.materials[0].double_sided = true;
  const int mesh = add_mesh(&base, square(0.5f, 0.0f, 0));
  const M44d shifted = M44d().setTranslation(V3d(2.0, 0.0, 0.0));
  // Row vectors: mirrored first, then moved to x = -2.
  const M44d mirrored =
      M44d().setScale(V3d(-1.0, 1.0, 1.0)) * M44d().setTranslation(V3d(-2.0, 0.0, 0.0));
  SceneDescription instanced = base;
  place(&instanced, mesh, shifted);
  place(&instanced, mesh, mirrored);
  SceneDescription baked_a = base, baked_b = base;
  place(&baked_a, mesh, shifted);
  place(&baked_b, mesh, mirrored);
  const Geometry gi(instanced), ga(baked_a), gb(baked_b);
  ASSERT_EQ(gi.embree->statistics().mesh_instances, 2u);
  ASSERT_EQ(ga.embree->statistics().meshes_baked, 1u);

  // Expected: shifted square opaque for world x in [2, 2.5]; mirrored one for [-2.5, -2].
  int compared = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 8; ++j) {
      const float x = -3.0f + 6.0f * (static_cast<float>(i) + 0.5f) / 64.0f;
      const float z = -0.45f + 0.9f * static_cast<float>(j) / 7.0f;
      const bool expected = (x > 2.0f && x < 2.5f) || (x > -2.5f && x < -2.0f);
      for (const bool camera : {true, false}) {
        const Ray r = down_from(x, z, camera);
        EXPECT_EQ(hits(*gi.embree, r), expected) << x << " " << z;
        EXPECT_EQ(hits(*ga.embree, r) || hits(*gb.embree, r), expected) << x << " " << z;
        Ray up;
        up.origin = V3f(x, -5.0f, z);
        up.direction = V3f(0, 1, 0);
        up.tfar = 10.0f;
        EXPECT_EQ(gi.embree->occluded(up), expected) << x << " " << z;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 1024);
}

// ---- BLEND ----

// A square of constant alpha over a background: with no light and no ambient term a pixel
// shows the square's emission where the camera ray keeps the hit, the background elsewhere.
SceneDescription blend_square(float alpha) {
  SceneDescription scene;
  MaterialDescription m = lambert_like(0.0f);
  m.emissive = C3f(1.0f, 1.0f, 1.0f);
  m.alpha_mode = AlphaMode::blend;
  m.alpha = alpha;
  scene.materials.push_back(m);
  place(&scene, add_mesh(&scene, square(2.0f, 0.0f, 0)));
  scene.cameras.push_back(ortho_camera_looking_down_y(5.0, 1.0));
  return scene;
}

struct PixelStatistics {
  double mean = 0.0;
  double rms_error = 0.0;  // against `expected`
  double mean_alpha = 0.0;
};

PixelStatistics statistics(const Image& image, double expected) {
  PixelStatistics s;
  const double n = static_cast<double>(image.width) * image.height;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      s.mean += p[0] / n;
      s.rms_error += (p[0] - expected) * (p[0] - expected) / n;
      s.mean_alpha += p[3] / n;
    }
  s.rms_error = std::sqrt(s.rms_error);
  return s;
}

TEST(AlphaModes, BlendConvergesToTheAlphaBlendedValue) {
  // alpha 0.25, surface 1, background 0.2: 0.25 x 1 + 0.75 x 0.2 = 0.4. Each sample keeps
  // the hit with probability 0.25 independently, so a pixel of N samples has a binomial
  // error of sd = |1 - 0.2| sqrt(0.25 x 0.75 / N): 0.0433 at N = 64, 0.0217 at N = 256. The
  // mean of 32 x 32 pixels has sd 0.0014 at N = 64: within 0.01 is 7 sd. The pixels' RMS
  // error must match the binomial sd within 20% (1024 pixels estimate it to about 2%):
  // neither correlated decisions (larger) nor a fixed dither (smaller) pass.
  const SceneDescription scene = blend_square(0.25f);
  const auto phong = make_integrator("phong");
  testing::TestSettings settings;
  settings.width = settings.height = 32;
  settings.background = V3f(0.2f);
  const double expected = 0.25 * 1.0 + 0.75 * 0.2;
  for (const int spp : {64, 256}) {
    settings.spp = spp;
    const PixelStatistics s = statistics(render_scene(scene, *phong, settings).image, expected);
    const double sd = 0.8 * std::sqrt(0.25 * 0.75 / spp);
    std::printf("blend %3d spp: mean %.5f (expected %.5f), rms/sd %.3f, coverage %.5f\n", spp,
                s.mean, expected, s.rms_error / sd, s.mean_alpha);
    EXPECT_NEAR(s.mean, expected, 0.01) << spp;
    EXPECT_NEAR(s.rms_error / sd, 1.0, 0.2) << spp;
    EXPECT_NEAR(s.mean_alpha, 0.25, 0.01) << spp;  // coverage: the fraction of kept hits
  }
}

TEST(AlphaModes, BlendAttenuatesShadowRaysLayerByLayer) {
  // Shadow rays through two stacked BLEND squares (alpha 0.25 and 0.5) reach the light with
  // probability 0.75 x 0.5 = 0.375 when the two decisions are independent (a shared random
  // number would give min(0.75, 0.5) = 0.5). 10^4 distinct rays: binomial sd 0.0048; the
  // tolerance 0.02 is 4 sd.
  SceneDescription scene;
  for (const float alpha : {0.25f, 0.5f}) {
    MaterialDescription m = lambert_like(0.5f);
    m.alpha_mode = AlphaMode::blend;
    m.alpha = alpha;
    scene.materials.push_back(m);
  }
  place(&scene, add_mesh(&scene, square(2.0f, 1.0f, 0)));
  place(&scene, add_mesh(&scene, square(2.0f, 2.0f, 1)));
  const Geometry g(scene);
  int passed = 0, one_layer_passed = 0;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) {
      Ray r;
      r.origin = V3f(-1.0f + 0.02f * i, 0.0f, -1.0f + 0.02f * j);
      r.direction = V3f(0, 1, 0);
      r.tfar = 10.0f;
      passed += !g.embree->occluded(r);
      r.tfar = 1.5f;  // the lower square alone
      one_layer_passed += !g.embree->occluded(r);
    }
  std::printf("blend shadows: %.4f pass two layers (0.375), %.4f one (0.75)\n", passed / 1e4,
              one_layer_passed / 1e4);
  EXPECT_NEAR(passed / 1e4, 0.375, 0.02);
  EXPECT_NEAR(one_layer_passed / 1e4, 0.75, 0.02);
}

TEST(AlphaModes, BlendDecisionsAreStableAndUniform) {
  // The same ray and primitive always give the same number (Embree may report a hit more
  // than once); different primitives or instances give independent ones.
  Ray r;
  r.origin = V3f(0.1f, 0.2f, 0.3f);
  r.direction = V3f(0.0f, 0.6f, 0.8f);
  const uint64_t h = ray_hash(r);
  EXPECT_EQ(blend_uniform(h, 1, 2, 3), blend_uniform(ray_hash(r), 1, 2, 3));
  EXPECT_NE(blend_uniform(h, 1, 2, 3), blend_uniform(h, 1, 2, 4));
  EXPECT_NE(blend_uniform(h, 1, 2, 3), blend_uniform(h, 0, 2, 3));
  // Uniform in [0, 1): the mean of 10^5 draws is 0.5 with sd 0.0009.
  double sum = 0.0;
  float lowest = 1.0f, highest = 0.0f;
  for (unsigned p = 0; p < 100000; ++p) {
    const float u = blend_uniform(h, RTC_INVALID_GEOMETRY_ID, 0, p);
    sum += u;
    lowest = std::min(lowest, u);
    highest = std::max(highest, u);
  }
  EXPECT_NEAR(sum / 1e5, 0.5, 0.005);
  EXPECT_GE(lowest, 0.0f);
  EXPECT_LT(highest, 1.0f);
}

TEST(AlphaModes, ImagesAreIdenticalForAnyThreadCount) {
  SceneDescription scene = masked_square_over_ground();
  MaterialDescription glass = lambert_like(0.3f);
  glass.alpha_mode = AlphaMode::blend;
  glass.alpha = 0.4f;
  scene.materials.push_back(glass);
  place(&scene, add_mesh(&scene, square(0.6f, 1.5f, 2, -0.5f, 0.0f)));
  testing::TestSettings settings;
  settings.width = settings.height = 64;
  settings.spp = 8;
  settings.tile_size = 8;
  const auto whitted = make_integrator("whitted");
  settings.threads = 1;
  const Image one = render_scene(scene, *whitted, settings).image;
  settings.threads = 3;
  const Image three = render_scene(scene, *whitted, settings).image;
  ASSERT_EQ(one.rgba.size(), three.rgba.size());
  EXPECT_EQ(std::memcmp(one.rgba.data(), three.rgba.data(), one.rgba.size() * sizeof(float)), 0);
}

// ---- doubleSided ----

TEST(AlphaModes, CameraRaysCullBackFacesOfSingleSidedMaterialsOnly) {
  // A square facing down, seen from above: single-sided, the camera sees through it to the
  // ground, which it still shadows; double-sided, the camera sees it. Secondary rays
  // (not from the camera) see the back face either way.
  for (const bool double_sided : {false, true}) {
    SceneDescription scene;
    scene.materials.push_back(lambert_like(0.5f));
    MaterialDescription m = lambert_like(0.8f);
    m.double_sided = double_sided;
    scene.materials.push_back(m);
    place(&scene, add_mesh(&scene, square(4.0f, 0.0f, 0)));
    place(&scene, add_mesh(&scene, square_facing_down(0.5f, 1.0f, 1)));
    const Geometry g(scene);
    SurfaceHit hit;
    ASSERT_TRUE(g.embree->intersect(down_from(0.0f, 0.0f, true), &hit));
    EXPECT_NEAR(hit.position.y, double_sided ? 1.0f : 0.0f, 1e-6f);
    ASSERT_TRUE(g.embree->intersect(down_from(0.0f, 0.0f, false), &hit));
    EXPECT_NEAR(hit.position.y, 1.0f, 1e-6f);
    EXPECT_TRUE(hit.back_face);
    Ray to_sun;
    to_sun.origin = V3f(0.0f, 0.0f, 0.0f);
    to_sun.direction = V3f(0, 1, 0);
    to_sun.tnear = 1e-4f;
    EXPECT_TRUE(g.embree->occluded(to_sun));  // its front faces the ground: still a shadow
  }
}

TEST(AlphaModes, CullingFollowsTheAuthoredFrontThroughMirroringNodes) {
  // glTF: a node with a negative determinant flips the winding, so the authored front face
  // stays in front. A square facing +Y, mirrored in y by its node, faces -Y in the world:
  // seen from above it is its back. Baked (one node) and instanced (two nodes) agree.
  for (const int nodes : {1, 2}) {
    SceneDescription scene;
    scene.materials.push_back(lambert_like(0.8f));
    const int mesh = add_mesh(&scene, square(0.5f, 1.0f, 0));
    place(&scene, mesh, M44d().setScale(V3d(1.0, -1.0, 1.0)));
    if (nodes == 2) place(&scene, mesh, M44d().setTranslation(V3d(5.0, 0.0, 0.0)));
    const Geometry g(scene);
    EXPECT_FALSE(hits(*g.embree, down_from(0.0f, 0.0f, true))) << nodes;
    EXPECT_TRUE(hits(*g.embree, down_from(0.0f, 0.0f, false))) << nodes;
    if (nodes == 2) {
      EXPECT_TRUE(hits(*g.embree, down_from(5.0f, 0.0f, true)));  // not mirrored: front
    }
  }
}

TEST(AlphaModes, TheDefaultMaterialIsSingleSided) {
  SceneDescription scene;
  place(&scene, add_mesh(&scene, square_facing_down(0.5f, 1.0f, -1)));
  const Geometry g(scene);
  EXPECT_FALSE(hits(*g.embree, down_from(0.0f, 0.0f, true)));
  EXPECT_TRUE(hits(*g.embree, down_from(0.0f, 0.0f, false)));
}

TEST(AlphaModes, SpheresAreSeenFromBothSidesAndIgnoreAlpha) {
  SceneDescription scene;
  MaterialDescription m = masked(-1, 0.0f);
  scene.materials.push_back(m);
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, "ball"});
  for (const SphereMode mode :
       {SphereMode::analytic, SphereMode::embree_points, SphereMode::mesh}) {
    GeometryOptions options;
    options.spheres.mode = mode;
    const EmbreeScene g(scene, options);
    Ray inside;  // a camera ray from the centre sees the back of the shell
    inside.origin = V3f(0.0f, 0.0f, 0.0f);  // Imath leaves vectors uninitialised
    inside.direction = V3f(0, 1, 0);
    inside.from_camera = true;
    EXPECT_TRUE(hits(g, inside));
    EXPECT_TRUE(hits(g, down_from(0.0f, 0.0f, true)));
  }
}

// ---- the feature set and the loader ----

TEST(AlphaModes, FeatureSetNamesTheAlphaModesInUse) {
  SceneDescription scene = masked_square_over_ground();
  EXPECT_TRUE(derive_scene_features(scene, {}).alpha_mask);
  EXPECT_NE(to_string(derive_scene_features(scene, {})).find(" alpha=mask "), std::string::npos);
  MaterialDescription b = lambert_like(0.5f);
  b.alpha_mode = AlphaMode::blend;
  scene.materials.push_back(b);
  EXPECT_FALSE(derive_scene_features(scene, {}).alpha_blend);  // not used yet
  place(&scene, add_mesh(&scene, square(0.5f, 2.0f, 2)));
  EXPECT_NE(to_string(derive_scene_features(scene, {})).find(" alpha=mask+blend "),
            std::string::npos);
}

std::string material_file(const test::json& material, const std::string& name) {
  test::Builder b;
  const int pos = b.quad_positions();
  const int idx = b.accessor(b.view(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), 5123, 6, "SCALAR");
  b.doc["materials"] = test::json::array({material});
  b.node(
      {{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"material", 0}})}});
  return b.write(name);
}

TEST(AlphaModes, LoaderReadsAlphaModeCutoffAndDoubleSided) {
  const SceneDescription opaque =
      load_gltf(material_file(test::json::object(), "alpha_default.gltf"));
  ASSERT_EQ(opaque.materials.size(), 1u);
  EXPECT_EQ(opaque.materials[0].alpha_mode, AlphaMode::opaque);
  EXPECT_EQ(opaque.materials[0].alpha_cutoff, 0.5f);
  EXPECT_FALSE(opaque.materials[0].double_sided);
  const SceneDescription mask = load_gltf(material_file(
      {{"alphaMode", "MASK"}, {"alphaCutoff", 0.25}, {"doubleSided", true}}, "alpha_mask.gltf"));
  EXPECT_EQ(mask.materials[0].alpha_mode, AlphaMode::mask);
  EXPECT_EQ(mask.materials[0].alpha_cutoff, 0.25f);
  EXPECT_TRUE(mask.materials[0].double_sided);
  const SceneDescription blend =
      load_gltf(material_file({{"alphaMode", "BLEND"}}, "alpha_blend.gltf"));
  EXPECT_EQ(blend.materials[0].alpha_mode, AlphaMode::blend);
}

std::string load_error(const std::string& path) {
  try {
    load_gltf(path);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "loaded";
}

TEST(AlphaModes, LoaderRefusesUnknownModesAndNegativeCutoffs) {
  const std::string mode = load_error(material_file({{"alphaMode", "blend"}}, "alpha_bad.gltf"));
  EXPECT_NE(mode.find("alpha_bad.gltf: materials[0].alphaMode: \"blend\" is not OPAQUE, MASK or "
                      "BLEND"),
            std::string::npos)
      << mode;
  const std::string cutoff = load_error(
      material_file({{"alphaMode", "MASK"}, {"alphaCutoff", -0.5}}, "alpha_cutoff.gltf"));
  EXPECT_NE(cutoff.find("alpha_cutoff.gltf: materials[0].alphaCutoff: "), std::string::npos)
      << cutoff;
}

}  // namespace
}  // namespace prism
