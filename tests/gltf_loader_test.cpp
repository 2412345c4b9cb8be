// Tests of scene_io/gltf_loader against the glTF samples Debian ships with assimp, and against
// small glTFs written here to pin down one rule each.
#include "scene_io/gltf_loader.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <OpenImageIO/strutil.h>
#include <nlohmann/json.hpp>

#include "tests/gltf_test_builder.h"
#include "tests/scratch_dir.h"

#ifndef PRISM_ASSIMP_GLTF2_DIR
#define PRISM_ASSIMP_GLTF2_DIR "/usr/share/assimp/models/glTF2"
#endif

namespace prism {
namespace {

using nlohmann::json;

const std::string kSamples = PRISM_ASSIMP_GLTF2_DIR;

std::size_t triangle_count(const Mesh& mesh) {
  std::size_t n = 0;
  for (const Primitive& p : mesh.primitives) n += p.indices.size() / 3;
  return n;
}

std::size_t instanced_triangles(const SceneDescription& scene) {
  std::size_t n = 0;
  for (const MeshInstance& i : scene.instances) n += triangle_count(scene.meshes.at(i.mesh));
  return n;
}

// Runs load_gltf expecting a LoadError and returns its message.
std::string load_error(const std::string& path) {
  try {
    load_gltf(path);
  } catch (const LoadError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " loaded without error";
  return {};
}

void expect_one_line_error(const std::string& path, const std::string& file_name,
                           const std::string& element) {
  const std::string message = load_error(path);
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(file_name), std::string::npos) << message;
  EXPECT_NE(message.find(element), std::string::npos) << message;
}

bool has_warning(const SceneDescription& scene, const std::string& text) {
  for (const std::string& w : scene.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// The shipped samples.

TEST(GltfLoaderSamples, BoxTexturedIsTheSameInAllThreeForms) {
  const std::vector<std::string> paths = {kSamples + "/BoxTextured-glTF/BoxTextured.gltf",
                                          kSamples + "/BoxTextured-glTF-Binary/BoxTextured.glb",
                                          kSamples + "/BoxTextured-glTF-Embedded/BoxTextured.gltf"};
  std::vector<SceneDescription> scenes;
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    SceneDescription s = load_gltf(path);
    EXPECT_EQ(s.source_path, path);
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.instances.size(), 1u);
    ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
    const Primitive& p = s.meshes[0].primitives[0];
    EXPECT_EQ(p.indices.size(), 36u);
    EXPECT_EQ(p.positions.size(), 24u);
    EXPECT_EQ(p.normals.size(), 24u);
    EXPECT_EQ(p.uv0.size(), 24u);
    EXPECT_EQ(p.material, 0);
    for (const V3f& n : p.normals) EXPECT_NEAR(n.length(), 1.0f, 1e-5f);
    // The root node's matrix turns +Y into -Z (a Z-up to Y-up conversion).
    const M44d& m = s.instances[0].object_to_world;
    EXPECT_DOUBLE_EQ(m[1][2], -1.0);
    EXPECT_DOUBLE_EQ(m[2][1], 1.0);
    EXPECT_DOUBLE_EQ(m[0][0], 1.0);
    EXPECT_EQ(s.instances[0].node_name, "nodes[1]");

    ASSERT_EQ(s.materials.size(), 1u);
    const MaterialDescription& mat = s.materials[0];
    EXPECT_EQ(mat.name, "Texture");
    EXPECT_EQ(mat.base_colour, C3f(1.0f, 1.0f, 1.0f));
    EXPECT_FLOAT_EQ(mat.alpha, 1.0f);
    EXPECT_FLOAT_EQ(mat.metallic, 0.0f);
    EXPECT_FLOAT_EQ(mat.roughness, 1.0f);
    EXPECT_EQ(mat.base_colour_texture, 0);
    EXPECT_EQ(mat.metallic_roughness_texture, -1);
    EXPECT_FALSE(mat.double_sided);

    ASSERT_EQ(s.textures.size(), 1u);
    const TextureImage& t = s.textures[0];
    EXPECT_EQ(t.width, 211);
    EXPECT_EQ(t.height, 211);
    EXPECT_EQ(t.channels, 3);
    ASSERT_TRUE(t.shared_codes);  // an 8-bit PNG stays 8-bit
    EXPECT_EQ(t.value_count(), 211u * 211u * 3u);
    EXPECT_EQ(t.encoding, TextureEncoding::srgb);
    // Only the plain .gltf variant's sampler differs from glTF's default REPEAT.
    const bool plain = path == paths[0];
    EXPECT_EQ(t.wrap_s, plain ? TextureWrap::mirrored_repeat : TextureWrap::repeat);
    EXPECT_EQ(t.wrap_t, plain ? TextureWrap::clamp_to_edge : TextureWrap::repeat);
    scenes.push_back(std::move(s));
  }
  for (std::size_t i = 1; i < scenes.size(); ++i) {
    EXPECT_EQ(scenes[i].meshes[0].primitives[0].positions,
              scenes[0].meshes[0].primitives[0].positions);
    EXPECT_EQ(scenes[i].meshes[0].primitives[0].indices, scenes[0].meshes[0].primitives[0].indices);
    EXPECT_EQ(scenes[i].meshes[0].primitives[0].uv0, scenes[0].meshes[0].primitives[0].uv0);
    EXPECT_EQ(*scenes[i].textures[0].shared_codes, *scenes[0].textures[0].shared_codes);
  }
}

TEST(GltfLoaderSamples, TwoCylinderEngine) {
  const SceneDescription s =
      load_gltf(kSamples + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  EXPECT_EQ(s.meshes.size(), 29u);
  EXPECT_EQ(s.instances.size(), 67u);
  EXPECT_EQ(s.materials.size(), 34u);
  EXPECT_EQ(instanced_triangles(s), 121496u);
  std::size_t mesh_triangles = 0;
  for (const Mesh& m : s.meshes) mesh_triangles += triangle_count(m);
  EXPECT_EQ(mesh_triangles, 75730u);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].projection, Projection::perspective);
  EXPECT_NEAR(s.cameras[0].yfov, 0.3143463730812073, 1e-12);
  EXPECT_NEAR(s.cameras[0].camera_to_world[3][0], 1005.9874267578125, 1e-9);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfLoaderSamples, Cameras) {
  const SceneDescription s = load_gltf(kSamples + "/cameras/Cameras.gltf");
  ASSERT_EQ(s.cameras.size(), 2u);
  const CameraDescription& p = s.cameras[0];
  EXPECT_EQ(p.name, "cameras[0]");
  EXPECT_EQ(p.projection, Projection::perspective);
  EXPECT_DOUBLE_EQ(p.yfov, 0.7);
  EXPECT_DOUBLE_EQ(p.aspect_ratio, 1.0);
  EXPECT_DOUBLE_EQ(p.znear, 0.01);
  EXPECT_EQ(V3d(p.camera_to_world[3][0], p.camera_to_world[3][1], p.camera_to_world[3][2]),
            V3d(0.5, 0.5, 3.0));
  const CameraDescription& o = s.cameras[1];
  EXPECT_EQ(o.name, "cameras[1]");
  EXPECT_EQ(o.projection, Projection::orthographic);
  EXPECT_DOUBLE_EQ(o.xmag, 1.0);
  EXPECT_DOUBLE_EQ(o.ymag, 1.0);
  EXPECT_DOUBLE_EQ(o.znear, 0.01);
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(instanced_triangles(s), 2u);
}

TEST(GltfLoaderSamples, PrimitiveModes) {
  struct Case {
    int number;
    const char* skipped_mode;  // nullptr: two triangles expected
  };
  const Case cases[] = {{0, "POINTS"}, {1, "LINES"},     {2, "LINE_LOOP"},   {3, "LINE_STRIP"},
                        {4, nullptr},  {5, nullptr},     {6, nullptr},       {7, "POINTS"},
                        {8, "LINES"},  {9, "LINE_LOOP"}, {10, "LINE_STRIP"}, {11, nullptr},
                        {12, nullptr}, {13, nullptr},    {14, nullptr},      {15, nullptr}};
  for (const Case& c : cases) {
    char name[64];
    std::snprintf(name, sizeof name, "Mesh_PrimitiveMode_%02d.gltf", c.number);
    SCOPED_TRACE(name);
    const SceneDescription s =
        load_gltf(kSamples + "/glTF-Asset-Generator/Mesh_PrimitiveMode/" + name);
    if (c.skipped_mode) {
      EXPECT_TRUE(s.instances.empty());
      EXPECT_TRUE(s.meshes.empty());
      EXPECT_TRUE(has_warning(s, std::string("meshes[0].primitives[0]: mode ") + c.skipped_mode))
          << (s.warnings.empty() ? "no warning" : s.warnings[0]);
    } else {
      ASSERT_EQ(s.instances.size(), 1u);
      EXPECT_EQ(instanced_triangles(s), 2u);
      EXPECT_TRUE(s.warnings.empty());
    }
  }
  // The indexed strip [0 3 1 2] and fan [0 3 2 1] with glTF's winding rules.
  const SceneDescription strip =
      load_gltf(kSamples + "/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf");
  EXPECT_EQ(strip.meshes.at(0).primitives.at(0).indices, (std::vector<uint32_t>{0, 3, 1, 3, 2, 1}));
  const SceneDescription fan =
      load_gltf(kSamples + "/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf");
  EXPECT_EQ(fan.meshes.at(0).primitives.at(0).indices, (std::vector<uint32_t>{3, 2, 0, 2, 1, 0}));
}

TEST(GltfLoaderSamples, BrokenFilesFailWithOneLineNamingFileAndElement) {
  struct Case {
    const char* path;
    const char* file_name;
    const char* element;
  };
  const Case cases[] = {
      {"IndexOutOfRange/IndexOutOfRange.gltf", "IndexOutOfRange.gltf",
       "meshes[0].primitives[0].indices: index 255"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "AllIndicesOutOfRange.gltf",
       "meshes[0].primitives[0].indices: index 65535"},
      {"MissingBin/BoxTextured.gltf", "BoxTextured.gltf", "buffers[0].uri"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "BoxWithInfinites.glb",
       "accessors[2]: vertex 0 position is not finite"},
      {"RecursiveNodes/RecursiveNodes.gltf", "RecursiveNodes.gltf", "nodes[0]: "},
      {"SchemaFailures/sceneWrongType.gltf", "sceneWrongType.gltf", "scene: "},
      {"wrongTypes/badArray.gltf", "badArray.gltf", "meshes[0].primitives: expected an array"},
      {"wrongTypes/badExtension.gltf", "badExtension.gltf",
       "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform"},
      {"wrongTypes/badNumber.gltf", "badNumber.gltf", "materials[0].normalTexture"},
      {"wrongTypes/badObject.gltf", "badObject.gltf",
       "materials[0].pbrMetallicRoughness: expected an object"},
      {"wrongTypes/badString.gltf", "badString.gltf", "scenes[0].name: expected a string"},
      {"wrongTypes/badUint.gltf", "badUint.gltf",
       "materials[0].pbrMetallicRoughness.baseColorTexture.index"},
      {"IncorrectVertexArrays/Cube.gltf", "Cube.gltf", "meshes[1].primitives[0]: 35 vertices"},
      {"TestNoRootNode/NoScene.gltf", "NoScene.gltf", "scene: "},
      {"does-not-exist.gltf", "does-not-exist.gltf", "file: "},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.path);
    expect_one_line_error(kSamples + "/" + c.path, c.file_name, c.element);
  }
}

