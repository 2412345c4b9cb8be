// glTF's orthographic xmag and ymag: both honoured when the image has their ratio (the
// default resolution does); when the resolution asks for another ratio, ymag is kept and
// xmag follows the image, so pixels stay square, with a warning saying so (docs/accuracy.md,
// "Orthographic xmag/ymag").
//
// A lit quad x in [-2.25, 1.5], y in [-1.5, 0.75] (z = 0) seen from +Z with xmag 3, ymag 2:
// its edges fall on pixel boundaries in every mapping tested, so each pixel centre is half
// a pixel from the nearest edge and the lit rectangle's columns and rows are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "session/session.h"
#include "tests/gltf_test_builder.h"

namespace prism {
namespace {

using test::Builder;
using test::json;

constexpr double kX0 = -2.25, kX1 = 1.5, kY0 = -1.5, kY1 = 0.75;

std::string quad_scene() {
  Builder b;
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["materials"] = json::array({{{"pbrMetallicRoughness",
                                      {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}},
                                       {"metallicFactor", 0.0},
                                       {"roughnessFactor", 1.0}}}}});
  const int positions =
      b.positions({static_cast<float>(kX0), static_cast<float>(kY0), 0, static_cast<float>(kX1),
                   static_cast<float>(kY0), 0, static_cast<float>(kX1), static_cast<float>(kY1), 0,
                   static_cast<float>(kX0), static_cast<float>(kY1), 0});
  const int indices =
      b.accessor(b.view(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), 5123, 6, "SCALAR");
  const int quad =
      b.mesh({{"attributes", {{"POSITION", positions}}}, {"indices", indices}, {"material", 0}});
  b.node({{"mesh", quad}});
  // A sun travelling along -Z, the node's own -Z.
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] =
      json::array({{{"type", "directional"}, {"intensity", 3.0}}});
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.doc["cameras"] = json::array(
      {{{"name", "wide"},
        {"type", "orthographic"},
        {"orthographic", {{"xmag", 3.0}, {"ymag", 2.0}, {"znear", 0.01}, {"zfar", 100.0}}}}});
  b.node({{"translation", {0.0, 0.0, 10.0}}, {"camera", 0}});
  return b.write("orthographic_xmag_ymag.gltf");
}

// The lit rectangle: first and one-past-last lit column and row.
struct Lit {
  int left = -1, right = -1, top = -1, bottom = -1;
};

Lit lit_rectangle(const Image& image) {
  Lit r{image.width, 0, image.height, 0};
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i)
      if (image.pixel(i, j)[0] > 0.0f) {
        r.left = std::min(r.left, i);
        r.right = std::max(r.right, i + 1);
        r.top = std::min(r.top, j);
        r.bottom = std::max(r.bottom, j + 1);
      }
  return r;
}

struct Case {
  int width, height;      // 0 x 0: the default resolution
  double half_x, half_y;  // the extents the image must cover
  int expect_width, expect_height;
  const char* warning;  // expected in the render's warnings, or "" for none
};

TEST(OrthographicCamera, XmagAndYmagPlacePointsWhereGltfDoes) {
  SceneRequest request;
  request.path = quad_scene();
  Session session(request);
  const Case cases[] = {
      // The default resolution: 480 high at xmag / ymag = 1.5.
      {0, 0, 3.0, 2.0, 720, 480, ""},
      // Wider than 3:2: ymag kept, xmag widened to 2 * 800 / 400 = 4.
      {800, 400, 4.0, 2.0, 800, 400, "ymag kept, xmag 3 widened to 4"},
      // Narrower: ymag still kept (as a perspective camera keeps yfov), xmag narrowed to
      // 2 * 500 / 400 = 2.5.
      {500, 400, 2.5, 2.0, 500, 400, "ymag kept, xmag 3 narrowed to 2.5"},
  };
  for (const Case& c : cases) {
    RenderJob job;
    job.integrator = "shadow";
    job.width = c.width;
    job.height = c.height;
    const RenderOutput out = session.render(job);
    ASSERT_EQ(out.film.width, c.expect_width);
    ASSERT_EQ(out.film.height, c.expect_height);
    const int w = out.film.width, h = out.film.height;
    // Analytic: x maps to (x / half_x + 1) / 2 * width, y to (1 - y / half_y) / 2 * height,
    // integers here (pixel boundaries).
    const double left = (kX0 / c.half_x + 1.0) * 0.5 * w, right = (kX1 / c.half_x + 1.0) * 0.5 * w;
    const double top = (1.0 - kY1 / c.half_y) * 0.5 * h, bottom = (1.0 - kY0 / c.half_y) * 0.5 * h;
    for (const double edge : {left, right, top, bottom})
      ASSERT_NEAR(edge, std::round(edge), 1e-9) << "the quad's edges must be pixel boundaries";
    const Lit lit = lit_rectangle(out.image);
    std::printf("%dx%d: lit columns [%d, %d) rows [%d, %d), analytic [%g, %g) [%g, %g)\n", w, h,
                lit.left, lit.right, lit.top, lit.bottom, left, right, top, bottom);
    EXPECT_EQ(lit.left, std::lround(left)) << w << "x" << h;
    EXPECT_EQ(lit.right, std::lround(right)) << w << "x" << h;
    EXPECT_EQ(lit.top, std::lround(top)) << w << "x" << h;
    EXPECT_EQ(lit.bottom, std::lround(bottom)) << w << "x" << h;
    std::string warnings;
    for (const std::string& line : out.warnings) warnings += line + "\n";
    if (*c.warning) {
      ASSERT_EQ(out.warnings.size(), 1u) << warnings;
      EXPECT_NE(out.warnings[0].find(c.warning), std::string::npos) << out.warnings[0];
      EXPECT_NE(out.warnings[0].find("camera 'wide'"), std::string::npos) << out.warnings[0];
    } else {
      EXPECT_TRUE(out.warnings.empty()) << warnings;
    }
  }
}

}  // namespace
}  // namespace prism
