#include "renderer/image/image_output.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/version.h"

namespace fs = std::filesystem;

namespace prism {
namespace {

class ImageOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The built-in config, whatever the developer's environment says.
    if (const char* old = std::getenv("OCIO")) old_ocio_ = old;
    unsetenv("OCIO");
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("prism_image_output_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    fs::remove_all(dir_);
    if (!old_ocio_.empty()) setenv("OCIO", old_ocio_.c_str(), 1);
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Names in the test directory, to prove no temporary file was left behind.
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
  std::string old_ocio_;
};

Image filled(int w, int h, float r, float g, float b, float a) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* p = image.pixel(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = a;
    }
  }
  return image;
}

// Values that exercise the range an EXR must keep: negative, tiny, above 1, fractional.
Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* p = image.pixel(x, y);
      p[0] = 0.013f * x - 0.05f;
      p[1] = 1.0f / (1.0f + x + 7 * y);
      p[2] = 3.7f * y + 0.001f * x;
      p[3] = (x + y) % 2 ? 1.0f : 0.5f;
    }
  }
  return image;
}

RenderMetadata sample_metadata() {
  RenderMetadata m;
  m.integrator = "whitted";
  m.spp = 16;
  m.render_seconds = 2.5;
  m.world_to_camera = M44d(1, 0, 0, 0, 0, 0.8, -0.6, 0, 0, 0.6, 0.8, 0, 1.25, -2.5, -10.0, 1);
  m.world_to_ndc = M44d(2.1, 0, 0, 0, 0, 2.8, 0, 0, 0.5, 0.5, 1.0001, 1, 0, 0, -0.002, 0);
  m.scene_path = "scenes/cornell.gltf";
  m.extra = {{"sphereMode", "analytic"}, {"rays", "123456"}};
  return m;
}

std::vector<char> read_bytes(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

std::vector<float> read_pixels(const std::string& file, OIIO::ImageSpec* spec_out) {
  auto in = OIIO::ImageInput::open(file);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
      << in->geterror();
  *spec_out = spec;
  return pixels;
}

std::vector<unsigned char> read_png(const std::string& file, OIIO::ImageSpec* spec_out) {
  auto in = OIIO::ImageInput::open(file);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<unsigned char> pixels(static_cast<std::size_t>(spec.width) * spec.height *
                                    spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data()));
  *spec_out = spec;
  return pixels;
}

TEST_F(ImageOutputTest, PngPreviewOfMidGreyIs118InBothWorkingSpaces) {
  const int expected = static_cast<int>(std::lround(255.0 * 0.46135613));
  ASSERT_EQ(expected, 118);
  for (WorkingSpace space : {WorkingSpace::linear_rec709, WorkingSpace::acescg}) {
    ColourPipeline colour(space);
    const std::string file = path(std::string("grey_") + to_string(space) + ".png");
    write_png_preview(file, filled(5, 3, 0.18f, 0.18f, 0.18f, 1.0f), colour);
    OIIO::ImageSpec spec;
    const std::vector<unsigned char> pixels = read_png(file, &spec);
    EXPECT_EQ(spec.width, 5);
    EXPECT_EQ(spec.height, 3);
    EXPECT_EQ(spec.nchannels, 3);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
    ASSERT_EQ(pixels.size(), 5u * 3u * 3u);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      EXPECT_EQ(static_cast<int>(pixels[i]), expected) << to_string(space) << " byte " << i;
    }
  }
}

TEST_F(ImageOutputTest, PngPreviewClampsAndKeepsRowOrder) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  Image image(1, 2);
  const float top[4] = {7.0f, -2.0f, 1.0f, 1.0f};
  const float bottom[4] = {0.0f, 0.0031308f, 0.18f, 1.0f};
  std::copy(top, top + 4, image.pixel(0, 0));
  std::copy(bottom, bottom + 4, image.pixel(0, 1));
  const std::string file = path("clamp.png");
  write_png_preview(file, image, colour);
  OIIO::ImageSpec spec;
  const std::vector<unsigned char> px = read_png(file, &spec);
  ASSERT_EQ(px.size(), 6u);
  EXPECT_EQ(px[0], 255);
  EXPECT_EQ(px[1], 0);
  EXPECT_EQ(px[2], 255);
  EXPECT_EQ(px[3], 0);
  EXPECT_EQ(px[4], 10);   // round(255 * 0.04045) = round(10.31)
  EXPECT_EQ(px[5], 118);  // round(255 * 0.46135613) = round(117.65)
}