TEST(GltfLoaderSamples, SceneWithoutNodesLoadsEmptyWithAWarning) {
  const SceneDescription s = load_gltf(kSamples + "/TestNoRootNode/SceneWithoutNodes.gltf");
  EXPECT_TRUE(s.instances.empty());
  EXPECT_TRUE(s.meshes.empty());
  EXPECT_TRUE(has_warning(s, "scenes[0]: the scene has no nodes"));
}

TEST(GltfLoaderSamples, ZeroNormalsAreDroppedWithAWarning) {
  const SceneDescription s = load_gltf(kSamples + "/BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].primitives.at(0).normals.empty());
  EXPECT_EQ(s.meshes[0].primitives[0].positions.size(), 24u);
  EXPECT_TRUE(has_warning(s, "normal"));
}

// ---------------------------------------------------------------------------------------------
// Hand-made files.

using test::base64;
using test::Builder;

TEST(GltfLoaderHandMade, IndexComponentTypesAndNonIndexed) {
  Builder b;
  const int pos = b.quad_positions();
  const std::vector<uint32_t> expected = {0, 1, 2, 0, 2, 3};
  const int u8 = b.accessor(b.view(std::vector<uint8_t>{0, 1, 2, 0, 2, 3}), 5121, 6, "SCALAR");
  const int u16 = b.accessor(b.view(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), 5123, 6, "SCALAR");
  const int u32 = b.accessor(b.view(std::vector<uint32_t>{0, 1, 2, 0, 2, 3}), 5125, 6, "SCALAR");
  const int six = b.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1});
  for (int indices : {u8, u16, u32}) {
    b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", indices}})}});
  }
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", six}}}})}});
  const SceneDescription s = load_gltf(b.write("indices.gltf"));
  ASSERT_EQ(s.instances.size(), 4u);
  ASSERT_EQ(s.meshes.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const Primitive& p = s.meshes[std::size_t(i)].primitives.at(0);
    EXPECT_EQ(p.indices, expected) << "mesh " << i;
    EXPECT_EQ(p.positions.size(), 4u);
    EXPECT_EQ(p.positions[2], V3f(1, 1, 0));
    EXPECT_TRUE(p.normals.empty());
    EXPECT_EQ(p.material, -1);
  }
  EXPECT_EQ(s.meshes[3].primitives.at(0).indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(s.meshes[3].primitives[0].positions[5], V3f(1, 1, 1));
}

