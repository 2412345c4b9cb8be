// Writing rendered images: the EXR master (exr_file.h) and the PNG preview (png_file.h).
//
// Files are written to a temporary name beside the target and renamed into place, so a
// failed or interrupted write never leaves a half-written file or clobbers an old one.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "renderer/image/colour.h"
#include "renderer/image/exr_file.h"
#include "renderer/image/image.h"
#include "renderer/scene_description.h"

namespace prism {

struct RenderMetadata {
  std::string integrator;
  int spp = 1;
  double render_seconds = 0.0;
  M44d world_to_camera;  // Imath row-vector convention, as OpenEXR's worldToCamera
  M44d world_to_ndc;     // as OpenEXR's worldToNDC
  std::string scene_path;
  // The part of the image rendered (RenderSettings::region), stored as the EXR's data window;
  // empty: the whole image.
  std::optional<TileRect> region;
  // Anything else worth keeping (sphere mode, ray counts, ...), as prism:<key> attributes.
  std::vector<std::pair<std::string, std::string>> extra;
};

// Throws std::runtime_error("<path>: <reason>") on failure; the target is then untouched.
void write_exr(const std::string& path, const Image& image, const ColourPipeline& colour,
               const RenderMetadata& metadata, const ExrWriteOptions& options);
inline void write_exr(const std::string& path, const Image& image, const ColourPipeline& colour,
                      const RenderMetadata& metadata,
                      ExrPixelType pixel_type = ExrPixelType::half) {
  write_exr(path, image, colour, metadata, ExrWriteOptions{pixel_type});
}
void write_png_preview(const std::string& path, const Image& image, const ColourPipeline& colour,
                       const DisplayOptions& display = {});
// An image already display-referred (RGB in [0, 1]) as an 8-bit PNG.
void write_display_png(const std::string& path, const Image& display);

// The formats an output may have, chosen by its extension. EXR, TIFF and HDR hold the
// scene-linear image; PNG and JPEG the display-referred one (through the OCIO view).
enum class ImageFormat { exr, tiff, hdr, png, jpeg };
// By `path`'s extension (.exr, .tif, .tiff, .hdr, .png, .jpg, .jpeg, any case); false for
// any other.
bool image_format_for_path(const std::string& path, ImageFormat* format);
inline constexpr const char* kImageExtensions = ".exr, .tif, .tiff, .hdr, .png, .jpg or .jpeg";
inline bool display_referred(ImageFormat format) {
  return format == ImageFormat::png || format == ImageFormat::jpeg;
}
// Writes any of them but EXR (write_exr), atomically: TIFF and HDR through OpenImageIO
// (loaded on first use), PNG and JPEG through the colour pipeline's view. Throws
// std::runtime_error("<path>: <reason>").
void write_image(const std::string& path, ImageFormat format, const Image& image,
                 const ColourPipeline& colour, const DisplayOptions& display);

}  // namespace prism
