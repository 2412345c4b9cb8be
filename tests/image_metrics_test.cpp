// Error metrics against hand-computed values, the EXR reader, and rendering in passes.
#include "renderer/image/image_metrics.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrators/registry.h"
#include "tests/test_scenes.h"

namespace fs = std::filesystem;

namespace prism {
namespace {

void set(Image* image, int x, int y, float r, float g, float b, float a = 1.0f) {
  float* p = image->pixel(x, y);
  p[0] = r;
  p[1] = g;
  p[2] = b;
  p[3] = a;
}

// Values are powers of two, so the float inputs are exact and only the metrics' own
// arithmetic (in double) separates them from the formulas below.
TEST(ImageMetrics, TwoPixelsByHand) {
  Image a(2, 1), b(2, 1);
  set(&a, 0, 0, 0.5f, 0.25f, 1.0f);
  set(&b, 0, 0, 0.5f, 0.5f, 0.5f);
  set(&a, 1, 0, 0.0f, 0.0f, 0.0f);
  set(&b, 1, 0, 0.125f, 0.0f, 0.0f);
  const ImageError e = compare_images(a, b);
  EXPECT_EQ(e.compared_pixels, 2u);
  EXPECT_EQ(e.non_finite_a, 0u);
  EXPECT_EQ(e.non_finite_b, 0u);
  const double eps = kRelMseEpsilon;
  // Differences: pixel 0 (0, -0.25, 0.5); pixel 1 (-0.125, 0, 0).
  const ChannelError& r = e.channel[0];
  EXPECT_NEAR(r.rmse, std::sqrt(0.015625 / 2), 1e-12);
  EXPECT_NEAR(r.relmse, (0.0 + 0.015625 / (0.015625 + eps)) / 2, 1e-12);
  EXPECT_NEAR(r.psnr, 10.0 * std::log10(2 / 0.015625), 1e-9);
  EXPECT_EQ(r.max_abs, 0.125);
  EXPECT_EQ(r.max_x, 1);
  EXPECT_EQ(r.max_y, 0);
  const ChannelError& g = e.channel[1];
  EXPECT_NEAR(g.rmse, std::sqrt(0.0625 / 2), 1e-12);
  EXPECT_NEAR(g.relmse, (0.0625 / (0.25 + eps) + 0.0) / 2, 1e-12);
  EXPECT_EQ(g.max_abs, 0.25);
  EXPECT_EQ(g.max_x, 0);
  const ChannelError& bl = e.channel[2];
  EXPECT_NEAR(bl.rmse, std::sqrt(0.25 / 2), 1e-12);
  EXPECT_NEAR(bl.relmse, (0.25 / (0.25 + eps)) / 2, 1e-12);
  EXPECT_NEAR(bl.psnr, 10.0 * std::log10(2 / 0.25), 1e-9);
  // Overall: six channel samples.
  const double squared = 0.015625 + 0.0625 + 0.25;
  EXPECT_NEAR(e.overall.rmse, std::sqrt(squared / 6), 1e-12);
  EXPECT_NEAR(e.overall.relmse,
              (0.015625 / (0.015625 + eps) + 0.0625 / (0.25 + eps) + 0.25 / (0.25 + eps)) / 6,
              1e-12);
  EXPECT_NEAR(e.overall.psnr, 10.0 * std::log10(6 / squared), 1e-9);
  EXPECT_EQ(e.overall.max_abs, 0.5);
  EXPECT_EQ(e.overall.max_x, 0);
  EXPECT_EQ(e.overall.max_y, 0);
  EXPECT_EQ(e.max_channel, 2);
}

TEST(ImageMetrics, RelMseDividesByTheReferenceNotTheImage) {
  Image a(1, 1), b(1, 1);
  set(&a, 0, 0, 2.0f, 2.0f, 2.0f);
  set(&b, 0, 0, 0.0f, 0.0f, 0.0f);
  EXPECT_NEAR(compare_images(a, b).overall.relmse, 4.0 / kRelMseEpsilon, 1e-9);
  EXPECT_NEAR(compare_images(b, a).overall.relmse, 4.0 / (4.0 + kRelMseEpsilon), 1e-12);
}

TEST(ImageMetrics, IdenticalImagesHaveInfinitePsnr) {
  Image a(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) set(&a, x, y, 0.1f * x, 0.2f * y, 7.0f);
  const ImageError e = compare_images(a, a);
  EXPECT_EQ(e.overall.rmse, 0.0);
  EXPECT_EQ(e.overall.relmse, 0.0);
  EXPECT_EQ(e.overall.max_abs, 0.0);
  EXPECT_TRUE(std::isinf(e.overall.psnr) && e.overall.psnr > 0.0);
  // Nothing stands out, so the "maximum" is the first sample compared.
  EXPECT_EQ(e.overall.max_x, 0);
  EXPECT_EQ(e.overall.max_y, 0);
  EXPECT_EQ(e.max_channel, 0);
}

TEST(ImageMetrics, MaximumIsTheFirstInScanOrderOnTies) {
  Image a(3, 3), b(3, 3);
  set(&a, 2, 1, 0.0f, 0.75f, 0.0f);  // row 1 is scanned before row 2
  set(&a, 0, 2, 0.75f, 0.0f, 0.0f);
  set(&a, 1, 0, 0.0f, 0.0f, 0.5f);
  const ImageError e = compare_images(a, b);
  EXPECT_EQ(e.overall.max_abs, 0.75);
  EXPECT_EQ(e.overall.max_x, 2);
  EXPECT_EQ(e.overall.max_y, 1);
  EXPECT_EQ(e.max_channel, 1);
  EXPECT_EQ(e.channel[0].max_x, 0);
  EXPECT_EQ(e.channel[0].max_y, 2);
  EXPECT_EQ(e.channel[2].max_abs, 0.5);
  EXPECT_EQ(e.channel[2].max_x, 1);
}

TEST(ImageMetrics, NonFinitePixelsAreCountedAndLeftOut) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Image a(4, 1), b(4, 1);
  set(&a, 0, 0, 0.5f, 0.5f, 0.5f);  // the only pixel finite in both: error 0.25 each
  set(&b, 0, 0, 0.25f, 0.25f, 0.25f);
  set(&a, 1, 0, 0.0f, nan, 0.0f);        // NaN in the image
  set(&b, 2, 0, 0.0f, 0.0f, 0.0f, inf);  // infinite alpha in the reference
  set(&a, 3, 0, -inf, 0.0f, 0.0f);       // both
  set(&b, 3, 0, nan, nan, nan, nan);
  const ImageError e = compare_images(a, b);
  EXPECT_EQ(e.non_finite_a, 2u);
  EXPECT_EQ(e.non_finite_b, 2u);
  EXPECT_EQ(e.compared_pixels, 1u);
  EXPECT_DOUBLE_EQ(e.overall.rmse, 0.25);
  EXPECT_DOUBLE_EQ(e.overall.max_abs, 0.25);
  EXPECT_NEAR(e.overall.relmse, 0.0625 / (0.0625 + kRelMseEpsilon), 1e-12);
  EXPECT_TRUE(std::isfinite(e.overall.psnr));
}

TEST(ImageMetrics, NothingToCompareGivesNaN) {
  Image a(2, 2), b(2, 2);
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y) set(&a, x, y, std::numeric_limits<float>::quiet_NaN(), 0, 0);
  const ImageError e = compare_images(a, b);
  EXPECT_EQ(e.compared_pixels, 0u);
  EXPECT_EQ(e.non_finite_a, 4u);
  EXPECT_TRUE(std::isnan(e.overall.rmse));
  EXPECT_TRUE(std::isnan(e.channel[1].psnr));
  EXPECT_EQ(e.overall.max_x, -1);
}