TEST_F(ImageOutputTest, FloatExrRoundTripsPixelsAndMetadata) {
  for (WorkingSpace space : {WorkingSpace::linear_rec709, WorkingSpace::acescg}) {
    ColourPipeline colour(space);
    const Image image = gradient(7, 5);
    const RenderMetadata metadata = sample_metadata();
    const std::string file = path(std::string("render_") + to_string(space) + ".exr");
    write_exr(file, image, colour, metadata, ExrPixelType::float32);

    OIIO::ImageSpec spec;
    const std::vector<float> pixels = read_pixels(file, &spec);
    EXPECT_EQ(spec.width, 7);
    EXPECT_EQ(spec.height, 5);
    ASSERT_EQ(spec.nchannels, 4);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.channelnames, (std::vector<std::string>{"R", "G", "B", "A"}));
    ASSERT_EQ(pixels.size(), image.rgba.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) EXPECT_EQ(pixels[i], image.rgba[i]) << i;

    EXPECT_EQ(spec.get_string_attribute("compression"), "piz");
    EXPECT_EQ(spec.get_string_attribute("Software"), std::string("prism ") + kVersion);

    const OIIO::ParamValue* chroma =
        spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
    ASSERT_NE(chroma, nullptr) << to_string(space);
    const std::array<float, 8> expected_chroma =
        space == WorkingSpace::acescg
            ? std::array<float, 8>{0.713f, 0.293f, 0.165f,   0.830f,
                                   0.128f, 0.044f, 0.32168f, 0.33767f}
            : std::array<float, 8>{0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(static_cast<const float*>(chroma->data())[i], expected_chroma[i]) << i;
    }

    for (const auto& [name, matrix] :
         {std::pair<const char*, M44d>{"worldToCamera", metadata.world_to_camera},
          {"worldToNDC", metadata.world_to_ndc}}) {
      const OIIO::ParamValue* p = spec.find_attribute(name, OIIO::TypeMatrix44);
      ASSERT_NE(p, nullptr) << name;
      const float* m = static_cast<const float*>(p->data());
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
          EXPECT_EQ(m[r * 4 + c], static_cast<float>(matrix[r][c])) << name << " " << r << c;
        }
      }
    }

    EXPECT_EQ(spec.get_string_attribute("prism:integrator"), "whitted");
    const OIIO::ParamValue* spp = spec.find_attribute("prism:spp", OIIO::TypeInt);
    ASSERT_NE(spp, nullptr);
    EXPECT_EQ(*static_cast<const int*>(spp->data()), 16);
    const OIIO::ParamValue* seconds = spec.find_attribute("prism:renderSeconds", OIIO::TypeFloat);
    ASSERT_NE(seconds, nullptr);
    EXPECT_EQ(*static_cast<const float*>(seconds->data()), 2.5f);
    EXPECT_EQ(spec.get_string_attribute("prism:scene"), "scenes/cornell.gltf");
    EXPECT_EQ(spec.get_string_attribute("prism:workingSpace"), to_string(space));
    EXPECT_EQ(spec.get_string_attribute("prism:ocioConfig"), "built-in");
    EXPECT_EQ(spec.get_string_attribute("prism:sphereMode"), "analytic");
    EXPECT_EQ(spec.get_string_attribute("prism:rays"), "123456");
  }
  EXPECT_EQ(listing(), (std::vector<std::string>{"render_acescg.exr", "render_linear-rec709.exr"}));
}

TEST_F(ImageOutputTest, HalfExrIsTheDefaultAndKeepsHalfPrecision) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const Image image = gradient(9, 4);
  const std::string file = path("half.exr");
  write_exr(file, image, colour, sample_metadata());
  OIIO::ImageSpec spec;
  const std::vector<float> pixels = read_pixels(file, &spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::HALF);
  ASSERT_EQ(pixels.size(), image.rgba.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    // Round to nearest keeps the relative error within half an ulp: 2^-11. Values below
    // half's normal range (2^-14) are denormals with a fixed absolute step of 2^-24.
    const float v = image.rgba[i];
    const float tolerance = std::max(std::abs(v) * 0x1p-11f, 0x1p-25f);
    EXPECT_NEAR(pixels[i], v, tolerance) << i;
  }
  // Not trivially float: something must have been rounded.
  bool any_rounded = false;
  for (std::size_t i = 0; i < pixels.size(); ++i) any_rounded |= pixels[i] != image.rgba[i];
  EXPECT_TRUE(any_rounded);
}

