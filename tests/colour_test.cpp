#include "renderer/image/colour.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "renderer/builtin_ocio_config.h"

namespace prism {
namespace {

// Sets $OCIO for one test and restores the caller's value afterwards, so that the other
// tests (and a developer's own $OCIO) are unaffected.
class ScopedOcioEnv {
 public:
  explicit ScopedOcioEnv(const char* value) {
    if (const char* old = std::getenv("OCIO")) old_ = old;
    if (value) {
      setenv("OCIO", value, 1);
    } else {
      unsetenv("OCIO");
    }
  }
  ~ScopedOcioEnv() {
    if (old_) {
      setenv("OCIO", old_->c_str(), 1);
    } else {
      unsetenv("OCIO");
    }
  }

 private:
  std::optional<std::string> old_;
};

// --- An independent derivation of Rec.709 -> ACEScg from the published primaries. ---

using Mat3 = std::array<std::array<double, 3>, 3>;
using Vec3 = std::array<double, 3>;

Mat3 multiply(const Mat3& a, const Mat3& b) {
  Mat3 m{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) m[r][c] += a[r][k] * b[k][c];
  return m;
}

Vec3 multiply(const Mat3& a, const Vec3& v) {
  Vec3 out{};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out[r] += a[r][k] * v[k];
  return out;
}

Mat3 inverse(const Mat3& m) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  Mat3 inv{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      // Cofactor of (c, r), i.e. the adjugate's (r, c) entry.
      const int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
      inv[r][c] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
    }
  }
  return inv;
}

Vec3 xy_to_XYZ(double x, double y) {
  return {x / y, 1.0, (1.0 - x - y) / y};
}

// RGB -> XYZ for primaries and white given as rx ry gx gy bx by wx wy.
Mat3 rgb_to_xyz(const std::array<double, 8>& p) {
  Mat3 primaries{};
  for (int i = 0; i < 3; ++i) {
    const Vec3 xyz = xy_to_XYZ(p[2 * i], p[2 * i + 1]);
    for (int r = 0; r < 3; ++r) primaries[r][i] = xyz[r];
  }
  const Vec3 scale = multiply(inverse(primaries), xy_to_XYZ(p[6], p[7]));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) primaries[r][c] *= scale[c];
  return primaries;
}

Mat3 bradford(double src_x, double src_y, double dst_x, double dst_y) {
  const Mat3 cone{
      {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  const Vec3 src = multiply(cone, xy_to_XYZ(src_x, src_y));
  const Vec3 dst = multiply(cone, xy_to_XYZ(dst_x, dst_y));
  Mat3 gain{};
  for (int i = 0; i < 3; ++i) gain[i][i] = dst[i] / src[i];
  return multiply(inverse(cone), multiply(gain, cone));
}

constexpr std::array<double, 8> kRec709 = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290};
constexpr std::array<double, 8> kAp1 = {0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767};

Mat3 expected_rec709_to_acescg() {
  return multiply(
      inverse(rgb_to_xyz(kAp1)),
      multiply(bradford(kRec709[6], kRec709[7], kAp1[6], kAp1[7]), rgb_to_xyz(kRec709)));
}

double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double srgb_encode(double v) {
  return v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// --- Tests ---

TEST(WorkingSpace, NamesRoundTrip) {
  EXPECT_STREQ(to_string(WorkingSpace::linear_rec709), "linear-rec709");
  EXPECT_STREQ(to_string(WorkingSpace::acescg), "acescg");
  WorkingSpace space = WorkingSpace::linear_rec709;
  ASSERT_TRUE(parse_enum("acescg", &space));
  EXPECT_EQ(space, WorkingSpace::acescg);
  ASSERT_TRUE(parse_enum("linear-rec709", &space));
  EXPECT_EQ(space, WorkingSpace::linear_rec709);
  EXPECT_FALSE(parse_enum("srgb", &space));
  EXPECT_FALSE(parse_enum("", &space));
  EXPECT_EQ(space, WorkingSpace::linear_rec709);
}

TEST(ColourPipeline, BuiltinConfigNamesAndChromaticities) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline rec709(WorkingSpace::linear_rec709);
  EXPECT_EQ(rec709.config_source(), "built-in");
  EXPECT_EQ(rec709.working_space_name(), "Linear Rec.709 (sRGB)");
  const std::array<float, 8> c709 = rec709.chromaticities();
  for (int i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(c709[i], static_cast<float>(kRec709[i])) << i;

  ColourPipeline acescg(WorkingSpace::acescg);
  EXPECT_EQ(acescg.working_space_name(), "ACEScg");
  const std::array<float, 8> cap1 = acescg.chromaticities();
  for (int i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(cap1[i], static_cast<float>(kAp1[i])) << i;
}

TEST(ColourPipeline, SrgbTextureDecodesWithThePiecewiseCurve) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::linear_rec709);
  float texels[] = {0.5f, 0.04045f, 1.0f, 0.0f, 0.01f, 0.8f};
  colour.srgb_texture_to_working(texels, 2, 3);
  EXPECT_NEAR(texels[0], 0.21404114, 1e-6);
  EXPECT_NEAR(texels[1], 0.0031308, 1e-6);
  EXPECT_NEAR(texels[2], 1.0, 1e-6);
  EXPECT_NEAR(texels[3], 0.0, 1e-7);
  EXPECT_NEAR(texels[4], srgb_decode(0.01), 1e-6);  // the linear segment
  EXPECT_NEAR(texels[5], srgb_decode(0.8), 1e-6);
}

TEST(ColourPipeline, SrgbTextureLeavesAlphaAlone) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::acescg);
  // Grey decodes to the same grey in ACEScg: the Rec.709 -> ACEScg matrix maps white to white.
  float texels[] = {0.5f, 0.5f, 0.5f, 0.5f, 1.0f, 0.0f, 0.0f, 0.25f};
  colour.srgb_texture_to_working(texels, 2, 4);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(texels[c], 0.21404114, 1e-6);
  EXPECT_EQ(texels[3], 0.5f);
  EXPECT_EQ(texels[7], 0.25f);
  const Mat3 m = expected_rec709_to_acescg();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(texels[4 + c], m[c][0], 1e-5);
  EXPECT_THROW(colour.srgb_texture_to_working(texels, 1, 2), std::invalid_argument);
}

