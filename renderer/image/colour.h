// Colour management through OpenColorIO.
//
// Prism renders in a scene-linear working space. glTF states its colour factors and light
// colours in linear Rec.709 and its colour textures in sRGB encoding; both are converted to
// the working space once, at scene build time. Output goes to EXR in the working space (with
// its chromaticities) and, for previews, through the config's display/view transform.
//
// The config is the one named by $OCIO, as OCIO's own tools do, or else the small config
// shipped in renderer/image/ocio/config.ocio, compiled into the binary so that an installed prism
// never looks for it on disk.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/enum_names.h"
#include "renderer/image/image.h"
#include "renderer/scene_description.h"

namespace prism {

enum class WorkingSpace { linear_rec709, acescg };

// For the command line and metadata (renderer/enum_names.h: to_string, parse_enum).
inline constexpr EnumName<WorkingSpace> kWorkingSpaceNames[] = {
    {WorkingSpace::linear_rec709, "linear-rec709"}, {WorkingSpace::acescg, "acescg"}};
constexpr std::span<const EnumName<WorkingSpace>> enum_names(WorkingSpace) {
  return kWorkingSpaceNames;
}

// How a display-referred output (PNG, JPEG, the preview) is made from the scene-linear image.
struct DisplayOptions {
  std::string view;       // a view of the config's display; empty = Standard, else its default
  double exposure = 0.0;  // stops: the scene-linear image is scaled by 2^exposure first
};

struct DisplayView {
  std::string display, view;
  bool is_default = false;  // what an empty DisplayOptions::view gives
};

class ColourPipeline {
 public:
  // Throws std::runtime_error with a one-line message if the config cannot be loaded or
  // lacks the colour spaces Prism needs.
  explicit ColourPipeline(WorkingSpace working_space);
  ~ColourPipeline();
  ColourPipeline(const ColourPipeline&) = delete;
  ColourPipeline& operator=(const ColourPipeline&) = delete;

  WorkingSpace working_space() const { return working_space_; }
  // The OCIO colour space name of the working space in the active config.
  const std::string& working_space_name() const;
  // Where the config came from: "$OCIO=<path>" or "built-in".
  const std::string& config_source() const;

  // A glTF colour factor or light colour (linear Rec.709) in the working space.
  C3f from_linear_rec709(const C3f& c) const;
  // Texels of an sRGB-encoded texture (base colour, emissive), in place, to the working
  // space. `channels` is 3 or 4; alpha is left alone.
  void srgb_texture_to_working(float* texels, std::size_t pixel_count, int channels) const;
  // What srgb_texture_to_working gives for each 8-bit code's value (code * (1.0f / 255.0f)),
  // per channel, from the same processor bit for bit; empty when the transform mixes
  // channels (a working space with other primaries), which no per-channel table reproduces.
  using CodeTable = std::array<std::array<float, 256>, 3>;
  std::optional<CodeTable> srgb_texture_code_table() const;
  // The image through the display/view transform (sRGB display, Standard view), as
  // display-referred RGBA in [0, 1] ready to quantise for a PNG.
  Image working_to_display(const Image& image) const;
  // Through the view `options` names (std::runtime_error listing the views when the config's
  // display has no such view), after the exposure.
  Image working_to_display(const Image& image, const DisplayOptions& options) const;
  // Every display and view of the config, the one used first.
  std::vector<DisplayView> views() const;
  // The display the images are shown on (sRGB - Display, else the config's default).
  const std::string& display() const;
  // CIE xy of the working space's red, green, blue and white: rx ry gx gy bx by wx wy.
  std::array<float, 8> chromaticities() const;

 private:
  struct Impl;
  WorkingSpace working_space_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace prism
