#include "renderer/image/colour.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "renderer/builtin_ocio_config.h"

namespace OCIO = OCIO_NAMESPACE;

namespace prism {

namespace {

constexpr const char* kLinearRec709Name = "Linear Rec.709 (sRGB)";
constexpr const char* kAcescgName = "ACEScg";
constexpr const char* kSrgbTextureName = "sRGB - Texture";
constexpr const char* kDisplayName = "sRGB - Display";
constexpr const char* kViewName = "Standard";

// OCIO's messages sometimes span lines; ours are promised to be one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Lossless only: the default optimisation level swaps pow() for a fast approximation and may
// bake 1D curves into LUTs, which costs more than the 1e-6 the sRGB decode is tested to.
OCIO::ConstCPUProcessorRcPtr cpu_processor(const OCIO::ConstProcessorRcPtr& processor) {
  return processor->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                             OCIO::OPTIMIZATION_LOSSLESS);
}

// Applies `processor` to the RGB of pixels with `channels` floats each, leaving any further
// channels untouched. Going through a small RGB scratch buffer keeps alpha out of the
// config's hands (a user config may well contain ops that touch it) without copying the
// whole image.
void apply_rgb(const OCIO::CPUProcessor& processor, float* data, std::size_t pixel_count,
               int channels) {
  if (channels == 3) {
    constexpr std::size_t kChunk = 1 << 20;
    for (std::size_t start = 0; start < pixel_count; start += kChunk) {
      const std::size_t n = std::min(kChunk, pixel_count - start);
      OCIO::PackedImageDesc desc(data + start * 3, static_cast<long>(n), 1, 3);
      processor.apply(desc);
    }
    return;
  }
  constexpr std::size_t kChunk = 4096;
  std::vector<float> scratch(kChunk * 3);
  for (std::size_t start = 0; start < pixel_count; start += kChunk) {
    const std::size_t n = std::min(kChunk, pixel_count - start);
    float* base = data + start * channels;
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) scratch[i * 3 + c] = base[i * channels + c];
    }
    OCIO::PackedImageDesc desc(scratch.data(), static_cast<long>(n), 1, 3);
    processor.apply(desc);
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) base[i * channels + c] = scratch[i * 3 + c];
    }
  }
}

// A PNG cannot hold NaN or out-of-range values; NaN becomes 0 so that a bad pixel shows as
// black rather than as whatever the float-to-int conversion happens to produce.
float clamp_unit(float v) {
  if (std::isnan(v)) return 0.0f;
  return std::clamp(v, 0.0f, 1.0f);
}

bool has_view(const OCIO::Config& config, const char* display, const char* view) {
  for (int i = 0; i < config.getNumViews(display); ++i) {
    if (std::string(config.getView(display, i)) == view) return true;
  }
  return false;
}

bool has_display(const OCIO::Config& config, const char* display) {
  for (int i = 0; i < config.getNumDisplays(); ++i) {
    if (std::string(config.getDisplay(i)) == display) return true;
  }
  return false;
}

}  // namespace

struct ColourPipeline::Impl {
  OCIO::ConstConfigRcPtr config;
  std::string source;
  std::string working_name;
  OCIO::ConstCPUProcessorRcPtr rec709_to_working;
  OCIO::ConstCPUProcessorRcPtr srgb_texture_to_working;
  OCIO::ConstCPUProcessorRcPtr working_to_display;
  std::string display, view;
  // Other views, built on first use; the map's nodes stay put, so a processor handed out
  // stays valid while others are added.
  std::mutex views_mutex;
  std::map<std::string, OCIO::ConstCPUProcessorRcPtr> other_views;

  OCIO::ConstCPUProcessorRcPtr display_processor(const std::string& view_name) {
    OCIO::DisplayViewTransformRcPtr display_view = OCIO::DisplayViewTransform::Create();
    display_view->setSrc(working_name.c_str());
    display_view->setDisplay(display.c_str());
    display_view->setView(view_name.c_str());
    return cpu_processor(config->getProcessor(display_view));
  }
};