TEST(ImageMetrics, DifferentSizesAreRefused) {
  EXPECT_THROW(compare_images(Image(2, 3), Image(3, 2)), std::invalid_argument);
}

class ReadExr : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("prism_read_exr_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `channels` channels named `names` with pixel value base + 0.25 * channel.
  std::string write(const std::string& name, const std::vector<std::string>& names) {
    const std::string path = (dir_ / name).string();
    const int n = static_cast<int>(names.size());
    OIIO::ImageSpec spec(2, 1, n, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    for (int c = 0; c < n; ++c)
      if (names[static_cast<size_t>(c)] == "A") spec.alpha_channel = c;
    std::vector<float> data;
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < n; ++c) data.push_back(static_cast<float>(x) + 0.25f * (c + 1));
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out && out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
    out->close();
    return path;
  }

  fs::path dir_;
};

TEST_F(ReadExr, RgbaKeepsItsChannels) {
  const Image image = read_exr(write("rgba.exr", {"R", "G", "B", "A"}));
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 1);
  const float* p = image.pixel(1, 0);
  EXPECT_EQ(p[0], 1.25f);
  EXPECT_EQ(p[1], 1.5f);
  EXPECT_EQ(p[2], 1.75f);
  EXPECT_EQ(p[3], 2.0f);
}

