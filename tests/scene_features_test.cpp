// The scene feature set (renderer/scene_features.h): each flag on small hand-built scenes and
// on the shipped scenes, and the promise behind shadows=no: where the rule says nothing can
// block a shadow ray, the shadow integrator renders exactly what phong renders.
#include <gtest/gtest.h>

#include "integrators/registry.h"
#include "renderer/scene_features.h"
#include "scene_io/gltf_loader.h"
#include "scene_passes/scene_defaults.h"
#include "tests/test_scenes.h"

#ifndef PRISM_SOURCE_DIR
#define PRISM_SOURCE_DIR "."
#endif

namespace prism {
namespace {

using testing::lambert_like;
using testing::quad_mesh;

SphereOptions mode(SphereMode m) {
  SphereOptions o;
  o.mode = m;
  return o;
}

using testing::directional_light;
using testing::point_light;

SceneDescription one_sphere() {
  SceneDescription s;
  s.materials.push_back(lambert_like(0.5f));
  s.spheres.push_back({V3d(0.0, 0.0, -5.0), 1.0, 0, "ball"});
  s.lights.push_back(point_light(V3d(2.0, 3.0, 0.0)));
  return s;
}

// A 2 m quad at y = 0 facing +Y, lit from above.
SceneDescription one_quad() {
  SceneDescription s;
  s.materials.push_back(lambert_like(0.5f));
  s.meshes.push_back(quad_mesh(1.0f, 0.0f, 0));
  s.instances.push_back({0, M44d(), "floor"});
  s.lights.push_back(point_light(V3d(0.0, 2.0, 0.0)));
  return s;
}

TEST(SceneFeatures, EmptySceneHasNothing) {
  const SceneFeatures f = derive_scene_features(SceneDescription(), SphereOptions());
  EXPECT_EQ(f.geometry, GeometryKind::none);
  EXPECT_EQ(f.lights, LightKinds::none);
  EXPECT_EQ(f.textures, TexturedSlots::none);
  EXPECT_FALSE(f.mirror);
  EXPECT_FALSE(f.transmission);
  EXPECT_FALSE(f.emission);
  EXPECT_FALSE(f.shadows);
  EXPECT_EQ(f.objects, 0u);
  EXPECT_EQ(to_string(f),
            "geometry=none lights=none textures=none mirror=no transmission=no emission=no "
            "alpha=none shadows=no");
}

TEST(SceneFeatures, OneExactSphereCannotShadowItselfButAnIcosphereCan) {
  const SceneDescription s = one_sphere();
  const SceneFeatures analytic = derive_scene_features(s, mode(SphereMode::analytic));
  EXPECT_EQ(analytic.geometry, GeometryKind::analytic_spheres);
  EXPECT_EQ(analytic.spheres, 1u);
  EXPECT_EQ(analytic.objects, 1u);
  EXPECT_EQ(analytic.lights, LightKinds::positional);
  EXPECT_FALSE(analytic.shadows);

  const SceneFeatures points = derive_scene_features(s, mode(SphereMode::embree_points));
  EXPECT_EQ(points.geometry, GeometryKind::point_spheres);
  EXPECT_FALSE(points.shadows);

  // Interpolated normals face the light beyond the flat faces' terminator.
  const SceneFeatures mesh = derive_scene_features(s, mode(SphereMode::mesh));
  EXPECT_EQ(mesh.geometry, GeometryKind::sphere_meshes);
  EXPECT_TRUE(mesh.shadows);
}

TEST(SceneFeatures, OneFlatQuadCannotShadowItselfUnlessALightLiesInItsPlane) {
  SceneDescription s = one_quad();
  SceneFeatures f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.geometry, GeometryKind::triangles);
  EXPECT_EQ(f.triangles, 2u);
  EXPECT_FALSE(f.shadows);

  s.lights = {directional_light(V3d(0.3, -1.0, 0.2))};
  f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.lights, LightKinds::directional_only);
  EXPECT_FALSE(f.shadows);