TEST(GltfLoaderHandMade, StripAndFanWinding) {
  Builder b;
  const int pos = b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0});
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}, {"mode", 5}})}});
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}, {"mode", 6}})}});
  const SceneDescription s = load_gltf(b.write("winding.gltf"));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].primitives.at(0).indices,
            (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
  EXPECT_EQ(s.meshes[1].primitives.at(0).indices,
            (std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
  // Every strip triangle of this zig-zag faces +Z, i.e. is counter-clockwise seen from +Z.
  const Primitive& strip = s.meshes[0].primitives[0];
  for (std::size_t t = 0; t < strip.indices.size(); t += 3) {
    const V3f& a = strip.positions[strip.indices[t]];
    const V3f& b1 = strip.positions[strip.indices[t + 1]];
    const V3f& c = strip.positions[strip.indices[t + 2]];
    EXPECT_GT((b1 - a).cross(c - a).z, 0.0f) << "triangle " << t / 3;
  }
}

TEST(GltfLoaderHandMade, NestedTrsAndMatrixTransforms) {
  Builder b;
  const int mesh = b.mesh({{"attributes", {{"POSITION", b.quad_positions()}}}, {"mode", 6}});
  // parent: translate (1,2,3); child: rotate 90 degrees about +Z then scale 2 (TRS);
  // grandchild: matrix translating by (1,0,0).
  const double h = std::sqrt(0.5);
  const int grandchild = b.node({{"name", "grandchild"},
                                 {"mesh", mesh},
                                 {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}},
                                false);
  const int child = b.node({{"children", {grandchild}},
                            {"rotation", {0, 0, h, h}},
                            {"scale", {2, 2, 2}},
                            {"mesh", mesh}},
                           false);
  b.node({{"name", "parent"}, {"translation", {1, 2, 3}}, {"children", {child}}});
  const SceneDescription s = load_gltf(b.write("transforms.gltf"));
  ASSERT_EQ(s.instances.size(), 2u);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.instances[0].node_name, "nodes[1]");
  EXPECT_EQ(s.instances[1].node_name, "grandchild");
  EXPECT_EQ(s.instances[0].mesh, 0);
  EXPECT_EQ(s.instances[1].mesh, 0);
  // child: p -> R(p) * 2 + (1,2,3); R maps +X to +Y.
  const V3d x = V3d(1, 0, 0) * s.instances[0].object_to_world;
  EXPECT_NEAR((x - V3d(1, 4, 3)).length(), 0.0, 1e-12);
  // grandchild: p + (1,0,0) first, then the child's transform.
  const V3d origin = V3d(0, 0, 0) * s.instances[1].object_to_world;
  EXPECT_NEAR((origin - V3d(1, 4, 3)).length(), 0.0, 1e-12);
  const V3d y = V3d(0, 1, 0) * s.instances[1].object_to_world;
  EXPECT_NEAR((y - V3d(-1, 4, 3)).length(), 0.0, 1e-12);
}

TEST(GltfLoaderHandMade, Spheres) {
  Builder b;
  b.doc["materials"] = json::array({{{"name", "a"}}, {{"name", "b"}}});
  const int fallback =
      b.mesh({{"attributes", {{"POSITION", b.quad_positions()}}}, {"material", 1}});
  const int sphere = b.node({{"name", "ball"},
                             {"translation", {0, 1, 0}},
                             {"mesh", fallback},
                             {"extensions", {{"PRISM_sphere", {{"radius", 0.5}}}}}},
                            false);
  b.node({{"translation", {1, 0, 0}}, {"scale", {3, 3, 3}}, {"children", {sphere}}});
  b.node({{"extensions", {{"PRISM_sphere", {{"radius", 2}, {"material", 0}}}}}});
  b.doc["extensionsUsed"] = {"PRISM_sphere"};
  const SceneDescription s = load_gltf(b.write("spheres.gltf"));
  EXPECT_TRUE(s.instances.empty()) << "the fallback mesh must not be rendered";
  ASSERT_EQ(s.spheres.size(), 2u);
  EXPECT_EQ(s.spheres[0].node_name, "ball");
  EXPECT_NEAR((s.spheres[0].centre - V3d(1, 3, 0)).length(), 0.0, 1e-12);
  EXPECT_NEAR(s.spheres[0].radius, 1.5, 1e-12);
  EXPECT_EQ(s.spheres[0].material, 1);  // from the fallback mesh's first primitive
  EXPECT_EQ(s.spheres[1].node_name, "nodes[2]");
  EXPECT_DOUBLE_EQ(s.spheres[1].radius, 2.0);
  EXPECT_EQ(s.spheres[1].material, 0);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfLoaderHandMade, SphereRejectsNonUniformScaleAndBadRadius) {
  {
    Builder b;
    b.node({{"name", "squashed"},
            {"scale", {1, 2, 1}},
            {"extensions", {{"PRISM_sphere", {{"radius", 1}}}}}});
    const std::string message = load_error(b.write("squashed.gltf"));
    EXPECT_NE(message.find("squashed.gltf: nodes[0]: PRISM_sphere needs a uniform world scale"),
              std::string::npos)
        << message;
  }
  {
    Builder b;
    b.node({{"extensions", {{"PRISM_sphere", {{"radius", -1}}}}}});
    expect_one_line_error(b.write("negative_radius.gltf"), "negative_radius.gltf",
                          "nodes[0].extensions.PRISM_sphere.radius");
  }
  {
    Builder b;
    b.node({{"extensions", {{"PRISM_sphere", {{"radius", 1}, {"material", 3}}}}}});
    expect_one_line_error(b.write("sphere_material.gltf"), "sphere_material.gltf",
                          "nodes[0].extensions.PRISM_sphere.material: material 3 out of range");
  }
}

TEST(GltfLoaderHandMade, PunctualLights) {
  Builder b;
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
      {{{"name", "sun"}, {"type", "directional"}, {"color", {1, 0.5, 0.25}}, {"intensity", 3}},
       {{"type", "spot"},
        {"intensity", 40},
        {"range", 10},
        {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}},
       {{"type", "point"}}});
  const double h = std::sqrt(0.5);
  // Rotating -90 degrees about X turns the light's -Z into -Y: straight down.
  b.node({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.node({{"translation", {0, 5, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  const SceneDescription s = load_gltf(b.write("lights.gltf"));
  ASSERT_EQ(s.lights.size(), 3u);
  const Light& sun = s.lights[0];
  EXPECT_EQ(sun.name, "sun");
  EXPECT_EQ(sun.type, LightType::directional);
  EXPECT_EQ(sun.colour, C3f(1.0f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(sun.intensity, 3.0f);
  EXPECT_NEAR((sun.direction - V3d(0, -1, 0)).length(), 0.0, 1e-12);
  const Light& spot = s.lights[1];
  EXPECT_EQ(spot.type, LightType::spot);
  EXPECT_FLOAT_EQ(spot.intensity, 40.0f);
  EXPECT_DOUBLE_EQ(spot.range, 10.0);
  EXPECT_DOUBLE_EQ(spot.inner_cone_angle, 0.1);
  EXPECT_DOUBLE_EQ(spot.outer_cone_angle, 0.5);
  EXPECT_EQ(spot.position, V3d(1, 2, 3));
  EXPECT_NEAR((spot.direction - V3d(0, 0, -1)).length(), 0.0, 1e-12);
  const Light& point = s.lights[2];
  EXPECT_EQ(point.type, LightType::point);
  EXPECT_EQ(point.position, V3d(0, 5, 0));
  EXPECT_FLOAT_EQ(point.intensity, 1.0f);
  EXPECT_DOUBLE_EQ(point.range, 0.0);
  EXPECT_EQ(point.colour, C3f(1.0f, 1.0f, 1.0f));
}

TEST(GltfLoaderHandMade, MaterialExtensions) {
  Builder b;
  b.doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior",
                             "KHR_materials_volume",       "KHR_materials_emissive_strength",
                             "KHR_materials_iridescence",  "KHR_materials_clearcoat",
                             "KHR_materials_sheen"};
  b.doc["extensionsRequired"] = {"KHR_materials_transmission"};
  b.doc["materials"] = json::array(
      {{{"name", "glass"},
        {"doubleSided", true},
        {"pbrMetallicRoughness",
         {{"baseColorFactor", {0.9, 0.8, 0.7, 0.5}},
          {"metallicFactor", 0.25},
          {"roughnessFactor", 0.125}}},
        {"emissiveFactor", {0.5, 0.25, 1}},
        {"extensions",
         {{"KHR_materials_transmission", {{"transmissionFactor", 0.75}}},
          {"KHR_materials_ior", {{"ior", 1.33}}},
          {"KHR_materials_volume",
           {{"thicknessFactor", 0.5},
            {"attenuationDistance", 2.0},
            {"attenuationColor", {0.5, 0.25, 1.0}}}},
          {"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}},
          {"KHR_materials_specular",
           {{"specularFactor", 0.5}, {"specularColorFactor", {2.0, 1.0, 0.0}}}},
          {"KHR_materials_clearcoat",
           {{"clearcoatFactor", 0.75}, {"clearcoatRoughnessFactor", 0.25}}},
          {"KHR_materials_sheen",
           {{"sheenColorFactor", {0.5, 0.25, 1.0}}, {"sheenRoughnessFactor", 0.625}}}}}},
       json::object(),
       {{"extensions", {{"KHR_materials_unlit", json::object()}}}}});
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", b.quad_positions()}}},
                           {"indices",
                            b.accessor(b.view(std::vector<uint16_t>{0, 1, 2}), 5123, 3, "SCALAR")},
                           {"material", 0}})}});
  const SceneDescription s = load_gltf(b.write("materials.gltf"));
  ASSERT_EQ(s.materials.size(), 3u);
  const MaterialDescription& m = s.materials[0];
  EXPECT_EQ(m.name, "glass");
  EXPECT_FALSE(m.unlit);
  EXPECT_TRUE(s.materials[2].unlit);
  EXPECT_TRUE(m.double_sided);
  EXPECT_NEAR(m.base_colour.x, 0.9f, 1e-6f);
  EXPECT_NEAR(m.base_colour.z, 0.7f, 1e-6f);
  EXPECT_FLOAT_EQ(m.alpha, 0.5f);
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.125f);
  EXPECT_EQ(m.emissive, C3f(2.0f, 1.0f, 4.0f));
  EXPECT_FLOAT_EQ(m.transmission, 0.75f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.thickness, 0.5f);
  EXPECT_FLOAT_EQ(m.attenuation_distance, 2.0f);
  EXPECT_EQ(m.attenuation_colour, C3f(0.5f, 0.25f, 1.0f));
  EXPECT_FLOAT_EQ(m.specular, 0.5f);
  EXPECT_EQ(m.specular_colour, C3f(2.0f, 1.0f, 0.0f));  // above 1 is allowed by the extension
  EXPECT_FLOAT_EQ(m.clearcoat, 0.75f);
  EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.25f);
  EXPECT_EQ(m.clearcoat_texture, -1);
  EXPECT_EQ(m.clearcoat_normal_texture, -1);
  EXPECT_EQ(m.sheen_colour, C3f(0.5f, 0.25f, 1.0f));
  EXPECT_FLOAT_EQ(m.sheen_roughness, 0.625f);
  EXPECT_EQ(m.sheen_colour_texture, -1);
  EXPECT_EQ(m.sheen_roughness_texture, -1);
  // glTF's defaults.
  const MaterialDescription& d = s.materials[1];
  EXPECT_EQ(d.name, "materials[1]");
  EXPECT_FLOAT_EQ(d.metallic, 1.0f);
  EXPECT_FLOAT_EQ(d.roughness, 1.0f);
  EXPECT_FLOAT_EQ(d.ior, 1.5f);
  EXPECT_FLOAT_EQ(d.transmission, 0.0f);
  EXPECT_FLOAT_EQ(d.thickness, 0.0f);  // thin-walled
  EXPECT_EQ(d.attenuation_distance, std::numeric_limits<float>::infinity());
  EXPECT_EQ(d.attenuation_colour, C3f(1.0f, 1.0f, 1.0f));
  EXPECT_EQ(d.emissive, C3f(0.0f, 0.0f, 0.0f));
  EXPECT_FALSE(d.double_sided);
  EXPECT_FLOAT_EQ(d.specular, 1.0f);
  EXPECT_EQ(d.specular_colour, C3f(1.0f, 1.0f, 1.0f));
  EXPECT_FLOAT_EQ(d.clearcoat, 0.0f);
  EXPECT_FLOAT_EQ(d.clearcoat_roughness, 0.0f);
  EXPECT_EQ(d.sheen_colour, C3f(0.0f, 0.0f, 0.0f));
  EXPECT_FLOAT_EQ(d.sheen_roughness, 0.0f);
  EXPECT_EQ(s.meshes.at(0).primitives.at(0).material, 0);
  EXPECT_TRUE(has_warning(s, "extensionsUsed: extension \"KHR_materials_iridescence\""));
  // Supported now: no warning.
  EXPECT_FALSE(has_warning(s, "extensionsUsed: extension \"KHR_materials_sheen\""));
  EXPECT_FALSE(has_warning(s, "extensionsUsed: extension \"KHR_materials_clearcoat\""));
  EXPECT_FALSE(has_warning(s, "KHR_materials_volume"));
}

TEST(GltfLoaderHandMade, TexturesPerEncodingAndNormalisedTexcoords) {
  // A 2x1 RGB PNG would need an encoder; instead reuse the sample's PNG through a relative uri.
  Builder b;
  const std::filesystem::path dir = test::scratch_dir("gltf_loader_test");
  std::filesystem::copy_file(kSamples + "/BoxTextured-glTF/CesiumLogoFlat.png",
                             dir / "logo with space.png",
                             std::filesystem::copy_options::overwrite_existing);
  b.doc["images"] = json::array({{{"uri", "logo%20with%20space.png"}}});
  b.doc["samplers"] = json::array({{{"wrapS", 33071}}});
  b.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  b.doc["materials"] = json::array(
      {{{"pbrMetallicRoughness",
         {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}},
        {"emissiveTexture", {{"index", 0}}},
        {"extensions",
         {{"KHR_materials_clearcoat",
           {{"clearcoatFactor", 1},
            {"clearcoatTexture", {{"index", 0}}},
            {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}},
          {"KHR_materials_sheen",
           {{"sheenColorTexture", {{"index", 0}}},
            {"sheenRoughnessTexture", {{"index", 0}, {"texCoord", 1}}}}}}}}});
  const int uv = b.accessor(b.view(std::vector<uint16_t>{0, 0, 65535, 0, 65535, 65535, 0, 65535}),
                            5123, 4, "VEC2", true);
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", b.quad_positions()}, {"TEXCOORD_0", uv}}},
                           {"mode", 6},
                           {"material", 0}})}});
  const SceneDescription s = load_gltf(b.write("textures.gltf"));
  ASSERT_EQ(s.textures.size(), 2u);
  const MaterialDescription& m = s.materials.at(0);
  EXPECT_EQ(m.base_colour_texture, m.emissive_texture);
  EXPECT_NE(m.base_colour_texture, m.metallic_roughness_texture);
  EXPECT_EQ(s.textures.at(std::size_t(m.base_colour_texture)).encoding, TextureEncoding::srgb);
  EXPECT_EQ(s.textures.at(std::size_t(m.metallic_roughness_texture)).encoding,
            TextureEncoding::linear_data);
  EXPECT_EQ(s.textures[0].shared_codes, s.textures[1].shared_codes);
  // The layers' colour is sRGB, their weights, roughnesses and normals data.
  EXPECT_EQ(m.sheen_colour_texture, m.base_colour_texture);
  EXPECT_EQ(m.sheen_roughness_texture, m.metallic_roughness_texture);
  EXPECT_EQ(m.sheen_roughness_mapping.texcoord, 1);
  EXPECT_EQ(m.clearcoat_texture, m.metallic_roughness_texture);
  EXPECT_EQ(m.clearcoat_normal_texture, m.metallic_roughness_texture);
  EXPECT_FLOAT_EQ(m.clearcoat_normal_scale, 0.5f);
  EXPECT_EQ(s.textures[0].wrap_s, TextureWrap::clamp_to_edge);
  EXPECT_EQ(s.textures[0].wrap_t, TextureWrap::repeat);
  const Primitive& p = s.meshes.at(0).primitives.at(0);
  EXPECT_EQ(p.uv0, (std::vector<V2f>{V2f(0, 0), V2f(1, 0), V2f(1, 1), V2f(0, 1)}));
}