ColourPipeline::ColourPipeline(WorkingSpace working_space)
    : working_space_(working_space), impl_(std::make_unique<Impl>()) {
  const char* env = std::getenv("OCIO");
  const bool from_env = env != nullptr && env[0] != '\0';
  impl_->source = from_env ? std::string("$OCIO=") + env : std::string("built-in");
  const std::string where = "OCIO config " + impl_->source;

  try {
    if (from_env) {
      impl_->config = OCIO::Config::CreateFromFile(env);
    } else {
      std::istringstream stream(kBuiltinOcioConfig);
      impl_->config = OCIO::Config::CreateFromStream(stream);
    }
    impl_->config->validate();
  } catch (const OCIO::Exception& e) {
    throw std::runtime_error(one_line(where + ": cannot load: " + e.what()));
  }
  const OCIO::Config& config = *impl_->config;

  // Looked up by name (or alias), not by role: the roles of an arbitrary config say nothing
  // about which space is Rec.709 and which is AP1.
  auto require_space = [&](const char* name) {
    OCIO::ConstColorSpaceRcPtr space = config.getColorSpace(name);
    if (!space) {
      throw std::runtime_error(where + ": has no colour space '" + name + "', which Prism needs");
    }
    return std::string(space->getName());
  };
  const std::string rec709 = require_space(kLinearRec709Name);
  const std::string srgb_texture = require_space(kSrgbTextureName);
  impl_->working_name = working_space == WorkingSpace::acescg ? require_space(kAcescgName) : rec709;

  // A user config need not have our display and view; fall back to its defaults as OCIO
  // applications do, so that e.g. the ACES studio config previews through its ACES view.
  std::string display = has_display(config, kDisplayName) ? kDisplayName : "";
  if (display.empty()) display = config.getDefaultDisplay();
  if (display.empty()) throw std::runtime_error(where + ": defines no display");
  std::string view = has_view(config, display.c_str(), kViewName) ? kViewName : "";
  if (view.empty()) view = config.getDefaultView(display.c_str());
  if (view.empty()) throw std::runtime_error(where + ": display '" + display + "' has no view");

  try {
    impl_->rec709_to_working =
        cpu_processor(config.getProcessor(rec709.c_str(), impl_->working_name.c_str()));
    impl_->srgb_texture_to_working =
        cpu_processor(config.getProcessor(srgb_texture.c_str(), impl_->working_name.c_str()));
    impl_->display = display;
    impl_->view = view;
    impl_->working_to_display = impl_->display_processor(view);
  } catch (const OCIO::Exception& e) {
    throw std::runtime_error(one_line(where + ": cannot build colour transforms: " + e.what()));
  }
}

ColourPipeline::~ColourPipeline() = default;

const std::string& ColourPipeline::working_space_name() const {
  return impl_->working_name;
}

const std::string& ColourPipeline::config_source() const {
  return impl_->source;
}

C3f ColourPipeline::from_linear_rec709(const C3f& c) const {
  float rgb[3] = {c.x, c.y, c.z};
  impl_->rec709_to_working->applyRGB(rgb);
  return C3f(rgb[0], rgb[1], rgb[2]);
}

void ColourPipeline::srgb_texture_to_working(float* texels, std::size_t pixel_count,
                                             int channels) const {
  if (channels != 3 && channels != 4) {
    throw std::invalid_argument("srgb_texture_to_working: channels must be 3 or 4, not " +
                                std::to_string(channels));
  }
  apply_rgb(*impl_->srgb_texture_to_working, texels, pixel_count, channels);
}

