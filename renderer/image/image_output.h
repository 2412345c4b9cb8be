// Writing rendered images: the EXR master (exr_file.h) and the PNG preview (png_file.h).
//
// Files are written to a temporary name beside the target and renamed into place, so a
// failed or interrupted write never leaves a half-written file or clobbers an old one.
#pragma once

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
void write_png_preview(const std::string& path, const Image& image, const ColourPipeline& colour);

}  // namespace prism
