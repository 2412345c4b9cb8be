// The image codecs that replaced OpenImageIO on the render path (docs/images.md), checked
// against OpenImageIO itself, which the tests still link as the reference: every glTF PNG
// and JPEG decodes to the same floats bit for bit (8-bit codes normalised as the loader reads
// them), EXRs round-trip every value and header field, and OpenImageIO reads the EXRs and PNGs
// Prism writes.
#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

#include "renderer/image/exr_file.h"
#include "renderer/image/image_metrics.h"
#include "renderer/image/oiio_module.h"
#include "renderer/image/png_file.h"
#include "renderer/scene_description.h"
#include "scene_io/image_decoders.h"

namespace fs = std::filesystem;

namespace prism {
namespace {

using gltf_detail::ImageHeader;

std::vector<unsigned char> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A folder of this process's own (ctest runs each test in a process), removed when it ends
// so that runs leave nothing behind in the temporary directory.
fs::path scratch(const std::string& name) {
  static const struct Folder {
    fs::path path = fs::temp_directory_path() / ("prism_codecs_" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } folder;
  return folder.path / name;
}

// OpenImageIO's decoding of a file as floats, with straight alpha: glTF's texels are not
// premultiplied, and OpenImageIO premultiplies PNG colour by alpha unless told not to.
std::vector<float> oiio_texels(const fs::path& path, OIIO::ImageSpec* spec) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
  if (!in) return {};
  *spec = in->spec();
  std::vector<float> texels(size_t(spec->width) * spec->height * spec->nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec->nchannels, OIIO::TypeDesc::FLOAT, texels.data()));
  return texels;
}

// Decodes with Prism's codec and compares with OpenImageIO's floats, bit for bit.
void expect_same_as_oiio(const fs::path& path) {
  SCOPED_TRACE(path.string());
  const std::vector<unsigned char> bytes = read_file(path);
  const bool png = bytes.size() > 8 && bytes[0] == 0x89;
  ImageHeader header;
  const std::string problem =
      png ? gltf_detail::read_png_header(bytes.data(), bytes.size(), &header)
          : gltf_detail::read_jpeg_header(bytes.data(), bytes.size(), &header);
  ASSERT_EQ(problem, "");
  OIIO::ImageSpec spec;
  const std::vector<float> expected = oiio_texels(path, &spec);
  ASSERT_EQ(header.width, spec.width);
  ASSERT_EQ(header.height, spec.height);
  ASSERT_EQ(header.channels, spec.nchannels);
  // The samples as stored, normalised as the loader reads them: an 8-bit code through
  // TextureImage::code_value, a 16-bit sample as v * (1 / 65535).
  std::vector<uint16_t> samples(expected.size(), 0xFFFF);
  auto* raw = reinterpret_cast<unsigned char*>(samples.data());
  const std::string decoded =
      png ? gltf_detail::decode_png(bytes.data(), bytes.size(), header, raw)
          : gltf_detail::decode_jpeg(bytes.data(), bytes.size(), header, raw);
  ASSERT_EQ(decoded, "");
  std::vector<float> texels(expected.size());
  for (size_t i = 0; i < texels.size(); ++i)
    texels[i] =
        header.bits == 8 ? TextureImage::code_value(raw[i]) : float(samples[i]) * (1.0f / 65535.0f);
  size_t differing = 0;
  for (size_t i = 0; i < texels.size(); ++i)
    differing += std::memcmp(&texels[i], &expected[i], sizeof(float)) != 0;
  EXPECT_EQ(differing, 0u) << "of " << texels.size() << " values";
}

// A test image with every 8-bit value in each channel and partial alpha.
void write_with_oiio(const fs::path& path, int channels, OIIO::TypeDesc type) {
  const int w = 67, h = 41;
  std::vector<float> values(size_t(w) * h * channels);
  for (size_t i = 0; i < values.size(); ++i) values[i] = float((i * 37) % 256) / 255.0f;
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, channels, type);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values.data()));
  ASSERT_TRUE(out->close());
}