std::optional<ColourPipeline::CodeTable> ColourPipeline::srgb_texture_code_table() const {
  // Each code on every channel at once, then the same codes with the channels shifted
  // against each other: a transform whose outputs depend on one input channel each gives the
  // same values both ways, a matrix (or a 3D LUT) does not. The probes are as many pixels as
  // an image row, so they take the processor's path for whole rows.
  constexpr int kCodes = 256;
  constexpr int kShifts[] = {0, 1, 37, 85, 128, 211};
  std::vector<float> probe(std::size(kShifts) * kCodes * 3);
  for (std::size_t s = 0; s < std::size(kShifts); ++s)
    for (int v = 0; v < kCodes; ++v)
      for (int c = 0; c < 3; ++c)
        probe[(s * kCodes + v) * 3 + c] =
            TextureImage::code_value(static_cast<uint8_t>((v + c * kShifts[s]) % kCodes));
  apply_rgb(*impl_->srgb_texture_to_working, probe.data(), probe.size() / 3, 3);
  CodeTable table;
  for (int v = 0; v < kCodes; ++v)
    for (int c = 0; c < 3; ++c) table[c][v] = probe[v * 3 + c];
  for (std::size_t s = 1; s < std::size(kShifts); ++s)
    for (int v = 0; v < kCodes; ++v)
      for (int c = 0; c < 3; ++c) {
        const float expected = table[c][(v + c * kShifts[s]) % kCodes];
        const float got = probe[(s * kCodes + v) * 3 + c];
        if (std::memcmp(&expected, &got, sizeof got) != 0) return std::nullopt;
      }
  return table;
}

Image ColourPipeline::working_to_display(const Image& image) const {
  return working_to_display(image, DisplayOptions{});
}

Image ColourPipeline::working_to_display(const Image& image, const DisplayOptions& options) const {
  OCIO::ConstCPUProcessorRcPtr processor = impl_->working_to_display;
  if (!options.view.empty() && options.view != impl_->view) {
    std::lock_guard lock(impl_->views_mutex);
    OCIO::ConstCPUProcessorRcPtr& cached = impl_->other_views[options.view];
    if (!cached) {
      if (!has_view(*impl_->config, impl_->display.c_str(), options.view.c_str())) {
        impl_->other_views.erase(options.view);
        std::string names;
        for (const DisplayView& v : views())
          if (v.display == impl_->display) names += (names.empty() ? "" : ", ") + v.view;
        throw std::runtime_error("view '" + options.view + "': display '" + impl_->display +
                                 "' of OCIO config " + impl_->source + " has " + names);
      }
      try {
        cached = impl_->display_processor(options.view);
      } catch (const OCIO::Exception& e) {
        throw std::runtime_error(
            one_line("view '" + options.view + "': cannot build it: " + e.what()));
      }
    }
    processor = cached;
  }
  Image out = image;
  if (options.exposure != 0.0) {
    const float scale = static_cast<float>(std::exp2(options.exposure));
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
      for (int c = 0; c < 3; ++c) out.rgba[i + c] *= scale;
  }
  apply_rgb(*processor, out.rgba.data(), out.rgba.size() / 4, 4);
  for (float& v : out.rgba) v = clamp_unit(v);
  return out;
}

std::vector<DisplayView> ColourPipeline::views() const {
  std::vector<DisplayView> out;
  const OCIO::Config& config = *impl_->config;
  out.push_back({impl_->display, impl_->view, true});
  for (int d = 0; d < config.getNumDisplays(); ++d) {
    const std::string display = config.getDisplay(d);
    for (int v = 0; v < config.getNumViews(display.c_str()); ++v) {
      const std::string view = config.getView(display.c_str(), v);
      if (display != impl_->display || view != impl_->view) out.push_back({display, view, false});
    }
  }
  return out;
}

const std::string& ColourPipeline::display() const {
  return impl_->display;
}

std::array<float, 8> ColourPipeline::chromaticities() const {
  switch (working_space_) {
    case WorkingSpace::acescg:
      return {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    case WorkingSpace::linear_rec709:
      break;
  }
  return {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
}

}  // namespace prism
