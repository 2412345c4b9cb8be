#include "session/output_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "renderer/temporary_files.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

bool has_extension(const std::string& path, const char* extension) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == extension;
}

// The same file by another spelling (./a.exr, a symlink, a hard link) counts as the same.
bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  return fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
}

// A file that cannot be created there is found now, not after the render: one is made and
// removed at once, under the name the write's own temporary would have.
void check_writable(const std::string& path, const char* field) {
  const fs::path parent = fs::path(path).parent_path();
  const fs::path probe = (parent.empty() ? fs::path(".") : parent) / temporary_name(path);
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) throw RequestError(field, path + ": cannot be written: " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

// Each file a render may write, with the extension it must have (none: any image format's)
// and the field that names it in errors.
struct NamedOutput {
  const std::string* path;
  const char* extension;
  const char* field;
};
std::array<NamedOutput, 3> named_outputs(const OutputFiles& files) {
  return {{{&files.image, files.exr_only ? ".exr" : nullptr, "output"},
           {&files.preview, ".png", "preview"},
           {&files.sample_counts, ".exr", "sample-count-image"}}};
}

// The folders a path needs can be made: the nearest of its ancestors that exists is a
// writable directory.
void check_creatable(const fs::path& parent, const std::string& path, const char* field) {
  std::error_code error;
  fs::path existing = parent;
  while (!existing.empty() && !fs::exists(existing, error)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, error))
    throw RequestError(field, path + ": " + existing.string() + " is not a directory");
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw RequestError(field, path + ": directory " + parent.string() + " cannot be made in " +
                                  existing.string() + ": " + std::strerror(errno));
}

void check_path(const std::string& path, const char* extension, bool create_directories,
                const char* field) {
  if (extension && !has_extension(path, extension))
    throw RequestError(field, path + ": the file name must end in " + extension);
  ImageFormat format{};
  if (!extension && !image_format_for_path(path, &format))
    throw RequestError(field, path + ": the file name must end in " + kImageExtensions);
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent)) {
    if (!create_directories)
      throw RequestError(field, path + ": directory " + parent.string() + " does not exist");
    check_creatable(parent, path, field);
    return;  // no file to try until its folder is made
  }
  if (fs::is_directory(path)) throw RequestError(field, path + ": is a directory");
  check_writable(path, field);
}

}  // namespace

void check_output_files(const OutputFiles& files, const std::string& scene_path) {
  const std::array<NamedOutput, 3> outputs = named_outputs(files);
  for (size_t i = 0; i < std::size(outputs); ++i) {
    const NamedOutput& o = outputs[i];
    if (o.path->empty()) continue;
    check_path(*o.path, o.extension, files.create_directories, o.field);
    if (same_file(*o.path, scene_path))
      throw RequestError(o.field, *o.path + ": is the scene file itself");
    for (size_t j = 0; j < i; ++j)
      if (!outputs[j].path->empty() && same_file(*o.path, *outputs[j].path))
        throw RequestError(o.field, *o.path + ": is also the " + outputs[j].field + " file");
  }
}

void make_output_directories(const OutputFiles& files) {
  if (!files.create_directories) return;
  for (const NamedOutput& o : named_outputs(files)) {
    const fs::path parent = fs::path(*o.path).parent_path();
    if (o.path->empty() || parent.empty()) continue;
    std::error_code error;
    fs::create_directories(parent, error);
    if (error)
      throw RequestError(o.field, *o.path + ": directory " + parent.string() +
                                      " cannot be made: " + error.message());
  }
}

Image sample_count_image(const RenderOutput& output) {
  Image image(output.film.width, output.film.height);
  const std::vector<uint32_t>& counts = output.result.samples_per_pixel;
  for (size_t i = 0; i < image.rgba.size() / 4; ++i) {
    const float n =
        counts.empty() ? static_cast<float>(output.film.spp) : static_cast<float>(counts[i]);
    image.rgba[i * 4 + 0] = image.rgba[i * 4 + 1] = image.rgba[i * 4 + 2] = n;
    image.rgba[i * 4 + 3] = 1.0f;
  }
  return image;
}

void write_output_files(const OutputFiles& files, const RenderOutput& output,
                        const ColourPipeline& colour, int threads) {
  // Formats without a data window show a region alone, as pbrt writes a crop window.
  const std::optional<TileRect>& region = output.metadata.region;
  const Image cropped = region ? crop(output.image, *region) : Image();
  const Image& shown = region ? cropped : output.image;
  // The master last: once it exists, so do the others, and a batch that finds it (with its
  // job's fingerprint) after a kill may skip the job.
  if (!files.preview.empty()) write_png_preview(files.preview, shown, colour, files.display);
  if (!files.sample_counts.empty())
    write_exr(files.sample_counts, sample_count_image(output), colour, output.metadata,
              {ExrPixelType::float32, files.compression, threads});
  ImageFormat format = ImageFormat::exr;
  if (!image_format_for_path(files.image, &format) || format == ImageFormat::exr)
    write_exr(files.image, output.image, colour, output.metadata,
              {files.pixel_type, files.compression, threads});
  else
    write_image(files.image, format, shown, colour, files.display);
}

}  // namespace prism