TEST_F(ImageOutputTest, OverwritingReplacesTheOldFile) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const std::string file = path("again.exr");
  write_exr(file, filled(2, 2, 1, 1, 1, 1), colour, sample_metadata(), ExrPixelType::float32);
  write_exr(file, filled(2, 2, 0.25f, 0.5f, 0.75f, 1), colour, sample_metadata(),
            ExrPixelType::float32);
  OIIO::ImageSpec spec;
  const std::vector<float> pixels = read_pixels(file, &spec);
  ASSERT_EQ(pixels.size(), 16u);
  EXPECT_EQ(pixels[0], 0.25f);
  EXPECT_EQ(pixels[1], 0.5f);
  EXPECT_EQ(pixels[2], 0.75f);
  EXPECT_EQ(listing(), std::vector<std::string>{"again.exr"});
}

TEST_F(ImageOutputTest, NonexistentDirectoryThrowsAndWritesNothing) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const fs::path missing = dir_ / "no" / "such" / "dir";
  const std::string exr = (missing / "out.exr").string();
  const std::string png = (missing / "out.png").string();
  const Image image = filled(2, 2, 0.5f, 0.5f, 0.5f, 1.0f);
  try {
    write_exr(exr, image, colour, sample_metadata());
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(exr + ": ", 0), 0u) << message;
    EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  }
  EXPECT_THROW(write_png_preview(png, image, colour), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "no"));
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageOutputTest, EmptyImageIsRefusedAndTheOldFileKept) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const std::string exr = path("keep.exr");
  const std::string png = path("keep.png");
  write_exr(exr, filled(3, 2, 0.5f, 0.5f, 0.5f, 1.0f), colour, sample_metadata());
  write_png_preview(png, filled(3, 2, 0.5f, 0.5f, 0.5f, 1.0f), colour);
  const std::vector<char> exr_before = read_bytes(exr);
  const std::vector<char> png_before = read_bytes(png);
  ASSERT_FALSE(exr_before.empty());

  for (const Image& bad : {Image(0, 4), Image(4, 0), Image()}) {
    try {
      write_exr(exr, bad, colour, sample_metadata());
      FAIL() << "expected std::runtime_error";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(exr + ": ", 0), 0u) << message;
      EXPECT_NE(message.find("empty image"), std::string::npos) << message;
    }
    EXPECT_THROW(write_png_preview(png, bad, colour), std::runtime_error);
  }
  Image short_buffer(2, 2);
  short_buffer.rgba.resize(3);
  EXPECT_THROW(write_exr(exr, short_buffer, colour, sample_metadata()), std::runtime_error);

  EXPECT_EQ(read_bytes(exr), exr_before);
  EXPECT_EQ(read_bytes(png), png_before);
  EXPECT_EQ(listing(), (std::vector<std::string>{"keep.exr", "keep.png"}));
}

// The rename into place fails after OIIO has written the temporary file: the temporary
// must still be cleaned up and the target left as it was.
TEST_F(ImageOutputTest, FailedRenameRemovesTheTemporaryFile) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const fs::path target = dir_ / "taken.exr";
  fs::create_directories(target / "inside");
  try {
    write_exr(target.string(), filled(2, 2, 1, 1, 1, 1), colour, sample_metadata());
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(target.string() + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_TRUE(fs::is_directory(target / "inside"));
  EXPECT_EQ(listing(), std::vector<std::string>{"taken.exr"});
}

TEST_F(ImageOutputTest, RelativePathWritesIntoTheCurrentDirectory) {
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const fs::path old_cwd = fs::current_path();
  fs::current_path(dir_);
  EXPECT_NO_THROW(write_png_preview("relative.png", filled(1, 1, 1, 1, 1, 1), colour));
  fs::current_path(old_cwd);
  EXPECT_EQ(listing(), std::vector<std::string>{"relative.png"});
}

}  // namespace
}  // namespace prism