TEST_F(ReadExr, RgbGetsAlphaOne) {
  const Image image = read_exr(write("rgb.exr", {"R", "G", "B"}));
  const float* p = image.pixel(0, 0);
  EXPECT_EQ(p[0], 0.25f);
  EXPECT_EQ(p[1], 0.5f);
  EXPECT_EQ(p[2], 0.75f);
  EXPECT_EQ(p[3], 1.0f);
}

TEST_F(ReadExr, OneChannelIsGrey) {
  const Image image = read_exr(write("y.exr", {"Y"}));
  const float* p = image.pixel(1, 0);
  EXPECT_EQ(p[0], 1.25f);
  EXPECT_EQ(p[1], 1.25f);
  EXPECT_EQ(p[2], 1.25f);
  EXPECT_EQ(p[3], 1.0f);
}

TEST_F(ReadExr, FailuresAreOneLineNamingTheFile) {
  const std::string missing = (dir_ / "missing.exr").string();
  const std::string garbage = (dir_ / "garbage.exr").string();
  std::ofstream(garbage) << "not an image\n";
  for (const std::string& path : {missing, garbage, dir_.string()}) {
    try {
      read_exr(path);
      ADD_FAILURE() << path << " was read";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

// Passes must not change a single bit: the pass callback's last image and the returned one
// equal a plain render's, and every pass sees the samples taken so far.
TEST(RenderPasses, FinalImageIsBitIdenticalToOnePass) {
  SceneDescription scene;
  scene.materials.push_back(testing::lambert_like(0.5f));
  scene.spheres.push_back(Sphere{V3d(0.0, 0.0, 0.0), 1.0, 0, "ball"});
  scene.meshes.push_back(testing::quad_mesh(5.0f, -1.0f, 0));
  scene.instances.push_back(MeshInstance{0, M44d(), "floor"});
  Light sun;
  sun.type = LightType::directional;
  sun.intensity = 3.0f;
  sun.direction = V3d(0.3, -1.0, -0.2);
  scene.lights.push_back(sun);
  scene.cameras.push_back(testing::ortho_camera_looking_down_z(5.0, 1.3));
  testing::TestSettings settings;
  settings.width = 37;
  settings.height = 23;
  settings.spp = 5;
  settings.tile_size = 8;
  settings.threads = 2;
  for (const char* kind : {"phong", "whitted"}) {
    const auto integrator = make_integrator(kind);
    SCOPED_TRACE(kind);
    const testing::Rendered plain = testing::render_scene(scene, *integrator, settings);

    const ColourPipeline colour(WorkingSpace::linear_rec709);
    GeometryOptions options;
    options.world_origin = camera_position(scene.cameras[0]);
    const RenderScene render_scene(scene, options, colour);
    const Camera camera = render_scene.camera(scene.cameras[0], settings.width, settings.height);
    std::vector<int> samples_seen;
    std::vector<float> last_seen;
    int first_pass_fractional_alpha = 0, first_pass_covered = 0;
    Image passed;
    RenderCallbacks callbacks;
    callbacks.after_pass = [&](int samples, const Image& image) {
                                         samples_seen.push_back(samples);
                                         last_seen = image.rgba;
                                         if (samples != 1) return;
                                         for (size_t i = 3; i < image.rgba.size(); i += 4) {
                                           first_pass_covered += image.rgba[i] == 1.0f ? 1 : 0;
                                           first_pass_fractional_alpha +=
                                               image.rgba[i] != 0.0f && image.rgba[i] != 1.0f;
                                         }
    };
    const RenderResult result = render(*integrator, RenderContext{render_scene, camera, settings},
                                       &passed, callbacks);
    EXPECT_EQ(samples_seen, (std::vector<int>{1, 2, 3, 4, 5}));
    ASSERT_EQ(passed.rgba.size(), plain.image.rgba.size());
    EXPECT_EQ(0, std::memcmp(passed.rgba.data(), plain.image.rgba.data(),
                             passed.rgba.size() * sizeof(float)));
    EXPECT_EQ(last_seen, passed.rgba);
    EXPECT_EQ(result.rays[RayKind::camera], plain.result.rays[RayKind::camera]);
    EXPECT_EQ(result.rays.total(), plain.result.rays.total());
    // After one pass a pixel is covered or not: alpha is 0 or 1, never a fraction.
    EXPECT_EQ(first_pass_fractional_alpha, 0);
    EXPECT_GT(first_pass_covered, 0);
  }
}

}  // namespace
}  // namespace prism