  // Grazing light: the segment to it runs along the plane.
  s.lights = {directional_light(V3d(1.0, 0.0, 0.0))};
  EXPECT_TRUE(derive_scene_features(s, SphereOptions()).shadows);
  s.lights = {point_light(V3d(5.0, 0.0, 0.0))};
  EXPECT_TRUE(derive_scene_features(s, SphereOptions()).shadows);

  // Flat however it is placed.
  s.lights = {point_light(V3d(0.0, 0.0, 3.0))};
  s.instances[0].object_to_world =
      M44d().rotate(V3d(1.2, 0.4, 0.0)) * M44d().translate(V3d(7, 1, 2));
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).shadows);

  s.lights.clear();
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).shadows);
}

TEST(SceneFeatures, TwoObjectsOrABentMeshMayShadow) {
  SceneDescription s = one_quad();
  s.spheres.push_back({V3d(0.0, 1.0, 0.0), 0.5, 0, "ball"});
  SceneFeatures f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.geometry, GeometryKind::triangles | GeometryKind::analytic_spheres);
  EXPECT_EQ(f.objects, 2u);
  EXPECT_TRUE(f.shadows);

  // The same quad placed twice: two instances, two objects.
  s = one_quad();
  s.instances.push_back({0, M44d().setTranslation(V3d(0.0, 1.0, 0.0)), "shelf"});
  f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.triangles, 4u);
  EXPECT_EQ(f.objects, 2u);
  EXPECT_TRUE(f.shadows);

  // A tent: two faces meeting at a ridge, one mesh.
  s = one_quad();
  s.meshes[0].primitives[0].positions[2].y = 1.0f;
  s.meshes[0].primitives[0].positions[3].y = 1.0f;
  s.meshes[0].primitives[0].positions.push_back(V3f(0.0f, 0.0f, -3.0f));
  s.meshes[0].primitives[0].indices = {0, 1, 2, 0, 2, 3, 3, 2, 4};
  s.meshes[0].primitives[0].normals.clear();
  f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.objects, 1u);
  EXPECT_TRUE(f.shadows);
}

TEST(SceneFeatures, MirrorFollowsRoughnessThresholdAndTexture) {
  SceneDescription s = one_sphere();
  s.materials[0].roughness = kMirrorRoughness;
  EXPECT_TRUE(derive_scene_features(s, SphereOptions()).mirror);
  s.materials[0].roughness = kMirrorRoughness + 0.01f;
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).mirror);

  // Roughness = factor x green: a 2x1 map whose smallest green is 0.25.
  TextureImage map;
  map.width = 2;
  map.height = 1;
  map.channels = 3;
  map.encoding = TextureEncoding::linear_data;
  map.texels = {0.0f, 0.9f, 1.0f, 0.0f, 0.25f, 1.0f};
  s.textures.push_back(map);
  s.materials[0].metallic_roughness_texture = 0;
  s.materials[0].roughness = 0.4f;  // down to 0.1 where green is 0.25
  SceneFeatures f = derive_scene_features(s, SphereOptions());
  EXPECT_TRUE(f.mirror);
  EXPECT_EQ(f.textures, TexturedSlots::metallic_roughness);
  s.materials[0].roughness = 0.5f;  // never below 0.125
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).mirror);

  // A mirror material nothing uses does not count.
  s.materials.push_back(lambert_like(0.5f));
  s.materials.back().roughness = 0.0f;
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).mirror);
}

