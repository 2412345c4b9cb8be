// The structural side of real glTF files (issue 6): sparse accessors, morph targets at their
// default weights, skins at rest, scene selection, KHR_materials_pbrSpecularGlossiness and
// KHR_draco_mesh_compression. Each hand-made file pins one rule with values computed by hand.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <Imath/ImathBox.h>

#include "renderer/geometry/embree_scene.h"
#include "scene_io/gltf_loader.h"
#include "scene_io/gltf_specular_glossiness.h"
#include "tests/gltf_test_builder.h"
#include "tests/scratch_dir.h"

#ifndef PRISM_ASSIMP_GLTF2_DIR
#define PRISM_ASSIMP_GLTF2_DIR "/usr/share/assimp/models/glTF2"
#endif

namespace prism {
namespace {

using nlohmann::json;
using test::Builder;
namespace fs = std::filesystem;

const std::string kSamples = PRISM_ASSIMP_GLTF2_DIR;

constexpr int kFloat = 5126;
constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;

std::string load_error(const std::string& path, const LoadOptions& options = {}) {
  try {
    load_gltf(path, options);
  } catch (const LoadError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " loaded without error";
  return {};
}

// Float results of float inputs: exact up to the rounding of a few float operations.
constexpr float kFloatTolerance = 1e-6f;

void expect_near(const V3f& a, const V3f& b, float tolerance = kFloatTolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// ---------------------------------------------------------------------------------------------
// Sparse accessors.

// A triangle whose POSITION accessor is `base` (or zeros) with vertices 0 and 2 replaced.
json sparse_positions(Builder& b, bool with_base) {
  json a = {{"componentType", kFloat}, {"count", 3}, {"type", "VEC3"}};
  if (with_base) a["bufferView"] = b.view(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  a["sparse"] = {
      {"count", 2},
      {"indices",
       {{"bufferView", b.view(std::vector<uint16_t>{0, 2})}, {"componentType", kUnsignedShort}}},
      {"values", {{"bufferView", b.view(std::vector<float>{5, 5, 5, 7, 8, 9})}}}};
  return a;
}

int add_accessor(Builder& b, const json& a) {
  b.doc["accessors"].push_back(a);
  return static_cast<int>(b.doc["accessors"].size() - 1);
}

TEST(GltfSparse, SubstitutesIntoTheBaseAndIntoZeros) {
  for (bool with_base : {true, false}) {
    SCOPED_TRACE(with_base ? "with base" : "zeros");
    Builder b;
    const int positions = add_accessor(b, sparse_positions(b, with_base));
    b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", positions}}}})}});
    const SceneDescription s = load_gltf(b.write("sparse.gltf"));
    const std::vector<V3f>& p = s.meshes.at(0).primitives.at(0).positions;
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[0], V3f(5, 5, 5));
    EXPECT_EQ(p[1], with_base ? V3f(1, 0, 0) : V3f(0, 0, 0));
    EXPECT_EQ(p[2], V3f(7, 8, 9));
  }
}

TEST(GltfSparse, BadIndicesAndRangesAreErrors) {
  struct Case {
    const char* what;
    std::vector<uint16_t> indices;
    int count;
    const char* expected;
  };
  const Case cases[] = {
      {"not increasing", {2, 0}, 2, "accessors[0].sparse.indices: index 0 at position 1 is not"},
      {"repeated", {1, 1}, 2, "accessors[0].sparse.indices: index 1 at position 1 is not"},
      {"out of range",
       {0, 3},
       2,
       "accessors[0].sparse.indices: index 3 at position 1 out of range"},
      {"count above the accessor's", {0, 1, 2, 3}, 4, "accessors[0].sparse.count: count 4"},
      {"values past their view", {0, 1, 2}, 3, "accessors[0].sparse.values: byteOffset 0 + 36"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Builder b;
    json a = sparse_positions(b, true);
    a["sparse"]["count"] = c.count;
    a["sparse"]["indices"]["bufferView"] = b.view(c.indices);
    const int positions = add_accessor(b, a);
    b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", positions}}}})}});
    const std::string message = load_error(b.write("bad_sparse.gltf"));
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  // A zero-filled sparse accessor is allocated whole: its size is limited.
  Builder b;
  json a = sparse_positions(b, false);
  a["count"] = 30'000'000;  // 360 MB of zeros
  const int positions = add_accessor(b, a);
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", positions}}}})}});
  const std::string message = load_error(b.write("huge_sparse.gltf"));
  EXPECT_NE(message.find("accessors[0]: sparse accessor of 30000000 elements"), std::string::npos)
      << message;
}

// ---------------------------------------------------------------------------------------------
// Morph targets.

// A unit quad with normals +Z and two targets: target 0 lifts every vertex by +Z and tilts the
// normals towards +X; target 1 (a sparse accessor) moves vertex 2 by +X only.
Builder morph_quad(const json& mesh_weights) {
  Builder b;
  const int positions = b.quad_positions();
  const int normals =
      b.accessor(b.view(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}), kFloat, 4, "VEC3");
  const int indices =
      b.accessor(b.view(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), kUnsignedShort, 6, "SCALAR");
  const int lift = b.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  const int tilt = b.positions({1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0});
  json moved = {{"componentType", kFloat}, {"count", 4}, {"type", "VEC3"}};
  moved["sparse"] = {
      {"count", 1},
      {"indices",
       {{"bufferView", b.view(std::vector<uint16_t>{2})}, {"componentType", kUnsignedShort}}},
      {"values", {{"bufferView", b.view(std::vector<float>{1, 0, 0})}}}};
  const int move = add_accessor(b, moved);
  b.doc["meshes"].push_back(
      {{"primitives", json::array({{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                                    {"indices", indices},
                                    {"targets", json::array({{{"POSITION", lift}, {"NORMAL", tilt}},
                                                             {{"POSITION", move}}})}}})}});
  if (!mesh_weights.is_null()) b.doc["meshes"][0]["weights"] = mesh_weights;
  return b;
}

TEST(GltfMorphTargets, MeshWeightsAndNodeWeightsOverridingThem) {
  Builder b = morph_quad(json::array({0.5, 2.0}));
  b.node({{"mesh", 0}});
  b.node({{"mesh", 0}, {"weights", json::array({0.0, 1.0})}});
  const SceneDescription s = load_gltf(b.write("morph.gltf"));
  // Two poses: two converted meshes.
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.instances.size(), 2u);
  const Primitive& mesh_pose = s.meshes[std::size_t(s.instances[0].mesh)].primitives.at(0);
  // base + 0.5 * (0, 0, 1) + 2 * (1, 0, 0) at vertex 2 only.
  const std::vector<V3f> expected = {{0, 0, 0.5f}, {1, 0, 0.5f}, {3, 1, 0.5f}, {0, 1, 0.5f}};
  for (std::size_t i = 0; i < 4; ++i) expect_near(mesh_pose.positions[i], expected[i]);
  // (0, 0, 1) + 0.5 * (1, 0, 0), renormalised: (1, 0, 2) / sqrt(5).
  for (const V3f& n : mesh_pose.normals) expect_near(n, V3f(1, 0, 2) / std::sqrt(5.0f));

  const Primitive& node_pose = s.meshes[std::size_t(s.instances[1].mesh)].primitives.at(0);
  const std::vector<V3f> moved = {{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  for (std::size_t i = 0; i < 4; ++i) expect_near(node_pose.positions[i], moved[i]);
  for (const V3f& n : node_pose.normals) EXPECT_EQ(n, V3f(0, 0, 1));
}

TEST(GltfMorphTargets, NoWeightsIsTheBaseMeshAndWrongCountsAreErrors) {
  Builder b = morph_quad(json());
  b.node({{"mesh", 0}});
  const SceneDescription s = load_gltf(b.write("morph_default.gltf"));
  EXPECT_EQ(s.meshes.at(0).primitives.at(0).positions[2], V3f(1, 1, 0));

  Builder wrong_mesh = morph_quad(json::array({1.0}));
  wrong_mesh.node({{"mesh", 0}});
  std::string message = load_error(wrong_mesh.write("morph_wrong_mesh.gltf"));
  EXPECT_NE(message.find("meshes[0].weights: 1 weights for 2 morph targets"), std::string::npos)
      << message;

  Builder wrong_node = morph_quad(json());
  wrong_node.node({{"mesh", 0}, {"weights", json::array({1.0, 2.0, 3.0})}});
  message = load_error(wrong_node.write("morph_wrong_node.gltf"));
  EXPECT_NE(message.find("nodes[0].weights: 3 weights for 2 morph targets"), std::string::npos)
      << message;
}

TEST(GltfMorphTargets, AnimatedMorphCubeRestsAtItsDefaultWeights) {
  // Its mesh weights are [0, 0]: the rest pose is the base cube, 12 triangles, +-1 cm.
  const SceneDescription s =
      load_gltf(kSamples + "/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  const Primitive& p = s.meshes[0].primitives.at(0);
  EXPECT_EQ(p.indices.size(), 36u);
  Imath::Box3f box;
  for (const V3f& v : p.positions) box.extendBy(v);
  expect_near(box.min, V3f(-0.01f), 1e-6f);
  expect_near(box.max, V3f(0.01f), 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Skins.

// One triangle skinned to two joints. Joint 0 sits at the origin; joint 1 was bound at (1, 0, 0)
// (inverse bind = translation by -1 in x) and rests at (2, 0, 0) turned 90 degrees about +Z.
// Vertex 0 follows joint 0, vertex 1 joint 1, vertex 2 both, with weights 0.25 + 0.25 that the
// loader renormalises to 0.5 + 0.5. The skinned node's own translation (100 in x) is ignored.
Builder skinned_triangle(const std::vector<uint8_t>& joints) {
  Builder b;
  const int positions = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int normals = b.positions({0, 0, 1, 1, 0, 0, 0, 0, 1});
  const int joint_indices = b.accessor(b.view(joints), kUnsignedByte, 3, "VEC4");
  const int weights = b.accessor(
      b.view(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 0.25f, 0.25f, 0, 0}), kFloat, 3, "VEC4");
  // Column-major, as glTF stores matrices.
  const std::vector<float> identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<float> inverse_bind = identity;
  std::vector<float> shifted = identity;
  shifted[12] = -1.0f;
  inverse_bind.insert(inverse_bind.end(), shifted.begin(), shifted.end());
  const int matrices = b.accessor(b.view(inverse_bind), kFloat, 2, "MAT4");
  const int mesh = b.mesh({{"attributes",
                            {{"POSITION", positions},
                             {"NORMAL", normals},
                             {"JOINTS_0", joint_indices},
                             {"WEIGHTS_0", weights}}}});
  const int joint0 = b.node({{"name", "root joint"}});
  const double s = std::sqrt(0.5);
  const int joint1 = b.node({{"translation", {2, 0, 0}}, {"rotation", {0, 0, s, s}}});
  b.doc["skins"] = json::array({{{"joints", {joint0, joint1}}, {"inverseBindMatrices", matrices}}});
  b.node({{"mesh", mesh}, {"skin", 0}, {"translation", {100, 0, 0}}});
  return b;
}

TEST(GltfSkins, LinearBlendSkinningAtRest) {
  Builder b = skinned_triangle({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
  const SceneDescription s = load_gltf(b.write("skin.gltf"));
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].object_to_world, M44d());  // vertices already in world space
  const Primitive& p = s.meshes.at(0).primitives.at(0);
  // v0: joint 0 (identity). v1: (1,0,0) - (1,0,0) = 0, turned, moved to (2,0,0).
  // v2: joint 0 gives (0,1,0); joint 1: (-1,1,0) turned to (-1,-1,0), moved to (1,-1,0);
  // half of each: (0.5, 0, 0).
  expect_near(p.positions[0], V3f(0, 0, 0));
  expect_near(p.positions[1], V3f(2, 0, 0));
  expect_near(p.positions[2], V3f(0.5f, 0, 0));
  // Normals turn with their joints: +X under joint 1 becomes +Y.
  expect_near(p.normals[0], V3f(0, 0, 1));
  expect_near(p.normals[1], V3f(0, 1, 0));
  expect_near(p.normals[2], V3f(0, 0, 1));
}

TEST(GltfSkins, JointIndexOutOfRangeAndMissingWeightsAreErrors) {
  Builder b = skinned_triangle({0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0});
  std::string message = load_error(b.write("skin_bad_joint.gltf"));
  EXPECT_NE(message.find("accessors[2]: joint 2 of vertex 1 out of range (the skin has 2 joints)"),
            std::string::npos)
      << message;

  Builder no_weights = skinned_triangle({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
  no_weights.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  message = load_error(no_weights.write("skin_no_weights.gltf"));
  EXPECT_NE(message.find("meshes[0].primitives[0].attributes: JOINTS_0 without WEIGHTS_0"),
            std::string::npos)
      << message;

  Builder bad_skin = skinned_triangle({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
  bad_skin.doc["nodes"][2]["skin"] = 4;
  message = load_error(bad_skin.write("skin_out_of_range.gltf"));
  EXPECT_NE(message.find("nodes[2].skin: skin 4 out of range"), std::string::npos) << message;
}

TEST(GltfSkins, SimpleSkinAtRest) {
  // simple_skin stores a 1 x 2 strip (0 <= x <= 1, 0 <= y <= 2). Both joints rest at (0, 1, 0)
  // unrotated and both inverse bind matrices translate by (-0.5, -1, 0): every skin matrix is a
  // translation by -0.5 in x, so the rest pose is the strip centred on x = 0.
  const SceneDescription s = load_gltf(kSamples + "/simple_skin/simple_skin.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  Imath::Box3f box;
  for (const V3f& v : s.meshes[0].primitives.at(0).positions) box.extendBy(v);
  expect_near(box.min, V3f(-0.5f, 0, 0));
  expect_near(box.max, V3f(0.5f, 2, 0));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.at(0);
}

// ---------------------------------------------------------------------------------------------
// Scenes.

Builder two_scenes() {
  Builder b;
  const int mesh =
      b.mesh({{"attributes", {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}});
  b.doc["scenes"] =
      json::array({{{"name", "first"}, {"nodes", {0}}}, {{"name", "second"}, {"nodes", {1, 2}}}});
  b.doc["scene"] = 1;
  for (int i = 0; i < 3; ++i) b.node({{"mesh", mesh}}, false);
  return b;
}

TEST(GltfScenes, DefaultSceneAndSelectionByNameOrIndex) {
  const std::string path = two_scenes().write("two_scenes.gltf");
  EXPECT_EQ(load_gltf(path).instances.size(), 2u);  // "scene": 1
  const auto instances = [&](const std::string& scene) {
    LoadOptions options;
    options.scene = scene;
    return load_gltf(path, options).instances.size();
  };
  EXPECT_EQ(instances("first"), 1u);
  EXPECT_EQ(instances("0"), 1u);
  EXPECT_EQ(instances("second"), 2u);
  EXPECT_EQ(instances("1"), 2u);

  for (const std::string bad : {"2", "-1", "third", "99999999999999999999999999", " 0"}) {
    SCOPED_TRACE(bad);
    LoadOptions options;
    options.scene = bad;
    try {
      load_gltf(path, options);
      ADD_FAILURE() << "no error";
    } catch (const SceneSelectionError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("two_scenes.gltf: scenes: no scene '" + bad + "'"), std::string::npos)
          << message;
      EXPECT_NE(message.find("(the file has 2 scenes: 0 'first', 1 'second'; give a name or an "
                             "index from 0 to 1)"),
                std::string::npos)
          << message;
    }
  }
}

TEST(GltfScenes, WithoutSceneTheFirstIsLoaded) {
  Builder b = two_scenes();
  b.doc.erase("scene");
  EXPECT_EQ(load_gltf(b.write("two_scenes_no_default.gltf")).instances.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// KHR_materials_pbrSpecularGlossiness.

// The extension's own energy model: a dielectric reflects F0 = 0.04 and diffuses the rest.
float brightness(const C3f& c) {
  return std::sqrt(0.299f * c.x * c.x + 0.587f * c.y * c.y + 0.114f * c.z * c.z);
}

TEST(GltfSpecularGlossiness, ConversionOnKnownInputs) {
  using gltf_detail::to_metallic_roughness;
  // A dielectric with F0 = 0.04: metallic 0, base colour = diffuse exactly.
  auto mr = to_metallic_roughness(C3f(0.5f, 0.3f, 0.2f), C3f(0.04f), 0.75f);
  EXPECT_EQ(mr.metallic, 0.0f);
  EXPECT_NEAR(mr.base_colour.x, 0.5f, 1e-6f);
  EXPECT_NEAR(mr.base_colour.y, 0.3f, 1e-6f);
  EXPECT_NEAR(mr.base_colour.z, 0.2f, 1e-6f);
  EXPECT_FLOAT_EQ(mr.roughness, 0.25f);
  // Specular below a dielectric's: still metallic 0.
  EXPECT_EQ(to_metallic_roughness(C3f(0.8f), C3f(0.01f), 1.0f).metallic, 0.0f);
  // A pure metal: black diffuse, white specular -> metallic 1, base colour white.
  mr = to_metallic_roughness(C3f(0.0f), C3f(1.0f), 0.2f);
  EXPECT_NEAR(mr.metallic, 1.0f, 1e-6f);
  EXPECT_NEAR(mr.base_colour.x, 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(mr.roughness, 0.8f);
  // Grey in between: the converted material must reflect the same specular F0 and diffuse the
  // same energy, F0 = 0.04 (1 - m) + base m = specular and base (1 - 0.04)(1 - m) =
  // diffuse (1 - specular): the quadratic makes both hold at once. Float rounding: 1e-5.
  for (const auto& [d, sp] :
       {std::pair{0.6f, 0.2f}, {1.0f, 0.2f}, {0.3f, 0.5f}, {0.05f, 0.9f}, {0.5f, 0.3f}}) {
    SCOPED_TRACE(std::to_string(d) + " " + std::to_string(sp));
    mr = to_metallic_roughness(C3f(d), C3f(sp), 0.5f);
    const float m = mr.metallic;
    const float base = mr.base_colour.x;
    EXPECT_GT(m, 0.0f);
    EXPECT_LT(m, 1.0f);
    EXPECT_NEAR(0.04f * (1 - m) + base * m, sp, 1e-5f);
    EXPECT_NEAR(base * 0.96f * (1 - m), d * (1 - sp), 1e-5f);
    EXPECT_NEAR(brightness(C3f(0.04f * (1 - m)) + mr.base_colour * m), brightness(C3f(sp)), 1e-5f);
  }
}

TEST(GltfSpecularGlossiness, BoxTexturedSpecularGlossinessMaterial) {
  const SceneDescription s =
      load_gltf(kSamples + "/BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf");
  ASSERT_EQ(s.materials.size(), 1u);
  const MaterialDescription& m = s.materials[0];
  // diffuse (1, 1, 1) x texture, specular 0.2, glossiness 1 (see the test above for the rule):
  // the quadratic 0.04 m^2 + (0.8 / 0.96 + 0.2 - 0.08) m - 0.16 = 0 has the root m = 1/6.
  EXPECT_NEAR(m.metallic, 1.0f / 6.0f, 1e-6f);
  EXPECT_EQ(m.roughness, 0.0f);
  EXPECT_NEAR(m.base_colour.x, 1.0f, 1e-5f);
  EXPECT_EQ(m.base_colour_texture, 0);  // the diffuse texture
  EXPECT_EQ(s.textures.at(0).encoding, TextureEncoding::srgb);
}

// ---------------------------------------------------------------------------------------------
// KHR_draco_mesh_compression.

std::size_t triangles(const SceneDescription& s) {
  std::size_t n = 0;
  for (const MeshInstance& i : s.instances) {
    for (const Primitive& p : s.meshes.at(std::size_t(i.mesh)).primitives)
      n += p.indices.size() / 3;
  }
  return n;
}

Imath::Box3f bounds(const Mesh& mesh) {
  Imath::Box3f box;
  for (const Primitive& p : mesh.primitives) {
    for (const V3f& v : p.positions) box.extendBy(v);
  }
  return box;
}

TEST(GltfDraco, TwoCylinderEngineMatchesTheUncompressedFile) {
  const SceneDescription draco = load_gltf(kSamples + "/draco/2CylinderEngine.gltf");
  const SceneDescription plain =
      load_gltf(kSamples + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  ASSERT_EQ(draco.meshes.size(), plain.meshes.size());
  ASSERT_EQ(draco.instances.size(), plain.instances.size());
  // The encoder left out the uncompressed file's degenerate triangles (repeated index or zero
  // area): what remains is exactly what the renderer keeps of the .glb.
  EXPECT_EQ(triangles(plain), 121496u);
  EXPECT_EQ(triangles(draco), 110336u);
  EXPECT_EQ(EmbreeScene(plain, GeometryOptions{}).statistics().triangles, triangles(draco));
  for (std::size_t m = 0; m < plain.meshes.size(); ++m) {
    SCOPED_TRACE(m);
    ASSERT_EQ(draco.meshes[m].primitives.size(), plain.meshes[m].primitives.size());
    // Draco quantises positions to a grid over each mesh's bounding box; the bounds agree to
    // a small fraction of the mesh's size (the file's encoder setting is not recorded, so the
    // tolerance is 2^-10 of the extent: 10 bits, coarser than any encoder default).
    const Imath::Box3f a = bounds(draco.meshes[m]);
    const Imath::Box3f b = bounds(plain.meshes[m]);
    const float tolerance = b.size().length() / 1024.0f;
    expect_near(a.min, b.min, tolerance);
    expect_near(a.max, b.max, tolerance);
  }
}

TEST(GltfDraco, CorruptStreamIsAOneLineError) {
  const fs::path dir = test::scratch_dir("gltf_structure_test") / "draco";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(kSamples + "/draco/2CylinderEngine.gltf", dir / "2CylinderEngine.gltf");
  fs::copy_file(kSamples + "/draco/2CylinderEngine.bin", dir / "2CylinderEngine.bin");
  // Overwrite the first compressed stream (bufferView 0 holds meshes[0]'s) with garbage.
  const json doc = json::parse(std::ifstream(dir / "2CylinderEngine.gltf"));
  const int view =
      doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"];
  const std::size_t offset = doc["bufferViews"][view].value("byteOffset", std::size_t{0});
  {
    std::fstream bin(dir / "2CylinderEngine.bin", std::ios::in | std::ios::out | std::ios::binary);
    bin.seekp(std::streamoff(offset));
    const std::string garbage(16, '\x7f');
    bin.write(garbage.data(), std::streamsize(garbage.size()));
  }
  const std::string message = load_error((dir / "2CylinderEngine.gltf").string());
  EXPECT_NE(message.find("meshes[0].primitives[0].extensions.KHR_draco_mesh_compression: Draco "
                         "cannot decode it"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace prism