TEST(ColourPipeline, Rec709FactorsAreIdentityInLinearRec709) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const C3f c = colour.from_linear_rec709(C3f(0.8f, 0.1f, 0.05f));
  EXPECT_FLOAT_EQ(c.x, 0.8f);
  EXPECT_FLOAT_EQ(c.y, 0.1f);
  EXPECT_FLOAT_EQ(c.z, 0.05f);
}

TEST(ColourPipeline, Rec709ToAcescgMatchesPrimariesWithBradford) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::acescg);
  const Mat3 m = expected_rec709_to_acescg();

  // Sanity of the derivation itself against the widely published values.
  EXPECT_NEAR(m[0][0], 0.61310, 1e-5);
  EXPECT_NEAR(m[1][0], 0.07020, 1e-5);
  EXPECT_NEAR(m[2][0], 0.02062, 1e-5);

  const C3f unit[3] = {C3f(1, 0, 0), C3f(0, 1, 0), C3f(0, 0, 1)};
  for (int i = 0; i < 3; ++i) {
    const C3f out = colour.from_linear_rec709(unit[i]);
    EXPECT_NEAR(out.x, m[0][i], 1e-6) << "primary " << i;
    EXPECT_NEAR(out.y, m[1][i], 1e-6) << "primary " << i;
    EXPECT_NEAR(out.z, m[2][i], 1e-6) << "primary " << i;
  }
  const C3f white = colour.from_linear_rec709(C3f(1, 1, 1));
  EXPECT_NEAR(white.x, 1.0, 1e-5);
  EXPECT_NEAR(white.y, 1.0, 1e-5);
  EXPECT_NEAR(white.z, 1.0, 1e-5);
}

TEST(ColourPipeline, MidGreyToDisplayIsTheSrgbEncodingInBothSpaces) {
  ScopedOcioEnv env(nullptr);
  ASSERT_NEAR(srgb_encode(0.18), 0.46135613, 1e-8);
  for (WorkingSpace space : {WorkingSpace::linear_rec709, WorkingSpace::acescg}) {
    ColourPipeline colour(space);
    Image image(2, 1);
    const float grey[4] = {0.18f, 0.18f, 0.18f, 0.25f};
    std::copy(grey, grey + 4, image.pixel(0, 0));
    const float odd[4] = {4.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), 1.5f};
    std::copy(odd, odd + 4, image.pixel(1, 0));

    const Image display = colour.working_to_display(image);
    ASSERT_EQ(display.width, 2);
    ASSERT_EQ(display.height, 1);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(display.pixel(0, 0)[c], 0.46135613, 1e-6) << to_string(space);
    EXPECT_EQ(display.pixel(0, 0)[3], 0.25f);
    for (int c = 0; c < 4; ++c) {
      EXPECT_GE(display.pixel(1, 0)[c], 0.0f) << c;
      EXPECT_LE(display.pixel(1, 0)[c], 1.0f) << c;
    }
    EXPECT_EQ(display.pixel(1, 0)[3], 1.0f);
  }
}