TEST(SceneFeatures, TransmissionEmissionAndTextureSlots) {
  SceneDescription s = one_sphere();
  s.materials[0].transmission = 1.0f;
  EXPECT_TRUE(derive_scene_features(s, SphereOptions()).transmission);
  s.materials[0].metallic = 1.0f;  // a metal never refracts...
  EXPECT_FALSE(derive_scene_features(s, SphereOptions()).transmission);
  TextureImage texel;
  texel.width = texel.height = 1;
  texel.channels = 3;
  texel.texels = {1.0f, 1.0f, 0.5f};
  texel.encoding = TextureEncoding::linear_data;
  s.textures.push_back(texel);
  s.materials[0].metallic_roughness_texture = 0;  // ...unless a map can make it partly metal
  SceneFeatures f = derive_scene_features(s, SphereOptions());
  EXPECT_TRUE(f.transmission);
  EXPECT_FALSE(f.emission);

  s.materials[0].base_colour_texture = 0;
  s.materials[0].emissive_texture = 0;
  f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.textures, TexturedSlots::base_colour | TexturedSlots::metallic_roughness |
                            TexturedSlots::emissive);
  EXPECT_FALSE(f.emission);  // the texture only scales a zero factor
  s.materials[0].emissive = C3f(0.0f, 0.2f, 0.0f);
  EXPECT_TRUE(derive_scene_features(s, SphereOptions()).emission);
  EXPECT_EQ(to_string(f.textures), "base-colour+metallic-roughness+emissive");
}

TEST(SceneFeatures, LightKinds) {
  SceneDescription s = one_sphere();
  s.lights = {directional_light(V3d(0, -1, 0)), directional_light(V3d(1, -1, 0))};
  SceneFeatures f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.lights, LightKinds::directional_only);
  EXPECT_EQ(f.directional_lights, 2u);
  Light spot = point_light(V3d(0, 3, 0));
  spot.type = LightType::spot;
  s.lights.push_back(spot);
  f = derive_scene_features(s, SphereOptions());
  EXPECT_EQ(f.lights, LightKinds::positional);
  EXPECT_EQ(f.spot_lights, 1u);
  EXPECT_EQ(f.point_lights, 0u);
}

TEST(SceneFeatures, MetadataPairs) {
  const SceneFeatures f = derive_scene_features(one_sphere(), SphereOptions());
  const auto pairs = feature_metadata(f);
  ASSERT_EQ(pairs.size(), 9u);
  EXPECT_EQ(pairs[0].first, "features");
  EXPECT_EQ(pairs[0].second, to_string(f));
  EXPECT_EQ(pairs[1],
            std::make_pair(std::string("featureGeometry"), std::string("analytic-spheres")));
  EXPECT_EQ(pairs[2].second, "positional");
  EXPECT_EQ(pairs[7], std::make_pair(std::string("featureShadows"), std::string("no")));
  EXPECT_EQ(pairs[8], std::make_pair(std::string("featureAlpha"), std::string("none")));
}

SceneFeatures shipped(const char* name, SphereOptions spheres = {}) {
  SceneDescription s = load_gltf(std::string(PRISM_SOURCE_DIR "/scenes/") + name);
  add_scene_defaults(&s);
  return derive_scene_features(s, spheres);
}

TEST(SceneFeatures, SpheresScene) {
  const SceneFeatures f = shipped("spheres.gltf");
  EXPECT_EQ(f.geometry, GeometryKind::triangles | GeometryKind::analytic_spheres);
  EXPECT_EQ(f.triangles, 4u);
  EXPECT_EQ(f.spheres, 4u);
  EXPECT_EQ(f.lights, LightKinds::positional);
  EXPECT_EQ(f.point_lights, 1u);
  EXPECT_EQ(f.directional_lights, 1u);
  EXPECT_EQ(f.textures, TexturedSlots::base_colour);
  EXPECT_TRUE(f.mirror);
  EXPECT_TRUE(f.transmission);
  EXPECT_FALSE(f.emission);
  EXPECT_TRUE(f.shadows);
  EXPECT_EQ(shipped("spheres.gltf", mode(SphereMode::mesh)).geometry,
            GeometryKind::triangles | GeometryKind::sphere_meshes);
}

