// The files a render writes: the image (the scene-linear EXR master, or by its extension
// TIFF or HDR, scene-linear, or PNG or JPEG, display-referred), an optional display-referred
// PNG preview and an optional sample-count EXR. Checked before the scene is loaded, so a typo in
// a path costs nothing and overwrites nothing; written through temporaries renamed into
// place (renderer/image/image_output.h), so nothing is ever half-written.
#pragma once

#include <string>

#include "renderer/image/colour.h"
#include "renderer/image/image_output.h"
#include "session/job.h"

namespace prism {

struct OutputFiles {
  std::string image;  // required
  // A batch's images are EXR: their metadata tells it whether they are up to date. A render
  // may write any ImageFormat, by the extension.
  bool exr_only = true;
  DisplayOptions display;     // the view and exposure of the PNG and JPEG outputs
  std::string preview;        // .png, or empty
  std::string sample_counts;  // .exr of each pixel's sample count (R = G = B), or empty
  ExrPixelType pixel_type = ExrPixelType::float32;
  ExrCompression compression = kDefaultExrCompression;
  // A batch's paths, spread over folders by their placeholders, may name folders that do not
  // exist yet: they are then checked to be creatable, and made by make_output_directories
  // when the job starts. A render's are not: a typo in `-o` is an error, not a new folder.
  bool create_directories = false;
};

// Throws RequestError naming the field ("output", "preview", "sample-count-image") when a
// path has the wrong extension, names a directory, sits in a directory that does not exist
// (with create_directories: that cannot be made, under a file or in a folder not writable)
// or where no file can be created (tried with a temporary file, removed at once), is the scene
// file itself or is another output of the same render.
void check_output_files(const OutputFiles& files, const std::string& scene_path);

// Makes the missing folders of every output path (create_directories), or throws
// RequestError naming the field and the folder.
void make_output_directories(const OutputFiles& files);

// Each pixel's sample count as grey (R = G = B), alpha 1.
Image sample_count_image(const RenderOutput& output);

// `threads` compress the EXRs (ExrWriteOptions::threads): the session's own when nothing
// else runs, 1 when the write overlaps another render.
void write_output_files(const OutputFiles& files, const RenderOutput& output,
                        const ColourPipeline& colour, int threads);

}  // namespace prism