TEST(ImageCodecs, GltfSampleImagesDecodeAsOpenImageIODecodesThem) {
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(PRISM_ASSIMP_GLTF2_DIR)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".png" && ext != ".jpg") continue;
    expect_same_as_oiio(entry.path());
    ++files;
  }
  EXPECT_GE(files, 10);  // the package's PNGs and its JPEG
}

TEST(ImageCodecs, EveryPngAndJpegLayoutDecodesAsOpenImageIODecodesIt) {
  for (int channels = 1; channels <= 4; ++channels) {
    for (OIIO::TypeDesc type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16}) {
      const fs::path png =
          scratch("layout" + std::to_string(channels) + "_" + type.c_str() + ".png");
      write_with_oiio(png, channels, type);
      expect_same_as_oiio(png);
    }
  }
  for (int channels : {1, 3}) {
    const fs::path jpeg = scratch("layout" + std::to_string(channels) + ".jpg");
    write_with_oiio(jpeg, channels, OIIO::TypeDesc::UINT8);
    expect_same_as_oiio(jpeg);
  }
}

TEST(ImageCodecs, BrokenImagesAreRefusedWithAReason) {
  std::vector<unsigned char> png =
      read_file(fs::path(PRISM_ASSIMP_GLTF2_DIR) / "BoxTextured-glTF" / "CesiumLogoFlat.png");
  ASSERT_GT(png.size(), 100u);
  ImageHeader header;
  ASSERT_EQ(gltf_detail::read_png_header(png.data(), png.size(), &header), "");
  std::vector<unsigned char> texels(size_t(header.width) * header.height * header.channels *
                                    size_t(header.bits / 8));
  // Cut short in the image data: the header reads, the pixels do not.
  const std::string cut =
      gltf_detail::decode_png(png.data(), png.size() / 2, header, texels.data());
  EXPECT_NE(cut.find("the PNG image cannot be read"), std::string::npos) << cut;
  // A corrupted IHDR fails its CRC.
  png[20] ^= 0x40;
  EXPECT_NE(gltf_detail::read_png_header(png.data(), png.size(), &header), "");
  const unsigned char not_jpeg[] = {0xFF, 0xD8, 0xFF, 0x00, 0x01, 0x02};
  EXPECT_NE(gltf_detail::read_jpeg_header(not_jpeg, sizeof not_jpeg, &header).find("JPEG"),
            std::string::npos);
}

TEST(ExrFile, RoundTripsEveryValueAndHeaderField) {
  Image image(5, 3);
  for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = 0.1f * float(i) - 2.0f;
  image.rgba[7] = 1e30f;
  ExrHeader header;
  header.chromaticities =
      std::array<float, 8>{0.64f, 0.33f, 0.3f, 0.6f, 0.15f, 0.06f, 0.3127f, 0.329f};
  header.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 4, 5, 6, 1};
  header.strings = {{"prism:integrator", "whitted"}};
  header.ints = {{"prism:spp", 16}};
  header.floats = {{"prism:renderSeconds", 1.5f}};
  for (ExrCompression c : {ExrCompression::none, ExrCompression::rle, ExrCompression::zips,
                           ExrCompression::zip, ExrCompression::piz}) {
    SCOPED_TRACE(to_string(c));
    const std::string path = scratch(std::string("round_") + to_string(c) + ".exr").string();
    write_exr_file(path, image, header, {ExrPixelType::float32, c, 2});
    const Image back = read_exr_file(path);
    ASSERT_EQ(back.width, 5);
    ASSERT_EQ(back.height, 3);
    EXPECT_EQ(std::memcmp(back.rgba.data(), image.rgba.data(), image.rgba.size() * 4), 0);
    const std::optional<ExrHeader> read = read_exr_header(path);
    ASSERT_TRUE(read);
    EXPECT_EQ(read->string_value("prism:integrator"), "whitted");
    EXPECT_EQ(read->int_value("prism:spp"), 16);
    EXPECT_EQ(read->float_value("prism:renderSeconds"), 1.5f);
    // OpenImageIO, the reference reader, sees the same file.
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_int_attribute("prism:spp"), 16);
    EXPECT_EQ(in->spec().get_string_attribute("prism:integrator"), "whitted");
    const OIIO::ParamValue* chroma =
        in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
    ASSERT_TRUE(chroma);
    EXPECT_EQ(static_cast<const float*>(chroma->data())[6], 0.3127f);
    const OIIO::ParamValue* w2c = in->spec().find_attribute("worldToCamera", OIIO::TypeMatrix44);
    ASSERT_TRUE(w2c);
    EXPECT_EQ(static_cast<const float*>(w2c->data())[13], 5.0f);
    std::vector<float> oiio(image.rgba.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, oiio.data()));
    EXPECT_EQ(std::memcmp(oiio.data(), image.rgba.data(), image.rgba.size() * 4), 0);
  }
}