TEST(SceneFeatures, FurnaceScene) {
  const SceneFeatures f = shipped("furnace.gltf");
  EXPECT_EQ(f.geometry, GeometryKind::analytic_spheres);
  EXPECT_EQ(f.spheres, 1u);
  EXPECT_EQ(f.lights, LightKinds::positional);
  EXPECT_EQ(f.textures, TexturedSlots::none);
  EXPECT_FALSE(f.mirror);
  EXPECT_FALSE(f.transmission);
  EXPECT_FALSE(f.emission);
  EXPECT_FALSE(f.shadows);  // a light inside one sphere
  EXPECT_TRUE(shipped("furnace.gltf", mode(SphereMode::mesh)).shadows);
}

TEST(SceneFeatures, WhittedScene) {
  const SceneFeatures f = shipped("whitted.gltf");
  EXPECT_EQ(f.geometry, GeometryKind::triangles | GeometryKind::analytic_spheres);
  EXPECT_EQ(f.spheres, 4u);
  EXPECT_EQ(f.point_lights, 2u);
  EXPECT_EQ(f.lights, LightKinds::positional);
  EXPECT_EQ(f.textures, TexturedSlots::none);
  EXPECT_TRUE(f.mirror);
  EXPECT_TRUE(f.transmission);
  EXPECT_FALSE(f.emission);
  EXPECT_TRUE(f.shadows);
}

// shadows=no is a promise: casting the shadow rays changes nothing.
void expect_shadow_rays_change_nothing(const SceneDescription& scene,
                                       const SphereOptions& spheres) {
  ASSERT_FALSE(derive_scene_features(scene, spheres).shadows);
  testing::TestSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.specialise = false;  // specialised, the shadow integrator would skip the rays
  GeometryOptions options;
  options.spheres = spheres;
  const auto phong = testing::render_scene(scene, "phong", settings, options);
  const auto shadow = testing::render_scene(scene, "shadow", settings, options);
  EXPECT_GT(shadow.result.rays[RayKind::shadow], 0u);
  ASSERT_EQ(phong.image.rgba.size(), shadow.image.rgba.size());
  for (size_t i = 0; i < phong.image.rgba.size(); ++i)
    ASSERT_EQ(phong.image.rgba[i], shadow.image.rgba[i]) << "value " << i;
}

TEST(SceneFeatures, NoShadowsMeansShadowRaysChangeNothing) {
  SceneDescription furnace = load_gltf(PRISM_SOURCE_DIR "/scenes/furnace.gltf");
  add_scene_defaults(&furnace);
  expect_shadow_rays_change_nothing(furnace, SphereOptions());

  SceneDescription ball = one_sphere();
  add_scene_defaults(&ball);
  expect_shadow_rays_change_nothing(ball, SphereOptions());
  expect_shadow_rays_change_nothing(ball, mode(SphereMode::embree_points));

  SceneDescription floor = one_quad();
  floor.lights.push_back(directional_light(V3d(0.5, -1.0, -0.3)));
  add_scene_defaults(&floor);
  expect_shadow_rays_change_nothing(floor, SphereOptions());
}

// The memory a loaded scene holds, as the batch runner's scene cache budgets it: textures
// that read one image (two samplers, or sRGB and linear uses) share its codes, counted once.
TEST(DescriptionBytes, SharedTexelsAreCountedOnce) {
  SceneDescription scene;
  const auto codes = std::make_shared<const std::vector<uint8_t>>(size_t{1} << 20, uint8_t{7});
  TextureImage image;
  image.width = 512;
  image.height = 512;
  image.channels = 4;
  image.shared_codes = codes;
  scene.textures.push_back(image);
  const uint64_t one = description_bytes(scene);
  EXPECT_GE(one, codes->capacity());
  scene.textures.push_back(image);  // the same image through another sampler
  EXPECT_EQ(description_bytes(scene), one) << "the second texture's codes were counted again";
  TextureImage other = image;
  other.shared_codes = std::make_shared<const std::vector<uint8_t>>(size_t{1} << 20, uint8_t{9});
  scene.textures.push_back(other);
  EXPECT_GE(description_bytes(scene), one + other.shared_codes->capacity());
}

}  // namespace
}  // namespace prism