TEST(GltfLoaderHandMade, AccessorPastItsBufferView) {
  Builder b;
  const int v = b.view(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0});
  const int pos = b.accessor(v, 5126, 4, "VEC3");  // 4 vertices in a view holding 3
  b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}})}});
  const std::string message = load_error(b.write("past_view.gltf"));
  EXPECT_NE(message.find("past_view.gltf: accessors[0]: "), std::string::npos) << message;
  EXPECT_NE(message.find("bufferViews[0]"), std::string::npos) << message;
}

TEST(GltfLoaderHandMade, ValidationErrorsNameTheElement) {
  struct Case {
    const char* name;
    void (*edit)(Builder&);
    const char* element;
  };
  const Case cases[] = {
      {"normals_count.gltf",
       [](Builder& b) {
         const int n = b.positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
         b.node({{"mesh",
                  b.mesh({{"attributes", {{"POSITION", b.quad_positions()}, {"NORMAL", n}}}})}});
       },
       "meshes[0].primitives[0].attributes.NORMAL: NORMAL has 3 elements but POSITION has 4"},
      {"uv_type.gltf",
       [](Builder& b) {
         const int uv = b.accessor(b.view(std::vector<uint8_t>{0, 0, 1, 1, 2, 2, 3, 3}), 5121, 4,
                                   "VEC2");  // not normalized
         b.node({{"mesh", b.mesh({{"attributes",
                                   {{"POSITION", b.quad_positions()}, {"TEXCOORD_0", uv}}}})}});
       },
       "accessors[0]: TEXCOORD_0 must be"},
      {"int_positions.gltf",
       [](Builder& b) {
         const int pos =
             b.accessor(b.view(std::vector<uint16_t>{0, 0, 0, 1, 1, 1, 2, 2, 2}), 5123, 3, "VEC3");
         b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", pos}}}})}});
       },
       "accessors[0]: POSITION must have componentType FLOAT"},
      {"bad_accessor_index.gltf",
       [](Builder& b) {
         b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", 7}}}})}});
       },
       "meshes[0].primitives[0].attributes.POSITION: accessor 7 out of range"},
      {"bad_mesh_index.gltf",
       [](Builder& b) {
         b.node({{"mesh", 3}});
       },
       "nodes[0].mesh: mesh 3 out of range"},
      {"no_position.gltf",
       [](Builder& b) {
         b.node({{"mesh", b.mesh({{"attributes", json::object()}})}});
       },
       "meshes[0].primitives[0].attributes: POSITION is missing"},
      {"cycle.gltf",
       [](Builder& b) {
         b.node({{"name", "a"}, {"children", {0}}});
       },
       "nodes[0]: the node hierarchy has a cycle"},
      {"two_parents.gltf",
       [](Builder& b) {
         b.node({{"children", {2}}});
         b.node({{"children", {2}}});
         b.node(json::object(), false);
       },
       "nodes[2]: node has more than one parent"},
      {"required.gltf",
       [](Builder& b) { b.doc["extensionsRequired"] = {"EXT_meshopt_compression"}; },
       "extensionsRequired: extension \"EXT_meshopt_compression\""},
      {"malformed.gltf", [](Builder& b) { b.doc["asset"] = "x"; }, "asset: expected an object"},
      {"nan_in_matrix.gltf",
       [](Builder& b) {
         b.node({{"scale", {1e300, 1, 1}}, {"children", {1}}});
         b.node({{"scale", {1e300, 1, 1}}}, false);
       },
       "nodes[0]: world transform is not finite as a float"},
      {"metallic_range.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"metallicFactor", 2}}}}});
       },
       "materials[0].pbrMetallicRoughness.metallicFactor"},
      {"bad_specular_colour.gltf",
       [](Builder& b) {
         b.node({{"mesh", b.mesh({{"attributes", {{"POSITION", b.quad_positions()}}}})}});
         b.doc["materials"] =
             json::array({{{"extensions",
                            {{"KHR_materials_specular", {{"specularColorFactor", {1, -1, 1}}}}}}}});
       },
       "materials[0].extensions.KHR_materials_specular.specularColorFactor[1]"},
      {"clearcoat_range.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.5}}}}}}});
       },
       "materials[0].extensions.KHR_materials_clearcoat.clearcoatFactor"},
      {"clearcoat_roughness_type.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions",
                {{"KHR_materials_clearcoat", {{"clearcoatRoughnessFactor", "smooth"}}}}}}});
       },
       "materials[0].extensions.KHR_materials_clearcoat.clearcoatRoughnessFactor"},
      {"clearcoat_texture_index.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions",
                {{"KHR_materials_clearcoat", {{"clearcoatTexture", {{"index", 7}}}}}}}}});
       },
       "materials[0].extensions.KHR_materials_clearcoat.clearcoatTexture.index"},
      {"clearcoat_normal_scale.gltf",
       [](Builder& b) {
         b.doc["materials"] =
             json::array({{{"extensions",
                            {{"KHR_materials_clearcoat",
                              {{"clearcoatNormalTexture", {{"index", 0}, {"scale", 1e300}}}}}}}}});
       },
       "materials[0].extensions.KHR_materials_clearcoat.clearcoatNormalTexture.scale"},
      {"sheen_colour_range.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions", {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 2, 1}}}}}}}});
       },
       "materials[0].extensions.KHR_materials_sheen.sheenColorFactor[1]"},
      {"sheen_colour_count.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions", {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1}}}}}}}});
       },
       "materials[0].extensions.KHR_materials_sheen.sheenColorFactor"},
      {"sheen_roughness_range.gltf",
       [](Builder& b) {
         b.doc["materials"] = json::array(
             {{{"extensions", {{"KHR_materials_sheen", {{"sheenRoughnessFactor", -0.5}}}}}}});
       },
       "materials[0].extensions.KHR_materials_sheen.sheenRoughnessFactor"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Builder b;
    c.edit(b);
    expect_one_line_error(b.write(c.name), c.name, c.element);
  }
}