TEST(ExrFile, HalfPixelsRoundAsImathRounds) {
  Image image(3, 1);
  image.rgba = {1.0f / 3.0f, 65504.0f, 70000.0f, 1.0f, 1e-8f, -2.5f,
                0.1f,        0.5f,     0.0f,     1.0f, 2.0f,  0.0f};
  const std::string path = scratch("half.exr").string();
  write_exr_file(path, image, {}, {ExrPixelType::half, ExrCompression::zip, 1});
  const Image back = read_exr_file(path);
  for (size_t i = 0; i < image.rgba.size(); ++i)
    EXPECT_EQ(back.rgba[i], float(half(image.rgba[i]))) << i;
}

TEST(ExrFile, DataWindowAndGreyChannelsAreRead) {
  // Written by OpenImageIO: one channel "Y", data window offset from the origin.
  const std::string path = scratch("grey_window.exr").string();
  OIIO::ImageSpec spec(4, 2, 1, OIIO::TypeDesc::FLOAT);
  spec.x = 10;
  spec.y = -3;
  spec.channelnames = {"Y"};
  const float values[] = {0, 1, 2, 3, 4, 5, 6, 7};
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values));
  ASSERT_TRUE(out->close());
  const Image image = read_exr_file(path);
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 2);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(image.rgba[i * 4 + 0], values[i]);
    EXPECT_EQ(image.rgba[i * 4 + 2], values[i]);
    EXPECT_EQ(image.rgba[i * 4 + 3], 1.0f);
  }
}

TEST(ExrFile, BrokenFilesAreOneLineErrorsNamingTheFile) {
  const std::string path = scratch("broken.exr").string();
  std::ofstream(path, std::ios::binary) << "\x76\x2f\x31\x01 not really an EXR";
  try {
    read_exr_file(path);
    FAIL() << "a broken EXR was read";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(PngFile, OpenImageIOReadsWhatPrismWrites) {
  const int w = 9, h = 4;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i * 7);
  const std::string path = scratch("written.png").string();
  write_png_file(path, w, h, rgb.data(), "prism test");
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 3);
  EXPECT_EQ(in->spec().get_string_attribute("Software"), "prism test");
  std::vector<uint8_t> back(rgb.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data()));
  EXPECT_EQ(back, rgb);
}

TEST(OiioModule, ReadsOtherFormatsOnlyWhenAsked) {
  // A PNG given where an image is compared: the module is loaded and reads it.
  const fs::path png = scratch("reference.png");
  write_with_oiio(png, 3, OIIO::TypeDesc::UINT8);
  const Image image = read_exr(png.string());
  EXPECT_EQ(image.width, 67);
  EXPECT_EQ(image.height, 41);
  EXPECT_FLOAT_EQ(image.rgba[1], 37.0f / 255.0f);
  EXPECT_EQ(image.rgba[3], 1.0f);
  EXPECT_NO_THROW(oiio_module(png.string()));
}

}  // namespace
}  // namespace prism