TEST(ColourPipeline, Rec709OutOfRangeClampsPerChannel) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::linear_rec709);
  Image image(1, 1);
  const float px[4] = {4.0f, -1.0f, 0.0031308f, 1.0f};
  std::copy(px, px + 4, image.pixel(0, 0));
  const Image display = colour.working_to_display(image);
  EXPECT_NEAR(display.pixel(0, 0)[0], 1.0f, 1e-6);  // clamped to 1, then encoded in float
  EXPECT_EQ(display.pixel(0, 0)[1], 0.0f);
  EXPECT_NEAR(display.pixel(0, 0)[2], 0.04045, 1e-6);
}

// The ACES 1.0 SDR-video view rolls highlights off: brighter scene values stay brighter on
// the display, all below white, where Standard clips everything from 1 up. Mid grey lands
// near the ACES reference's 0.18 -> about 0.39 (sRGB-encoded, after the RRT's contrast).
TEST(ColourPipeline, AcesViewRollsHighlightsOffWhereStandardClips) {
  ScopedOcioEnv env(nullptr);
  ColourPipeline colour(WorkingSpace::linear_rec709);
  const float values[] = {0.18f, 1.0f, 4.0f, 16.0f};
  Image image(4, 1);
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) image.pixel(i, 0)[c] = values[i];
  const Image aces = colour.working_to_display(image, {"ACES 1.0 SDR-video", 0.0});
  const Image standard = colour.working_to_display(image, {"Standard", 0.0});
  EXPECT_NEAR(aces.pixel(0, 0)[1], 0.39, 0.05);
  for (int i = 1; i < 4; ++i) {
    EXPECT_GT(aces.pixel(i, 0)[1], aces.pixel(i - 1, 0)[1]) << values[i];
    EXPECT_LT(aces.pixel(i, 0)[1], 1.0f) << values[i];
    EXPECT_NEAR(standard.pixel(i, 0)[1], 1.0f, 1e-6) << values[i];
  }
  // The exposure scales the scene-linear values first: +1 stop of 0.09 is 0.18.
  Image half(1, 1);
  for (int c = 0; c < 3; ++c) half.pixel(0, 0)[c] = 0.09f;
  EXPECT_NEAR(colour.working_to_display(half, {"", 1.0}).pixel(0, 0)[0], 0.46135613, 1e-6);
  EXPECT_THROW(colour.working_to_display(half, {"No such view", 0.0}), std::runtime_error);
  const std::vector<DisplayView> views = colour.views();
  ASSERT_EQ(views.size(), 3u);
  EXPECT_EQ(views[0].view, "Standard");
  EXPECT_TRUE(views[0].is_default);
  EXPECT_EQ(views[1].view, "ACES 1.0 SDR-video");
}

TEST(ColourPipeline, MissingOcioFileIsNamedInTheError) {
  const std::string path = "/nonexistent/prism-test/config.ocio";
  ScopedOcioEnv env(path.c_str());
  try {
    ColourPipeline colour(WorkingSpace::linear_rec709);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

class OcioFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("prism_colour_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write_config(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(OcioFileTest, ConfigFromOcioIsUsed) {
  const std::string path = write_config("copy.ocio", kBuiltinOcioConfig);
  ScopedOcioEnv env(path.c_str());
  ColourPipeline colour(WorkingSpace::acescg);
  EXPECT_EQ(colour.config_source(), "$OCIO=" + path);
  EXPECT_NEAR(colour.from_linear_rec709(C3f(1, 0, 0)).x, expected_rec709_to_acescg()[0][0], 1e-6);
}

TEST_F(OcioFileTest, EmptyOcioMeansBuiltin) {
  ScopedOcioEnv env("");
  ColourPipeline colour(WorkingSpace::linear_rec709);
  EXPECT_EQ(colour.config_source(), "built-in");
}

TEST_F(OcioFileTest, ConfigWithoutAcescgIsRejectedForAcescgOnly) {
  const std::string config = R"(ocio_profile_version: 2
roles:
  default: Raw
  scene_linear: Linear Rec.709 (sRGB)
  reference: Linear Rec.709 (sRGB)
displays:
  sRGB - Display:
    - !<View> {name: Standard, colorspace: sRGB - Texture}
colorspaces:
  - !<ColorSpace>
    name: Linear Rec.709 (sRGB)
  - !<ColorSpace>
    name: sRGB - Texture
    to_scene_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055}
  - !<ColorSpace>
    name: Raw
    isdata: true
)";
  const std::string path = write_config("no_acescg.ocio", config);
  ScopedOcioEnv env(path.c_str());
  EXPECT_NO_THROW(ColourPipeline colour(WorkingSpace::linear_rec709));
  try {
    ColourPipeline colour(WorkingSpace::acescg);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("ACEScg"), std::string::npos) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
  }
}

TEST_F(OcioFileTest, MalformedConfigIsAOneLineError) {
  const std::string path = write_config("broken.ocio", "ocio_profile_version: 2\nroles: [\n");
  ScopedOcioEnv env(path.c_str());
  try {
    ColourPipeline colour(WorkingSpace::linear_rec709);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace prism