TEST(GltfLoaderHandMade, MalformedJsonAndTruncatedGlb) {
  const auto dir = test::scratch_dir("gltf_loader_test");
  const std::string json_path = (dir / "broken.gltf").string();
  std::ofstream(json_path) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  expect_one_line_error(json_path, "broken.gltf", "JSON: ");

  // The real GLB cut in the middle of its binary chunk.
  std::ifstream in(kSamples + "/BoxTextured-glTF-Binary/BoxTextured.glb", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 2000u);
  const std::string glb_path = (dir / "truncated.glb").string();
  std::ofstream(glb_path, std::ios::binary).write(bytes.data(), 2000);
  expect_one_line_error(glb_path, "truncated.glb", "GLB header");
}

TEST(GltfLoaderHandMade, NoScenesRendersAllRootNodesWithAWarning) {
  Builder b;
  b.doc.erase("scene");
  b.doc.erase("scenes");
  const int mesh = b.mesh({{"attributes", {{"POSITION", b.quad_positions()}}}, {"mode", 6}});
  b.doc["nodes"] = json::array({{{"mesh", mesh}, {"children", {1}}},
                                {{"mesh", mesh}, {"translation", {0, 0, 1}}},
                                {{"mesh", mesh}, {"translation", {0, 0, 2}}}});
  const SceneDescription s = load_gltf(b.write("no_scenes.gltf"));
  ASSERT_EQ(s.instances.size(), 3u);
  EXPECT_EQ(s.instances[1].node_name, "nodes[1]");
  EXPECT_DOUBLE_EQ(s.instances[2].object_to_world[3][2], 2.0);
  EXPECT_TRUE(has_warning(s, "scenes: the file has no scenes"));
}

TEST(GltfLoaderHandMade, SharedCameraGivesOneDescriptionPerNodeInTraversalOrder) {
  Builder b;
  b.doc["cameras"] = json::array({{{"name", "cam"},
                                   {"type", "perspective"},
                                   {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}});
  const int inner = b.node({{"camera", 0}, {"translation", {0, 0, 7}}}, false);
  b.node({{"children", {inner}}});
  b.node({{"camera", 0}, {"translation", {0, 0, 9}}});
  const SceneDescription s = load_gltf(b.write("cameras.gltf"));
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.cameras[0].name, "cam");
  EXPECT_DOUBLE_EQ(s.cameras[0].camera_to_world[3][2], 7.0);
  EXPECT_DOUBLE_EQ(s.cameras[1].camera_to_world[3][2], 9.0);
  EXPECT_DOUBLE_EQ(s.cameras[1].aspect_ratio, 0.0);
  EXPECT_DOUBLE_EQ(s.cameras[1].yfov, 0.5);
}

}  // namespace
}  // namespace prism
